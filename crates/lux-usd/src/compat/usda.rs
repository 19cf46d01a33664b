//! The `.usda` compatibility pass: Sdf text-grammar constructs that Pixar's parser (usd-core)
//! accepts and `openusd` 0.6's `usda::parser` rejects, rewritten into equivalent text it
//! accepts before it parses the layer.
//!
//! Every construct is named after the rule of OpenUSD's text grammar it comes from
//! (`pxr/usd/sdf/textFileFormat.ll` for the lexer, `textFileFormat.yy` for the grammar,
//! `sdf/schema.cpp` for the type names):
//!
//! | Construct (accepted by usd-core) | openusd 0.6 | Rewritten to |
//! |---|---|---|
//! | `// comment` (lexer rule `"//"[^\r\n]*`) | `Logos error: ()` | `#/ comment` (same length) |
//! | text after the magic on line 1 (`#usda 1.0 // x`, trailing blanks; usd-core reads line 1 as one `TOK_MAGIC`) | "Text file must start with magic token" (its `#` comment rule out-matches the magic) | the tail removed |
//! | `asset a = "x.png"`, in `asset[]` arrays, `timeSamples` and typed dictionary entries (a quoted string where an asset path is expected; usd-core evaluates the string) | `Asset reference expected` | `@x.png@` (escapes evaluated, padded to the same length) |
//! | `config float a` (`prim_attr_variability: TOK_UNIFORM \| TOK_CONFIG`; read as uniform) | `attribute type expected` | `uniform float a` |
//! | legacy type names (`Vec3f[]`, `PointFloat`, `Color`, `Matrix4d`, …; `_AddLegacyTypesToRegistry`) | `Cannot parse value for unrecognized type` | the current name ([`legacy_type_name`]) |
//! | `pathExpression` (UsdCollectionAPI `membershipExpression`, Sdf 23.11), a type openusd 0.6 does not know | `Cannot parse value for unrecognized type` | `string` (the expression text kept; the loader reads it as text) |
//! | scalar asset time samples (`asset a.timeSamples = { 1: @x@ }`) | "Unsupported property metadata value token" | one-element `asset[]` samples (`1: [@x@]`), which the loader reads back as one asset |
//!
//! C-style `/* … */` comments (lexer state `SLASHTERIX_COMMENT`) are already skipped by
//! openusd's lexer; the pass only steps over them, like over strings, asset paths `@…@` /
//! `@@@…@@@`, path references `<…>` and `#` comments, whose insides are never changed.
//!
//! The pass never adds or removes a newline, so every line keeps its number; a replacement
//! shorter than the original is padded with spaces so that the columns after it stay where
//! they were, and [`UsdaRewrite::original_offset`] maps any position in the rewritten text back
//! to the original for the few longer ones. It runs in one linear scan and copies the text only
//! when something is rewritten ([`rewrite`] returns `None` otherwise, after cheap substring
//! pre-checks for ordinary files).

mod lexer;
#[cfg(test)]
mod tests;

use lexer::{Kind, Lexer, Token, is_ident_byte, line_end};

/// The legacy attribute type names Sdf still registers (`_AddLegacyTypesToRegistry` in
/// OpenUSD's `pxr/usd/sdf/schema.cpp`), each with the current type name holding the same
/// value type (and role, where openusd knows it). `Transform` (a `matrix4d` with the
/// `Transform` role) and `PointIndex` / `EdgeIndex` / `FaceIndex` (an `int` with an index role)
/// have no current name with their role: they map to their value type, `matrix4d` and `int`.
pub const LEGACY_TYPE_NAMES: [(&str, &str); 31] = [
    ("Vec2i", "int2"),
    ("Vec2h", "half2"),
    ("Vec2f", "float2"),
    ("Vec2d", "double2"),
    ("Vec3i", "int3"),
    ("Vec3h", "half3"),
    ("Vec3f", "float3"),
    ("Vec3d", "double3"),
    ("Vec4i", "int4"),
    ("Vec4h", "half4"),
    ("Vec4f", "float4"),
    ("Vec4d", "double4"),
    ("Point", "point3d"),
    ("PointFloat", "point3f"),
    ("Normal", "normal3d"),
    ("NormalFloat", "normal3f"),
    ("Vector", "vector3d"),
    ("VectorFloat", "vector3f"),
    ("Color", "color3d"),
    ("ColorFloat", "color3f"),
    ("Quath", "quath"),
    ("Quatf", "quatf"),
    ("Quatd", "quatd"),
    ("Matrix2d", "matrix2d"),
    ("Matrix3d", "matrix3d"),
    ("Matrix4d", "matrix4d"),
    ("Frame", "frame4d"),
    ("Transform", "matrix4d"),
    ("PointIndex", "int"),
    ("EdgeIndex", "int"),
    ("FaceIndex", "int"),
];

