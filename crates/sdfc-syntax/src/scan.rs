//! Byte-level scans of the source that need no grammar: the pre-checks run before pest (size,
//! unterminated comments, bracket depth), resynchronisation after a syntax error, and the token
//! and bracket look-ups that error messages use. Comments are skipped everywhere.

use crate::diag::Diagnostic;
use crate::span::Span;
use crate::{MAX_NESTING, MAX_SOURCE_BYTES};

/// The item keywords, in the order the error messages list them.
pub(crate) const ITEM_KEYWORDS: [&str; 8] = [
    "let", "fn", "param", "material", "light", "camera", "render", "scene",
];

/// All keywords of section 1.
pub(crate) const KEYWORDS: [&str; 10] = [
    "let", "fn", "param", "material", "light", "camera", "render", "scene", "true", "false",
];

pub(crate) fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

pub(crate) fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0C)
}

/// What [`Bytes`] yields: a significant (non-blank, non-comment) byte and its offset.
/// An unterminated block comment ends the scan, reported through `unterminated`.
struct Bytes<'s> {
    src: &'s [u8],
    pos: usize,
    unterminated: Option<usize>,
}

impl<'s> Bytes<'s> {
    fn new(source: &'s str, from: usize) -> Bytes<'s> {
        Bytes {
            src: source.as_bytes(),
            pos: from.min(source.len()),
            unterminated: None,
        }
    }
}

impl Iterator for Bytes<'_> {
    type Item = (usize, u8);

    fn next(&mut self) -> Option<(usize, u8)> {
        let src = self.src;
        while self.pos < src.len() {
            let i = self.pos;
            let b = src[i];
            if is_space(b) {
                self.pos += 1;
            } else if b == b'/' && src.get(i + 1) == Some(&b'/') {
                self.pos = src[i..]
                    .iter()
                    .position(|&c| c == b'\n')
                    .map_or(src.len(), |n| i + n);
            } else if b == b'/' && src.get(i + 1) == Some(&b'*') {
                match find(&src[i + 2..], b"*/") {
                    Some(n) => self.pos = i + 2 + n + 2,
                    None => {
                        self.unterminated = Some(i);
                        self.pos = src.len();
                    }
                }
            } else {
                self.pos += 1;
                return Some((i, b));
            }
        }
        None
    }
}

impl Bytes<'_> {
    /// Skips the run of [`PLAIN`] bytes at the current position and returns the last of them.
    /// The run holds neither blanks nor comments: it is what [`Iterator::next`] would have
    /// yielded one by one. The scans use it to go over words and numbers quickly.
    fn skip_plain(&mut self) -> Option<u8> {
        let start = self.pos;
        while self
            .src
            .get(self.pos)
            .is_some_and(|&c| PLAIN[usize::from(c)])
        {
            self.pos += 1;
        }
        (self.pos > start).then(|| self.src[self.pos - 1])
    }
}

/// The bytes that neither scan acts on, one by one: not blank, not `/` (which may start a
/// comment), no bracket, separator or `|`.
static PLAIN: [bool; 256] = {
    let mut table = [true; 256];
    let special = b" \t\r\n\x0C/()[]{},;|";
    let mut i = 0;
    while i < special.len() {
        table[special[i] as usize] = false;
        i += 1;
    }
    table
};

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// The checks that must pass before pest sees the text: the size limit, block comments that
/// never end, and bracket nesting (so that deep input cannot exhaust the stack).
pub(crate) fn precheck(source: &str) -> Result<(), Diagnostic> {
    if source.len() > MAX_SOURCE_BYTES {
        return Err(Diagnostic::error(
            Span::new(source.len(), source.len()),
            "file is larger than the 1 MiB limit",
        )
        .with_label("the file ends here")
        .with_hint(format!(
            "the file has {} bytes; the limit is {MAX_SOURCE_BYTES} bytes",
            source.len()
        )));
    }
    // Nesting counts open brackets plus lambdas whose body has not ended: those are the only
    // constructs the grammar (and every pass over the tree) recurses on. A lambda head is a `|`
    // where an operand is expected; its body ends at the `,`, `;` or closing bracket of the
    // bracket level it is in.
    let too_deep = |i: usize, what: &str| {
        Diagnostic::error(
            Span::new(i, i + 1),
            format!("{what}s are nested too deeply (more than {MAX_NESTING} levels)"),
        )
        .with_label(format!("this {what} is too deep"))
        .with_hint("split the expression into smaller pieces with `let`")
    };
    let mut depth = 0usize;
    let mut lambdas: Vec<usize> = vec![0]; // open lambdas per bracket level
    let mut prev = b';';
    let mut in_head = false;
    let mut bytes = Bytes::new(source, 0);
    loop {
        // Outside a lambda head, a plain byte only becomes `prev`.
        if !in_head {
            if let Some(last) = bytes.skip_plain() {
                prev = last;
            }
        }
        let Some((i, b)) = bytes.next() else {
            break;
        };
        if in_head {
            if is_ident_char(b) || b == b',' {
                prev = b;
                continue;
            }
            in_head = false;
            if b == b'|' {
                prev = b;
                continue;
            }
        }
        // `lambdas` always holds at least the top level.
        let open_here = |lambdas: &mut Vec<usize>| lambdas.last_mut().map_or(0, std::mem::take);
        match b {
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(too_deep(i, "bracket"));
                }
                lambdas.push(0);
            }
            b')' | b']' | b'}' => {
                let mut closed = open_here(&mut lambdas);
                if lambdas.len() > 1 {
                    lambdas.pop();
                    closed += 1;
                }
                depth = depth.saturating_sub(closed);
            }
            b',' | b';' => depth = depth.saturating_sub(open_here(&mut lambdas)),
            b'|' if b"([{,:=|&+-*/%<>!;".contains(&prev) => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(too_deep(i, "lambda"));
                }
                if let Some(n) = lambdas.last_mut() {
                    *n += 1;
                }
                in_head = true;
            }
            _ => {}
        }
        prev = b;
    }
    if let Some(i) = bytes.unterminated {
        return Err(
            Diagnostic::error(Span::new(i, i + 2), "unterminated block comment")
                .with_label("this comment is never closed")
                .with_hint("a block comment ends with `*/` (block comments do not nest)"),
        );
    }
    Ok(())
}

