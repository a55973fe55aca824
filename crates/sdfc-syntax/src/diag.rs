//! Diagnostics: what went wrong, where, and a hint; rendered with codespan-reporting.

use crate::elide::{has_long_lines, Elided};
use crate::span::Span;
use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label};
use codespan_reporting::files::{Error as FilesError, Files, SimpleFile};
use codespan_reporting::term::{self, termcolor::Buffer};
use std::ops::Range;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    Error,
    Warning,
}

/// One problem in a scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub message: String,
    /// Where it is; the caret goes under this span.
    pub span: Span,
    /// A short label shown under the caret.
    pub label: String,
    /// Further spans worth showing (for example where a name was first defined).
    pub secondary: Vec<(Span, String)>,
    /// How to fix it, where we know.
    pub hint: Option<String>,
    /// The 1-based line and column (in characters) of the span's start, once placed in its
    /// source ([`Diagnostic::placed`]): every diagnostic `sdfc_wgsl`'s entry points return is
    /// placed, so that its `Display` can say where it is without the source.
    pub place: Option<(u32, u32)>,
}

impl Diagnostic {
    pub fn error(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            message: message.into(),
            span,
            label: String::new(),
            secondary: Vec::new(),
            hint: None,
            place: None,
        }
    }

    pub fn warning(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(span, message)
        }
    }

    pub fn with_label(mut self, label: impl Into<String>) -> Diagnostic {
        self.label = label.into();
        self
    }

    pub fn with_hint(mut self, hint: impl Into<String>) -> Diagnostic {
        self.hint = Some(hint.into());
        self
    }

    pub fn with_secondary(mut self, span: Span, label: impl Into<String>) -> Diagnostic {
        self.secondary.push((span, label.into()));
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// 1-based line and column (in characters) of the start of the span.
    pub fn line_col(&self, source: &str) -> (usize, usize) {
        line_col(source, self.span.start as usize)
    }

    /// The diagnostic with its [`place`](Diagnostic::place) in `source` filled in.
    pub fn placed(mut self, source: &str) -> Diagnostic {
        let (line, col) = self.line_col(source);
        // Sources are far below 4 GiB (the compiler's size limit); saturate all the same.
        let narrow = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        self.place = Some((narrow(line), narrow(col)));
        self
    }
}

/// One line: where (once placed), what, and the hint: `3:14: error: unknown name `sphre`;
/// hint: did you mean `sphere`?`. The source line with carets needs the source: [`render`].
impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some((line, col)) = self.place {
            write!(f, "{line}:{col}: ")?;
        }
        let severity = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(f, "{severity}: {}", self.message)?;
        if let Some(hint) = &self.hint {
            write!(f, "; hint: {hint}")?;
        }
        Ok(())
    }
}