/// The current Sdf type name for a legacy one (`Vec3f` → `float3`, `PointFloat` → `point3f`,
/// `Color` → `color3d`, …; see [`LEGACY_TYPE_NAMES`]), or `None` for any other name. Array
/// brackets are not part of the name (`Vec3f[]` is `Vec3f` followed by `[` `]`).
pub fn legacy_type_name(name: &str) -> Option<&'static str> {
    LEGACY_TYPE_NAMES
        .iter()
        .find(|(old, _)| *old == name)
        .map(|(_, new)| *new)
}

/// A `.usda` text rewritten by [`rewrite`], with what is needed to map positions in it back to
/// the original.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UsdaRewrite {
    /// The rewritten text (the same number of lines as the original).
    pub text: String,
    /// The replaced ranges, in order: `(original start, original end, replacement length)`.
    spans: Vec<(usize, usize, usize)>,
}

impl UsdaRewrite {
    /// The byte offset in the original text of byte `offset` of the rewritten text. A position
    /// inside a replacement maps into the text it replaced (its last byte at most); positions
    /// past the end map past the original's end.
    pub fn original_offset(&self, offset: usize) -> usize {
        // `shift` = rewritten position − original position before the current span.
        let mut shift: isize = 0;
        for &(start, end, new_len) in &self.spans {
            let new_start = (start as isize + shift) as usize;
            if offset < new_start {
                break;
            }
            if offset < new_start + new_len {
                let inside = offset - new_start;
                return start + inside.min((end - start).saturating_sub(1));
            }
            shift += new_len as isize - (end - start) as isize;
        }
        (offset as isize - shift).max(0) as usize
    }

    /// Number of replaced ranges.
    pub fn edit_count(&self) -> usize {
        self.spans.len()
    }
}

/// Rewrites the constructs listed in the [module documentation](self) so that `openusd` 0.6's
/// `.usda` parser reads what usd-core reads. Returns `None` when the text needs no change (the
/// common case, decided without copying it). Malformed constructs are left as they are, for
/// the parser to report.
pub fn rewrite(text: &str) -> Option<UsdaRewrite> {
    if !may_need_rewrite(text) {
        return None;
    }
    let mut r = Rewriter {
        text,
        lex: Lexer::new(text.as_bytes()),
        edits: Vec::new(),
        prev: None,
    };
    if let Some(start) = magic_tail(text) {
        let end = line_end(text.as_bytes(), start);
        r.edits.push(Edit {
            start,
            end,
            new: String::new(),
        });
    }
    r.run();
    apply(text, r.edits)
}

/// Cheap substring pre-checks: whether [`rewrite`] can find anything at all.
fn may_need_rewrite(text: &str) -> bool {
    magic_tail(text).is_some()
        || text.contains("//")
        || text.contains("config")
        || text.contains("asset")
        || text.contains("pathExpression")
        || has_legacy_type_word(text.as_bytes())
}

/// Whether a word of `bytes` (not preceded by an identifier character) is a legacy type
/// name. One pass; a candidate is only checked at an upper-case initial of the table.
fn has_legacy_type_word(bytes: &[u8]) -> bool {
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if matches!(
            b,
            b'V' | b'P' | b'N' | b'C' | b'Q' | b'M' | b'F' | b'T' | b'E'
        ) && (i == 0 || !is_ident_byte(bytes[i - 1]))
        {
            let end = i + bytes[i..]
                .iter()
                .position(|b| !is_ident_byte(*b))
                .unwrap_or(bytes.len() - i);
            if std::str::from_utf8(&bytes[i..end])
                .ok()
                .and_then(legacy_type_name)
                .is_some()
            {
                return true;
            }
            i = end;
        } else {
            i += 1;
        }
    }
    false
}

