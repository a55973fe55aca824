//! The two pest parsers of the grammar (`grammar/sdf.pest`), which accept the same texts
//! within pest's call budget (the tree parser needs no more calls): the tree parser, whose
//! pairs the tree is built from, and the report parser, which keeps a pair for every
//! punctuation mark so that a syntax error can name what was expected.

/// Parses every item first: punctuation, `term` and `arg` are silent (`grammar/tree.pest`).
pub(crate) mod tree {
    #[derive(pest_derive::Parser)]
    #[grammar = "../../../grammar/sdf.pest"]
    #[grammar = "../../../grammar/tree.pest"]
    pub(crate) struct TreeParser;
}

/// Parses an item again after a syntax error, for the message (`grammar/report.pest`).
pub(crate) mod report {
    #[derive(pest_derive::Parser)]
    #[grammar = "../../../grammar/sdf.pest"]
    #[grammar = "../../../grammar/report.pest"]
    pub(crate) struct ReportParser;
}