/// Where to start parsing again after a syntax error at `err` in the item that starts at
/// `start`: just after the first `;` outside any `{ }` block, or after the `}` that closes the
/// block at depth 0, at or past the error; or at the start of a later line that begins with an
/// item head (`let NAME`, `scene =`, `camera {`, ...), which recovers from unclosed brackets.
/// Always returns an offset past `start`'s first token, so the caller makes progress.
pub(crate) fn resync(source: &str, start: usize, err: usize) -> usize {
    let mut stack: Vec<u8> = Vec::new();
    let mut seen_token = false;
    let mut bytes = Bytes::new(source, start);
    while let Some((i, b)) = bytes.next() {
        if i >= err && seen_token && at_line_start(source, i) && is_item_head(source, i) {
            return i;
        }
        seen_token = true;
        match b {
            b'(' | b'[' | b'{' => stack.push(b),
            b')' | b']' => {
                let open = if b == b')' { b'(' } else { b'[' };
                if let Some(k) = stack.iter().rposition(|&o| o == open) {
                    stack.truncate(k);
                }
            }
            b'}' => {
                if let Some(k) = stack.iter().rposition(|&o| o == b'{') {
                    stack.truncate(k);
                }
                if i >= err && !stack.contains(&b'{') {
                    return i + 1;
                }
            }
            b';' if i >= err && !stack.contains(&b'{') => return i + 1,
            _ => {}
        }
        // A plain byte right after a significant one is not at a line start, and the match
        // above ignores it: skip such runs (words, numbers, operators) at once.
        bytes.skip_plain();
    }
    source.len()
}

pub(crate) fn at_line_start(source: &str, i: usize) -> bool {
    source.as_bytes()[..i]
        .iter()
        .rev()
        .take_while(|&&b| b != b'\n')
        .all(|&b| b == b' ' || b == b'\t' || b == b'\r')
}

/// Whether an item visibly starts at `i`: an item keyword followed by what that item needs next.
pub(crate) fn is_item_head(source: &str, i: usize) -> bool {
    let bytes = source.as_bytes();
    let word = word_at(source, i);
    let rest = &bytes[i + word.len()..];
    let after_space = rest.iter().position(|&b| !is_space(b));
    let next = after_space.and_then(|n| rest.get(n).copied());
    match word {
        "let" | "fn" | "param" | "material" | "light" => {
            after_space.is_some_and(|n| n > 0) && next.is_some_and(is_ident_start)
        }
        "camera" | "render" => next == Some(b'{'),
        "scene" => {
            next == Some(b'=') && after_space.and_then(|n| rest.get(n + 1)).copied() != Some(b'=')
        }
        _ => false,
    }
}

/// The identifier-shaped word starting at `i` (empty if none).
pub(crate) fn word_at(source: &str, i: usize) -> &str {
    let bytes = source.as_bytes();
    if !bytes.get(i).copied().is_some_and(is_ident_start) {
        return "";
    }
    let n = bytes[i..].iter().take_while(|&&b| is_ident_char(b)).count();
    &source[i..i + n]
}

