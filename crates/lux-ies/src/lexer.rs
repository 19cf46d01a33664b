//! Tokeniser for the numeric part of an LM-63 file (everything after the `TILT=` line).
//!
//! LM-63 lets numbers be separated by any white space (including line breaks anywhere) and, in
//! practice, commas. A number is `[+-]digits[.digits][(e|E)[+-]digits]`; anything else (a detached
//! sign, `inf`, `NaN`, words) is text inside the numbers and refused.

use crate::error::{IesError, Position};

/// A whitespace/comma separated token with its 1-based line and column.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    pub text: &'a str,
    pub at: Position,
}

/// Streams tokens out of a text, tracking line and column.
pub(crate) struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
    col: usize,
}

impl<'a> Lexer<'a> {
    /// A lexer over `text`, whose first character is at (`line`, `col`).
    pub fn new(text: &'a str, line: usize, col: usize) -> Self {
        Lexer {
            text,
            pos: 0,
            line,
            col,
        }
    }

    /// Bytes not yet consumed (an upper bound on how many more tokens can follow, times 2).
    pub fn remaining(&self) -> usize {
        self.text.len() - self.pos
    }

    /// The current position (after the last token read).
    pub fn position(&self) -> Position {
        Position::new(self.line, self.col)
    }

    fn is_sep(c: char) -> bool {
        c.is_whitespace() || c == ',' || c == '\u{feff}' || c == '\u{1a}'
    }

    /// The next token, or `None` at the end of the text.
    pub fn next_token(&mut self) -> Option<Token<'a>> {
        let bytes = self.text.as_bytes();
        // skip separators
        while self.pos < bytes.len() {
            let c = self.text[self.pos..].chars().next().unwrap_or(' ');
            if !Self::is_sep(c) {
                break;
            }
            self.advance(c);
        }
        if self.pos >= bytes.len() {
            return None;
        }
        let start = self.pos;
        let at = self.position();
        while self.pos < bytes.len() {
            let c = self.text[self.pos..].chars().next().unwrap_or(' ');
            if Self::is_sep(c) {
                break;
            }
            self.advance(c);
        }
        Some(Token {
            text: &self.text[start..self.pos],
            at,
        })
    }

    fn advance(&mut self, c: char) {
        self.pos += c.len_utf8();
        if c == '\n' {
            self.line += 1;
            self.col = 1;
        } else if c != '\r' {
            self.col += 1;
        }
    }

    /// Reads a finite real number for `field`.
    pub fn real(&mut self, field: &dyn Fn() -> String) -> Result<(f64, Position), IesError> {
        let tok = self.next_token().ok_or_else(|| IesError::Truncated {
            at: self.position(),
            expected: field(),
        })?;
        let v = parse_number(tok.text).ok_or_else(|| IesError::NotANumber {
            at: tok.at,
            expected: field(),
            found: truncate(tok.text),
        })?;
        if !v.is_finite() {
            return Err(IesError::InvalidValue {
                at: tok.at,
                field: "number",
                value: truncate(tok.text),
                expected: format!("a finite {}", field()),
            });
        }
        Ok((v, tok.at))
    }

    /// Reads an integer for `field`. An integral decimal such as `2.0` is accepted; the returned
    /// flag is `true` when the token was not written as a plain integer (the caller warns).
    pub fn integer(
        &mut self,
        field: &dyn Fn() -> String,
    ) -> Result<(i64, Position, bool), IesError> {
        let tok = self.next_token().ok_or_else(|| IesError::Truncated {
            at: self.position(),
            expected: field(),
        })?;
        let v = parse_number(tok.text).ok_or_else(|| IesError::NotANumber {
            at: tok.at,
            expected: field(),
            found: truncate(tok.text),
        })?;
        if !v.is_finite() || v.fract() != 0.0 || v.abs() > 1e15 {
            return Err(IesError::InvalidValue {
                at: tok.at,
                field: "integer field",
                value: truncate(tok.text),
                expected: format!("an integer {}", field()),
            });
        }
        let decorated = tok
            .text
            .bytes()
            .any(|c| !(c.is_ascii_digit() || c == b'-' || c == b'+'));
        Ok((v as i64, tok.at, decorated))
    }
}

fn truncate(s: &str) -> String {
    s.chars().take(40).collect()
}

/// Parses an LM-63 number: `[+-](digits[.digits*] | .digits)[(e|E)[+-]digits]`. Returns `None`
/// for anything else (Rust's own `f64::from_str` would also accept `inf` and `NaN`).
pub(crate) fn parse_number(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let mut i = 0;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    let int_start = i;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
    }
    let mut digits = i - int_start;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        let f = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        digits += i - f;
    }
    if digits == 0 {
        return None;
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        i += 1;
        if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
            i += 1;
        }
        let e = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        if i == e {
            return None;
        }
    }
    if i != b.len() {
        return None;
    }
    s.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number("1e-1"), Some(0.1));
        assert_eq!(parse_number("-.5"), Some(-0.5));
        assert_eq!(parse_number("3."), Some(3.0));
        assert_eq!(parse_number("+2"), Some(2.0));
        for bad in [
            "+", "-", ".", "inf", "NaN", "1e", "1.2.3", "3a", "e5", "infinity", "",
        ] {
            assert_eq!(parse_number(bad), None, "{bad}");
        }
    }

    #[test]
    fn tokens_track_lines_and_columns() {
        let mut lx = Lexer::new("1, 2\r\n  3\n\n4", 10, 1);
        let t: Vec<_> = core::iter::from_fn(|| lx.next_token())
            .map(|t| (t.text, t.at.line, t.at.column))
            .collect();
        assert_eq!(
            t,
            vec![("1", 10, 1), ("2", 10, 4), ("3", 11, 3), ("4", 13, 1)]
        );
    }

    #[test]
    fn detached_sign_is_text() {
        let mut lx = Lexer::new("+ 3.0", 1, 1);
        let e = lx.real(&|| "x".into()).unwrap_err();
        assert!(matches!(e, IesError::NotANumber { .. }));
    }
}
