//! Long source lines cut down to windows around a diagnostic's labels, for its snippet.
//!
//! A generated scene may sit on one line of a megabyte; codespan-reporting would print that
//! line whole under every diagnostic, with a caret line as long. Here each line longer than
//! [`MAX_LINE`] bytes keeps [`CONTEXT`] bytes on each side of every label's ends, and each
//! stretch cut out is shown as [`CUT`]. Line numbers do not change; offsets are mapped both
//! ways so that carets land under the same text and the columns printed stay the source's.

use crate::diag::floor_char_boundary;
use std::ops::Range;

/// Lines longer than this, in bytes, are cut.
pub(crate) const MAX_LINE: usize = 160;
/// Bytes kept on each side of a label's start and end.
pub(crate) const CONTEXT: usize = 40;
/// What stands for a stretch cut out.
pub(crate) const CUT: &str = "...";

/// Whether any line of `source` is longer than [`MAX_LINE`] bytes (line breaks not counted).
pub(crate) fn has_long_lines(source: &str) -> bool {
    source
        .split('\n')
        .any(|l| l.trim_end_matches('\r').len() > MAX_LINE)
}

/// A source with its long lines cut, and where each kept stretch came from.
pub(crate) struct Elided {
    pub text: String,
    /// Kept stretches of the source, in order, and where each starts in `text`.
    runs: Vec<(Range<usize>, usize)>,
}

impl Elided {
    /// `source` with every line longer than [`MAX_LINE`] cut down to windows around the
    /// offsets in `points` on it (the first [`CONTEXT`] bytes twice over where it has none);
    /// for sources with such a line ([`has_long_lines`]).
    pub(crate) fn new(source: &str, points: &[usize]) -> Elided {
        let mut lines = Vec::new();
        let mut start = 0;
        for line in source.split_inclusive('\n') {
            let end = start + line.trim_end_matches(['\n', '\r']).len();
            lines.push(start..end);
            start += line.len();
        }
        let mut kept = Vec::new();
        let mut from = 0;
        for line in lines.into_iter().filter(|l| l.len() > MAX_LINE) {
            // Everything before this line (earlier lines, line breaks) is kept.
            kept.push(from..line.start);
            kept.extend(windows(source, &line, points));
            from = line.end;
        }
        kept.push(from..source.len());
        let mut text = String::with_capacity(source.len().min(1 << 16));
        let mut runs: Vec<(Range<usize>, usize)> = Vec::new();
        let mut shown_to = 0;
        for run in kept.into_iter().filter(|r| !r.is_empty()) {
            if run.start > shown_to {
                text.push_str(CUT);
                runs.push((run.clone(), text.len()));
            } else if let Some((last, _)) = runs.last_mut() {
                // Adjacent stretches (a window that reaches the end of its line) join.
                last.end = run.end;
            } else {
                runs.push((run.clone(), text.len()));
            }
            shown_to = run.end;
            text.push_str(&source[run]);
        }
        if shown_to < source.len() {
            text.push_str(CUT);
        }
        Elided { text, runs }
    }

    /// Where a source offset is in `text`: in a kept stretch, the same byte; in one cut
    /// out, the start of its [`CUT`].
    pub(crate) fn map(&self, offset: usize) -> usize {
        let i = self.runs.partition_point(|(r, _)| r.start <= offset);
        match i.checked_sub(1).map(|i| &self.runs[i]) {
            None => 0,
            Some((r, at)) => at + offset.min(r.end) - r.start,
        }
    }

    /// Where an offset of `text` came from in the source: in a [`CUT`], the start of the
    /// stretch it stands for.
    pub(crate) fn unmap(&self, offset: usize) -> usize {
        let i = self.runs.partition_point(|(_, at)| *at <= offset);
        match i.checked_sub(1).map(|i| &self.runs[i]) {
            None => 0,
            Some((r, at)) => r.start + (offset - at).min(r.len()),
        }
    }
}

/// The stretches of `line` to keep: [`CONTEXT`] bytes around each point on it, merged where
/// they overlap or lie less than half that apart, on character boundaries.
fn windows(source: &str, line: &Range<usize>, points: &[usize]) -> Vec<Range<usize>> {
    let mut spans: Vec<Range<usize>> = points
        .iter()
        .filter(|p| line.contains(p) || **p == line.end)
        .map(|&p| p.saturating_sub(CONTEXT).max(line.start)..(p + CONTEXT).min(line.end))
        .collect();
    if spans.is_empty() {
        spans.push(line.start..line.start + 2 * CONTEXT);
    }
    spans.sort_by_key(|r| r.start);
    let mut merged: Vec<Range<usize>> = Vec::new();
    for s in spans {
        let s = floor_char_boundary(source, s.start)..ceil_char_boundary(source, s.end);
        match merged.last_mut() {
            // A gap of less than half a window is not worth cutting.
            Some(last) if s.start <= last.end + CONTEXT / 2 => last.end = last.end.max(s.end),
            _ => merged.push(s),
        }
    }
    // Nor is one at either end of the line.
    if let Some(first) = merged
        .first_mut()
        .filter(|r| r.start <= line.start + CONTEXT / 2)
    {
        first.start = line.start;
    }
    if let Some(last) = merged
        .last_mut()
        .filter(|r| r.end + CONTEXT / 2 >= line.end)
    {
        last.end = line.end;
    }
    merged
}

fn ceil_char_boundary(s: &str, mut i: usize) -> usize {
    while i < s.len() && !s.is_char_boundary(i) {
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_lines_past_the_limit_are_long() {
        let line = "z".repeat(MAX_LINE);
        assert!(!has_long_lines(&format!(
            "let a = 1;\n{line}\r\nscene = a;"
        )));
        assert!(has_long_lines(&format!(
            "let a = 1;\n{line}z\r\nscene = a;"
        )));
    }

    #[test]
    fn a_long_line_keeps_windows_around_the_points_and_maps_both_ways() {
        let line = "x".repeat(1000);
        let source = format!("let a = 1;\n{line}\nscene = a;\n");
        let point = 11 + 500;
        let e = Elided::new(&source, &[point, point + 3]);
        let expected = format!(
            "let a = 1;\n{CUT}{}{CUT}\nscene = a;\n",
            "x".repeat(2 * CONTEXT + 3)
        );
        assert_eq!(e.text, expected);
        for p in [point, point + 3] {
            assert_eq!(e.unmap(e.map(p)), p);
        }
        assert_eq!(e.map(point), 11 + CUT.len() + CONTEXT);
        // Offsets cut out map to their mark, and back to the start of what it stands for.
        assert_eq!(e.map(11), 11);
        assert_eq!(e.unmap(e.map(11)), 11);
        assert_eq!(e.map(source.len()), e.text.len());
        assert_eq!(&e.text[e.map(11 + 1000)..], "\nscene = a;\n");
    }

    #[test]
    fn windows_stop_on_character_boundaries() {
        let line = "é".repeat(300);
        let e = Elided::new(&line, &[301]);
        assert!(e.text.starts_with(CUT) && e.text.ends_with(CUT));
        assert!(e.text.len() < 2 * CONTEXT + 2 * CUT.len() + 4);
    }

    #[test]
    fn a_long_line_without_points_keeps_its_start() {
        let source = format!("{}\nscene = a;", "y".repeat(500));
        let e = Elided::new(&source, &[510]);
        assert_eq!(
            e.text,
            format!("{}{CUT}\nscene = a;", "y".repeat(2 * CONTEXT))
        );
    }
}