/// Start of the text after the magic on line 1 (`#usda 1.0<tail>`), when that tail is separated
/// by a blank (usd-core ignores it; openusd's `#` comment rule would swallow the magic).
fn magic_tail(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let rest = text.strip_prefix("#usda ")?.as_bytes();
    let digits = |from: usize| {
        from + rest[from..]
            .iter()
            .take_while(|c| c.is_ascii_digit())
            .count()
    };
    let major = digits(0);
    if major == 0 || rest.get(major) != Some(&b'.') {
        return None;
    }
    let mut end = digits(major + 1);
    if end == major + 1 {
        return None;
    }
    if rest.get(end) == Some(&b'.') && rest.get(end + 1).is_some_and(u8::is_ascii_digit) {
        end = digits(end + 1);
    }
    let start = "#usda ".len() + end;
    matches!(b.get(start), Some(b' ' | b'\t')).then_some(start)
}

/// One replacement of the original range `start..end`.
struct Edit {
    start: usize,
    end: usize,
    new: String,
}

/// Applies sorted, non-overlapping edits; `None` if there are none (or, defensively, if they
/// would break the text).
fn apply(text: &str, mut edits: Vec<Edit>) -> Option<UsdaRewrite> {
    if edits.is_empty() {
        return None;
    }
    edits.sort_by_key(|e| e.start);
    let extra: usize = edits.iter().map(|e| e.new.len()).sum();
    let mut out = Vec::with_capacity(text.len() + extra);
    let mut spans = Vec::with_capacity(edits.len());
    let mut copied = 0;
    for e in &edits {
        if e.start < copied || e.end < e.start || e.end > text.len() {
            return None;
        }
        out.extend_from_slice(&text.as_bytes()[copied..e.start]);
        out.extend_from_slice(e.new.as_bytes());
        spans.push((e.start, e.end, e.new.len()));
        copied = e.end;
    }
    out.extend_from_slice(&text.as_bytes()[copied..]);
    let text = String::from_utf8(out).ok()?;
    Some(UsdaRewrite { text, spans })
}

// ---------------------------------------------------------------------------------------------
// The rewriting pass: finds the constructs over the token stream.

struct Rewriter<'a> {
    text: &'a str,
    lex: Lexer<'a>,
    edits: Vec<Edit>,
    /// The last significant token consumed.
    prev: Option<Token>,
}

