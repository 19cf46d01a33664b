//! The lexer of the `.usda` compatibility pass: the token classes of `textFileFormat.ll`
//! that matter for rewriting.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// Identifier, keyword or namespaced identifier (`inputs:texture:file`, `a::b`).
    Ident,
    /// `"…"`, `'…'`, `"""…"""`, `'''…'''`.
    Str,
    /// `@…@` or `@@@…@@@`.
    Asset,
    /// `<…>`.
    PathRef,
    /// A number (without its sign).
    Number,
    /// Any other single byte.
    Punct(u8),
    /// `# …` to the end of the line.
    HashComment,
    /// `// …` to the end of the line.
    SlashComment,
    /// `/* … */`.
    BlockComment,
    /// An unterminated string or asset path (to the end of its line).
    Unterminated,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Token {
    pub(super) kind: Kind,
    pub(super) start: usize,
    pub(super) end: usize,
    /// A line break between the previous significant token and this one.
    pub(super) newline_before: bool,
}

impl Token {
    pub(super) fn is(&self, p: u8) -> bool {
        self.kind == Kind::Punct(p)
    }
    pub(super) fn is_comment(&self) -> bool {
        matches!(
            self.kind,
            Kind::HashComment | Kind::SlashComment | Kind::BlockComment
        )
    }
}

pub(super) fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_' || b >= 0x80
}

pub(super) fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

/// End (exclusive) of the line holding `from`: the first `\n` or `\r` at or after it.
pub(super) fn line_end(b: &[u8], from: usize) -> usize {
    from + b[from.min(b.len())..]
        .iter()
        .position(|c| *c == b'\n' || *c == b'\r')
        .unwrap_or(b.len().saturating_sub(from))
}

#[derive(Clone, Copy)]
pub(super) struct Lexer<'a> {
    pub(super) b: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(b: &'a [u8]) -> Lexer<'a> {
        Lexer { b, pos: 0 }
    }

    pub(super) fn at(&self, i: usize) -> u8 {
        self.b.get(i).copied().unwrap_or(0)
    }

    pub(super) fn starts(&self, i: usize, s: &[u8]) -> bool {
        self.b.get(i..).is_some_and(|r| r.starts_with(s))
    }

    /// The next token, comments included.
    pub(super) fn next(&mut self) -> Option<Token> {
        let b = self.b;
        let mut newline = false;
        while let Some(&c) = b.get(self.pos) {
            match c {
                b'\n' | b'\r' => newline = true,
                b' ' | b'\t' | 0x0c => {}
                _ => break,
            }
            self.pos += 1;
        }
        let start = self.pos;
        let c = *b.get(start)?;
        let kind = match c {
            b'#' => {
                self.pos = line_end(b, start);
                Kind::HashComment
            }
            b'/' if self.at(start + 1) == b'/' => {
                self.pos = line_end(b, start);
                Kind::SlashComment
            }
            b'/' if self.at(start + 1) == b'*' => {
                let body = start + 2;
                let close = b[body..].windows(2).position(|w| w == b"*/");
                if b[body..close.map_or(b.len(), |c| body + c)]
                    .iter()
                    .any(|c| *c == b'\n' || *c == b'\r')
                {
                    newline = true;
                }
                self.pos = close.map_or(b.len(), |c| body + c + 2);
                Kind::BlockComment
            }
            b'"' | b'\'' => self.string(c),
            b'@' => self.asset(),
            b'<' => {
                let end = b[start + 1..]
                    .iter()
                    .position(|c| matches!(c, b'>' | b'<' | b'\n' | b'\r'));
                match end {
                    Some(e) if b[start + 1 + e] == b'>' => {
                        self.pos = start + e + 2;
                        Kind::PathRef
                    }
                    _ => {
                        self.pos = start + 1;
                        Kind::Punct(b'<')
                    }
                }
            }
            b'0'..=b'9' => self.number(),
            b'.' if self.at(start + 1).is_ascii_digit() => self.number(),
            c if is_ident_start(c) => self.ident(),
            _ => {
                self.pos = start + 1;
                Kind::Punct(c)
            }
        };
        Some(Token {
            kind,
            start,
            end: self.pos,
            newline_before: newline,
        })
    }

    /// A quoted string (escapes `\x` skip one character; single-quoted strings end at the line).
    pub(super) fn string(&mut self, q: u8) -> Kind {
        let b = self.b;
        let start = self.pos;
        let triple = self.at(start + 1) == q && self.at(start + 2) == q;
        let mut i = start + if triple { 3 } else { 1 };
        while i < b.len() {
            let c = b[i];
            if c == b'\\' {
                i += 2;
            } else if triple && c == q && self.at(i + 1) == q && self.at(i + 2) == q {
                self.pos = i + 3;
                return Kind::Str;
            } else if !triple && c == q {
                self.pos = i + 1;
                return Kind::Str;
            } else if !triple && (c == b'\n' || c == b'\r') {
                break;
            } else {
                i += 1;
            }
        }
        self.pos = if triple { b.len() } else { line_end(b, start) };
        Kind::Unterminated
    }

    /// `@…@` or `@@@…@@@` (`\@@@` escaped inside, up to two `@` before the closing `@@@`).
    pub(super) fn asset(&mut self) -> Kind {
        let b = self.b;
        let start = self.pos;
        if self.starts(start, b"@@@") {
            let mut i = start + 3;
            while i < b.len() {
                match b[i] {
                    b'\\' if self.starts(i + 1, b"@@@") => i += 4,
                    b'@' if self.starts(i, b"@@@") => {
                        let run = b[i..].iter().take_while(|c| **c == b'@').count();
                        self.pos = i + run;
                        return Kind::Asset;
                    }
                    b'\n' | b'\r' => break,
                    _ => i += 1,
                }
            }
        } else if let Some(e) = b[start + 1..]
            .iter()
            .position(|c| matches!(c, b'@' | b'\n' | b'\r'))
            && b[start + 1 + e] == b'@'
        {
            self.pos = start + e + 2;
            return Kind::Asset;
        }
        self.pos = line_end(b, start);
        Kind::Unterminated
    }

    pub(super) fn number(&mut self) -> Kind {
        let b = self.b;
        let digits = |i: usize| i + b[i..].iter().take_while(|c| c.is_ascii_digit()).count();
        let mut i = digits(self.pos);
        if self.at(i) == b'.' {
            i = digits(i + 1);
        }
        if matches!(self.at(i), b'e' | b'E') {
            let sign = usize::from(matches!(self.at(i + 1), b'+' | b'-'));
            if self.at(i + 1 + sign).is_ascii_digit() {
                i = digits(i + 1 + sign);
            }
        }
        self.pos = i;
        Kind::Number
    }

    /// An identifier, with `:`- or `::`-separated continuations.
    pub(super) fn ident(&mut self) -> Kind {
        let b = self.b;
        let word = |i: usize| i + b[i..].iter().take_while(|c| is_ident_byte(**c)).count();
        let mut i = word(self.pos);
        loop {
            if self.at(i) == b':' && is_ident_start(self.at(i + 1)) {
                i = word(i + 1);
            } else if self.starts(i, b"::") && is_ident_start(self.at(i + 2)) {
                i = word(i + 2);
            } else {
                break;
            }
        }
        self.pos = i;
        Kind::Ident
    }
}