/// 1-based line and column (in characters) of a byte offset.
pub fn line_col(source: &str, offset: usize) -> (usize, usize) {
    let offset = floor_char_boundary(source, offset.min(source.len()));
    let before = &source[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = source[line_start..offset].chars().count() + 1;
    (line, col)
}

/// The nearest character boundary at or before byte `i` of `s`.
pub(crate) fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while i > 0 && !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Renders diagnostics as text (`file:line:column`, the source line with carets, the hint),
/// without colour. Spans are clamped to the source so a bad span can never panic.
pub fn render(file_name: &str, source: &str, diagnostics: &[Diagnostic]) -> String {
    render_with(file_name, source, diagnostics, false)
}

/// As [`render`], with ANSI colours when `color` is true.
pub fn render_with(
    file_name: &str,
    source: &str,
    diagnostics: &[Diagnostic],
    color: bool,
) -> String {
    let mut buffer = if color {
        Buffer::ansi()
    } else {
        Buffer::no_color()
    };
    let config = term::Config::default();
    // Built once: most sources have no long line, and then every snippet is drawn from it.
    let whole = View {
        source,
        elided: None,
        file: SimpleFile::new(file_name, source),
    };
    let long_lines = has_long_lines(source);
    for d in diagnostics {
        let clamp = |s: Span| {
            let start = floor_char_boundary(source, (s.start as usize).min(source.len()));
            let end = floor_char_boundary(source, (s.end as usize).clamp(start, source.len()));
            start..end
        };
        let (line, col) = d.line_col(source);
        let cs = match d.severity {
            Severity::Error => CsDiagnostic::error(),
            Severity::Warning => CsDiagnostic::warning(),
        };
        let spans: Vec<Range<usize>> = std::iter::once(d.span)
            .chain(d.secondary.iter().map(|(s, _)| *s))
            .map(clamp)
            .collect();
        // Long lines are shown cut down to windows around the labels (`elide`).
        let points: Vec<usize> = spans.iter().flat_map(|r| [r.start, r.end]).collect();
        let elided = long_lines.then(|| Elided::new(source, &points));
        let cut = elided.as_ref().map(|e| View {
            source,
            elided: Some(e),
            file: SimpleFile::new(file_name, e.text.as_str()),
        });
        let view = cut.as_ref().unwrap_or(&whole);
        let place = |r: &Range<usize>| match &elided {
            Some(e) => e.map(r.start)..e.map(r.end),
            None => r.clone(),
        };
        let mut labels = vec![Label::primary((), place(&spans[0])).with_message(d.label.clone())];
        for (span, (_, msg)) in spans[1..].iter().zip(&d.secondary) {
            labels.push(Label::secondary((), place(span)).with_message(msg.clone()));
        }
        let mut notes = Vec::new();
        if let Some(h) = &d.hint {
            notes.push(format!("hint: {h}"));
        }
        let cs = cs
            .with_message(format!("{} ({file_name}:{line}:{col})", d.message))
            .with_labels(labels)
            .with_notes(notes);
        // Writing into an in-memory buffer cannot fail for I/O reasons; a formatting failure
        // would only lose this diagnostic's text, so fall back to a plain line.
        if term::emit_to_write_style(&mut buffer, &config, view, &cs).is_err() {
            buffer_plain(&mut buffer, file_name, line, col, &d.message);
        }
    }
    String::from_utf8_lossy(buffer.as_slice()).into_owned()
}

/// The file a diagnostic's snippet is drawn from: the source, or its long lines cut
/// ([`Elided`]), with columns counted in the source either way.
struct View<'s> {
    source: &'s str,
    elided: Option<&'s Elided>,
    /// The text shown, which gives the lines.
    file: SimpleFile<&'s str, &'s str>,
}

impl<'s> Files<'s> for View<'s> {
    type FileId = ();
    type Name = &'s str;
    type Source = &'s str;

    fn name(&'s self, (): ()) -> Result<&'s str, FilesError> {
        Ok(self.file.name())
    }

    fn source(&'s self, (): ()) -> Result<&'s str, FilesError> {
        Ok(self.file.source())
    }

    fn line_index(&'s self, (): (), byte_index: usize) -> Result<usize, FilesError> {
        self.file.line_index((), byte_index)
    }

    fn line_range(&'s self, (): (), line_index: usize) -> Result<Range<usize>, FilesError> {
        self.file.line_range((), line_index)
    }

    fn column_number(
        &'s self,
        (): (),
        line_index: usize,
        byte_index: usize,
    ) -> Result<usize, FilesError> {
        match self.elided {
            Some(e) => Ok(line_col(self.source, e.unmap(byte_index)).1),
            None => self.file.column_number((), line_index, byte_index),
        }
    }
}

fn buffer_plain(buffer: &mut Buffer, file: &str, line: usize, col: usize, msg: &str) {
    use std::io::Write;
    let _ = writeln!(buffer, "error: {msg} ({file}:{line}:{col})");
}

/// The known name closest to `name` (edit distance counting a swap of neighbouring letters
/// as one edit), if it is close enough to be a plausible misspelling.
pub fn nearest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let mut best: Option<(usize, &str)> = None;
    for k in known {
        if k == name {
            continue;
        }
        let d = edit_distance(name, k);
        let limit = (name.chars().count().max(k.chars().count()) / 3).max(1);
        if d <= limit && best.is_none_or(|(bd, bk)| d < bd || (d == bd && k < bk)) {
            best = Some((d, k));
        }
    }
    best.map(|(_, k)| k)
}

/// Optimal string alignment distance: insertions, deletions, substitutions and swaps of
/// adjacent characters each cost one.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swaps_count_as_one_edit() {
        assert_eq!(nearest("rde", ["red", "blue"]), Some("red"));
        assert_eq!(nearest("sphree", ["sphere", "box"]), Some("sphere"));
        assert_eq!(nearest("xyz", ["sphere"]), None);
    }
}