impl<'a> Rewriter<'a> {
    fn src(&self, t: &Token) -> &'a str {
        self.text.get(t.start..t.end).unwrap_or("")
    }

    /// The next significant token (`//` comments on the way are rewritten to `#/`).
    fn bump(&mut self) -> Option<Token> {
        let mut newline = false;
        loop {
            let mut t = self.lex.next()?;
            newline |= t.newline_before;
            if t.kind == Kind::SlashComment {
                self.edits.push(Edit {
                    start: t.start,
                    end: t.start + 1,
                    new: "#".into(),
                });
            }
            if t.kind == Kind::BlockComment {
                // a comment spanning lines separates statements like a line break
                newline |= self
                    .text
                    .get(t.start..t.end)
                    .is_some_and(|c| c.contains(['\n', '\r']));
            }
            if !t.is_comment() {
                t.newline_before = newline;
                self.prev = Some(t);
                return Some(t);
            }
        }
    }

    /// The next `N` significant tokens, without consuming them.
    fn peek<const N: usize>(&self) -> [Option<Token>; N] {
        let mut lex = self.lex;
        std::array::from_fn(|_| {
            loop {
                let t = lex.next()?;
                if !t.is_comment() {
                    return Some(t);
                }
            }
        })
    }

    fn peek_is(&self, p: u8) -> bool {
        matches!(self.peek::<1>(), [Some(t)] if t.is(p))
    }

    fn push(&mut self, t: &Token, new: String) {
        self.edits.push(Edit {
            start: t.start,
            end: t.end,
            new,
        });
    }

    fn run(&mut self) {
        let mut prev: Option<Token> = None;
        while let Some(t) = self.bump() {
            if t.kind == Kind::Ident {
                self.word(t, prev);
            }
            prev = self.prev;
        }
    }

    /// An identifier `t` after the significant token `prev`: the start of an attribute (or
    /// typed dictionary entry) declaration?
    fn word(&mut self, t: Token, prev: Option<Token>) {
        let qualifier = prev.is_some_and(|p| {
            p.kind == Kind::Ident
                && matches!(self.src(&p), "custom" | "uniform" | "varying" | "config")
        });
        let statement_start = match prev {
            None => true,
            Some(p) => t.newline_before || p.is(b'{') || p.is(b';') || p.is(b'('),
        };
        if !(statement_start || qualifier) {
            return;
        }
        let word = self.src(&t);
        if word == "config" {
            // `config TYPE NAME` / `config TYPE[] NAME`: read as uniform by usd-core.
            let [ty, a, b, c] = self.peek::<4>();
            let name = match (a, b) {
                (Some(a), Some(b)) if a.is(b'[') && b.is(b']') => c,
                _ => a,
            };
            if ty.is_some_and(|t| t.kind == Kind::Ident)
                && name.is_some_and(|n| n.kind == Kind::Ident)
            {
                self.push(&t, "uniform".into());
            }
            return;
        }
        // `pathExpression` values are quoted strings: read as `string`.
        let legacy =
            legacy_type_name(word).or_else(|| (word == "pathExpression").then_some("string"));
        if legacy.is_none() && word != "asset" {
            return;
        }
        // a type position: `TYPE NAME`, `TYPE[] NAME` (NAME may be a quoted dictionary key)
        let [a, b, c] = self.peek::<3>();
        let (is_array, name) = match (a, b) {
            (Some(a), Some(b)) if a.is(b'[') && b.is(b']') => (true, c),
            (Some(a), _) if a.is(b'[') => return,
            _ => (false, a),
        };
        if !name.is_some_and(|n| matches!(n.kind, Kind::Ident | Kind::Str)) {
            return;
        }
        if let Some(new) = legacy {
            self.push(&t, pad(new.to_owned(), t.end - t.start));
            return;
        }
        self.asset_declaration(t, is_array);
    }

    /// After the type `asset` / `asset[]`: converts quoted-string values to asset paths and
    /// scalar time samples to one-element arrays.
    fn asset_declaration(&mut self, ty: Token, is_array: bool) {
        if is_array {
            self.bump();
            self.bump();
        }
        self.bump(); // the name
        let [a, b, c] = self.peek::<3>();
        match (a, b, c) {
            (Some(dot), Some(suffix), Some(eq))
                if dot.is(b'.') && self.src(&suffix) == "timeSamples" && eq.is(b'=') =>
            {
                self.bump();
                self.bump();
                self.bump();
                if self.peek_is(b'{') {
                    self.bump();
                    self.asset_samples(ty, is_array);
                }
            }
            (Some(eq), _, _) if eq.is(b'=') => {
                self.bump();
                self.asset_value(is_array, false);
            }
            _ => {}
        }
    }

    /// One value of an asset attribute: a string (scalar) or an array of strings / paths.
    /// With `wrap`, a scalar becomes a one-element array. Returns whether a scalar was
    /// rewritten.
    fn asset_value(&mut self, is_array: bool, wrap: bool) -> bool {
        let [next] = self.peek::<1>();
        let Some(next) = next else { return false };
        match next.kind {
            Kind::Str if !is_array => {
                self.bump();
                let Some(lit) = string_to_asset(self.src(&next)) else {
                    return false;
                };
                let new = if wrap { format!("[{lit}]") } else { lit };
                self.push(&next, pad(new, next.end - next.start));
                true
            }
            Kind::Asset if !is_array && wrap => {
                self.bump();
                let new = format!("[{}]", self.src(&next));
                self.push(&next, new);
                true
            }
            Kind::Punct(b'[') if is_array => {
                self.bump();
                while let [Some(t)] = self.peek::<1>() {
                    match t.kind {
                        Kind::Punct(b']') => {
                            self.bump();
                            break;
                        }
                        Kind::Str => {
                            self.bump();
                            if let Some(lit) = string_to_asset(self.src(&t)) {
                                self.push(&t, pad(lit, t.end - t.start));
                            }
                        }
                        Kind::Asset | Kind::Punct(b',') => {
                            self.bump();
                        }
                        _ => break,
                    }
                }
                false
            }
            _ => false,
        }
    }

    /// The body of `asset NAME.timeSamples = {` up to its `}`.
    fn asset_samples(&mut self, ty: Token, is_array: bool) {
        let mark = self.edits.len();
        let mut wrapped = false;
        let mut closed = false;
        'entries: while let [Some(t)] = self.peek::<1>() {
            if t.is(b'}') {
                self.bump();
                closed = true;
                break;
            }
            if t.is(b',') {
                self.bump();
                continue;
            }
            // the time: an optionally signed number (or `inf`), then `:`
            for i in 0.. {
                let Some(k) = self.peek::<1>()[0] else {
                    break 'entries;
                };
                let time_part = matches!(
                    k.kind,
                    Kind::Number | Kind::Ident | Kind::Punct(b'-' | b'+')
                );
                if k.is(b':') && i > 0 {
                    self.bump();
                    break;
                }
                if !time_part || i >= 3 {
                    break 'entries;
                }
                self.bump();
            }
            let [v] = self.peek::<1>();
            match v.map(|v| v.kind) {
                Some(Kind::Str | Kind::Asset) if !is_array => {
                    wrapped |= self.asset_value(false, true);
                }
                Some(Kind::Punct(b'[')) if is_array => {
                    self.asset_value(true, false);
                }
                Some(Kind::Ident) => {
                    self.bump(); // `None`
                }
                _ => break,
            }
        }
        if !closed {
            // a block that does not end is left for the parser to report: keep only the
            // comment rewrites made on the way (`#` for `/`; a value rewrite is longer)
            let tail = self.edits.split_off(mark);
            self.edits.extend(
                tail.into_iter()
                    .filter(|e| e.new == "#" && e.end == e.start + 1),
            );
            return;
        }
        if wrapped {
            self.edits.push(Edit {
                start: ty.end,
                end: ty.end,
                new: "[]".into(),
            });
        }
    }
}