/// The token at `pos` as an error message shows it, and its span: a word, a number, a one- or
/// two-character operator, or any other single character; `None` at the end of the input.
pub(crate) fn token_at(source: &str, pos: usize) -> Option<(Span, &str)> {
    let bytes = source.as_bytes();
    let &b = bytes.get(pos)?;
    let len = if is_ident_start(b) {
        word_at(source, pos).len()
    } else if b.is_ascii_digit()
        || (b == b'.' && bytes.get(pos + 1).is_some_and(u8::is_ascii_digit))
    {
        1 + bytes[pos + 1..]
            .iter()
            .take_while(|&&c| is_ident_char(c) || c == b'.')
            .count()
    } else if matches!(
        bytes.get(pos..pos + 2),
        Some(b"<=" | b">=" | b"==" | b"!=" | b"||" | b"&&")
    ) {
        2
    } else {
        source
            .get(pos..)
            .and_then(|s| s.chars().next())
            .map_or(1, char::len_utf8)
    };
    let end = (pos + len).min(source.len());
    Some((Span::new(pos, end), source.get(pos..end).unwrap_or("?")))
}

/// The end offset of the last significant token that ends at or before `pos`, scanning from
/// `from` (which must be at a token boundary). `None` if there is none.
pub(crate) fn prev_token_end(source: &str, from: usize, pos: usize) -> Option<usize> {
    Bytes::new(source, from)
        .take_while(|&(i, _)| i < pos)
        .last()
        .map(|(i, _)| i + 1)
}

/// The offset of the first significant byte at or after `from`.
pub(crate) fn first_token(source: &str, from: usize) -> Option<usize> {
    Bytes::new(source, from).next().map(|(i, _)| i)
}

/// The identifier-shaped word that ends at `end`, with its start offset (empty if none).
pub(crate) fn word_before(source: &str, end: usize) -> (usize, &str) {
    let bytes = source.as_bytes();
    let end = end.min(bytes.len());
    let n = bytes[..end]
        .iter()
        .rev()
        .take_while(|&&b| is_ident_char(b))
        .count();
    let start = end - n;
    if n > 0 && bytes.get(start).copied().is_some_and(is_ident_start) {
        (start, &source[start..end])
    } else {
        (end, "")
    }
}

/// The innermost bracket opened between `from` and `pos` that is still open at `pos`.
pub(crate) fn unclosed_bracket(source: &str, from: usize, pos: usize) -> Option<(usize, u8)> {
    let mut stack: Vec<(usize, u8)> = Vec::new();
    for (i, b) in Bytes::new(source, from).take_while(|&(i, _)| i < pos) {
        match b {
            b'(' | b'[' | b'{' => stack.push((i, b)),
            b')' | b']' | b'}' => {
                let open = match b {
                    b')' => b'(',
                    b']' => b'[',
                    _ => b'{',
                };
                if let Some(k) = stack.iter().rposition(|&(_, o)| o == open) {
                    stack.truncate(k);
                }
            }
            _ => {}
        }
    }
    stack.pop()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resync_skips_to_semicolon_outside_blocks() {
        let src = "let a = (1 + ; let b = 2;";
        assert_eq!(resync(src, 0, 13), 14);
        let src = "material m { color: 1; x: 2 } let b = 2;";
        assert_eq!(resync(src, 0, 21), 29);
    }

    #[test]
    fn resync_stops_at_a_line_that_starts_an_item() {
        let src = "let a = f(1,\nscene = a;";
        assert_eq!(resync(src, 0, 13), 13);
        // but not at a call that happens to be named like a keyword
        let src = "let a = f(1,\n material(s, red)";
        assert_eq!(resync(src, 0, 14), src.len());
    }

    #[test]
    fn comments_are_skipped() {
        let src = "let a = 1 /* ; */ // ;\n;";
        assert_eq!(resync(src, 0, 10), src.len());
        assert!(precheck("/* ( ( ( */").is_ok());
        assert!(precheck("/* never closed").is_err());
    }

    #[test]
    fn nesting_counts_brackets_and_lambdas() {
        let deep = |n: usize, unit: &str| format!("scene = f({});", unit.repeat(n));
        assert!(precheck(&deep(MAX_NESTING - 1, "|p| ")).is_ok());
        assert!(precheck(&deep(MAX_NESTING, "|p| ")).is_err());
        assert!(precheck(&deep(MAX_NESTING / 2 - 1, "|p| f(")).is_ok());
        assert!(precheck(&deep(MAX_NESTING / 2, "|p| f(")).is_err());
        // lambdas side by side do not nest
        let wide = format!("scene = f({});", "|p| p, ".repeat(1000));
        assert!(precheck(&wide).is_ok());
        let wide = format!("scene = {};", "f(|x, z| x | z) | ".repeat(1000));
        assert!(precheck(&wide).is_ok());
        // `|` as an operator is not a lambda
        let ors = format!("scene = {};", "a | ".repeat(1000));
        assert!(precheck(&ors).is_ok());
    }

    #[test]
    fn tokens() {
        assert_eq!(token_at("a <= b", 2).map(|t| t.1), Some("<="));
        assert_eq!(token_at("x 1.5e3deg;", 2).map(|t| t.1), Some("1.5e3deg"));
        assert_eq!(token_at("é", 0).map(|t| t.1), Some("é"));
        assert_eq!(token_at("abc", 3), None);
    }
}