/// `new` padded with spaces to `len` bytes when shorter (columns after it stay put).
fn pad(mut new: String, len: usize) -> String {
    while new.len() < len {
        new.push(' ');
    }
    new
}

/// The asset-path literal (`@…@`, or `@@@…@@@` when the path holds `@`) for a quoted string,
/// its escapes evaluated as Sdf does (`Sdf_EvalQuotedString`: C escapes, `\xHH`, octal `\ooo`,
/// any other escaped character stands for itself). `None` when no literal can hold it: a line
/// break, `@@@`, a trailing `@`, or bytes that are not UTF-8.
fn string_to_asset(raw: &str) -> Option<String> {
    let b = raw.as_bytes();
    let q = *b.first()?;
    let trim = if b.len() >= 6 && b.starts_with(&[q; 3]) && b.ends_with(&[q; 3]) {
        3
    } else if b.len() >= 2 && b[b.len() - 1] == q {
        1
    } else {
        return None;
    };
    let body = &b[trim..b.len() - trim];
    let mut out = Vec::with_capacity(body.len());
    let mut i = 0;
    while i < body.len() {
        let c = body[i];
        i += 1;
        if c != b'\\' || i >= body.len() {
            out.push(c);
            continue;
        }
        let e = body[i];
        i += 1;
        out.push(match e {
            b'a' => 0x07,
            b'b' => 0x08,
            b'f' => 0x0c,
            b'n' => b'\n',
            b'r' => b'\r',
            b't' => b'\t',
            b'v' => 0x0b,
            b'x' => {
                let n = body[i..]
                    .iter()
                    .take(2)
                    .take_while(|c| c.is_ascii_hexdigit())
                    .count();
                let v = std::str::from_utf8(&body[i..i + n])
                    .ok()
                    .and_then(|h| u8::from_str_radix(h, 16).ok());
                i += n;
                v.unwrap_or(b'x')
            }
            b'0'..=b'7' => {
                let n = 1 + body[i..]
                    .iter()
                    .take(2)
                    .take_while(|c| (b'0'..=b'7').contains(c))
                    .count();
                let v = body[i - 1..i - 1 + n]
                    .iter()
                    .fold(0u32, |acc, d| acc * 8 + u32::from(d - b'0'));
                i += n - 1;
                (v & 0xff) as u8
            }
            other => other,
        });
    }
    let path = String::from_utf8(out).ok()?;
    if path.contains(['\n', '\r']) {
        return None;
    }
    if path.contains('@') {
        if path.contains("@@@") || path.ends_with('@') {
            return None;
        }
        return Some(format!("@@@{path}@@@"));
    }
    Some(format!("@{path}@"))
}
