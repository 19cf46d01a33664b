//! Where a `.usda` layer fails to parse, for `FILE:LINE:COLUMN: message` diagnostics.
//!
//! `openusd` 0.6 reports a stage whose text layer does not parse only as `failed to parse USDA
//! layer: …`, without a position, although its parser (`usda::parser::Parser`, public) keeps
//! the span of the last token it consumed ([`Parser::last_error_highlight`]). The loader calls
//! [`locate_usda_error`] on a layer that failed: it applies the same compatibility pass as the
//! resolver ([`super::usda::rewrite`]), parses again, and maps the parser's position back to
//! the text as written.

use super::usda::{UsdaRewrite, rewrite};
use openusd::usda::parser::Parser;
use std::fmt;
use std::path::Path;

/// Where (1-based line and column, counted in characters as `openusd`'s parser counts them)
/// and why a `.usda` text fails to parse: the position of the last token the parser read
/// before it gave up (for an unrecognised token, that token), in the text as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UsdaErrorLocation {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// The parser's diagnostic (its context chain, innermost last).
    pub message: String,
    /// The text of that line, without its line break.
    pub line_text: String,
}

impl fmt::Display for UsdaErrorLocation {
    /// `LINE:COLUMN: message` (prefix the file for the conventional `FILE:LINE:COLUMN: …`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

/// Parses `text` as a `.usda` layer the way the loader does (after the compatibility rewrite
/// of [`super::usda`]) and, if that fails, says where and why; `None` when it parses.
///
/// The position is that of the last token `openusd`'s parser consumed: for a malformed token
/// (`Logos error`, reported here as an unrecognised character) or a value of the wrong kind it
/// is the culprit itself; when the parser stops *before* an unexpected token it is the token
/// just ahead of it. Positions inside text the compatibility pass rewrote are mapped back to
/// the original.
pub fn locate_usda_error(text: &str) -> Option<UsdaErrorLocation> {
    let fixed = rewrite(text);
    let parsed = fixed.as_ref().map_or(text, |r| r.text.as_str());
    let mut parser = Parser::new(parsed);
    let err = parser.parse().err()?;
    let mut message = format!("{err:#}");
    let Some(h) = parser.last_error_highlight() else {
        return Some(position(text, 0, message));
    };
    let offset = offset_of(parsed, h.line, h.column);
    let original = fixed
        .as_ref()
        .map_or(offset, |r: &UsdaRewrite| r.original_offset(offset))
        .min(text.len());
    if message.contains("Logos error") {
        let c = text.get(original..).and_then(|s| s.chars().next());
        let what = match c {
            Some(c) => format!("unrecognized token starting with {c:?}"),
            None => "unrecognized token".to_owned(),
        };
        message = message.replace("Logos error: ()", &what);
    }
    Some(position(text, original, message))
}

/// [`locate_usda_error`] for raw layer bytes: a layer that is not UTF-8 (which `openusd`
/// rejects as a whole, "layer is not valid UTF-8") is located at its first invalid byte.
pub fn locate_usda_error_in_bytes(bytes: &[u8]) -> Option<UsdaErrorLocation> {
    match std::str::from_utf8(bytes) {
        Ok(text) => locate_usda_error(text),
        Err(e) => {
            let valid = e.valid_up_to();
            // the prefix is valid UTF-8 by definition
            let text = std::str::from_utf8(&bytes[..valid]).unwrap_or("");
            Some(position(
                text,
                valid,
                "the layer is not valid UTF-8 (the text format is UTF-8)".to_owned(),
            ))
        }
    }
}

/// `FILE:LINE:COLUMN: message` for the `.usda` layer `file` whose content is `bytes`, or `None`
/// when it parses (after the compatibility pass). The loader's error paths use this to name
/// the position of a parse failure.
pub fn describe_usda_error(file: &Path, bytes: &[u8]) -> Option<String> {
    locate_usda_error_in_bytes(bytes).map(|l| format!("{}:{l}", file.display()))
}

/// [`describe_usda_error`] for a layer named as `openusd` names it — a filesystem path or a
/// package entry `pkg.usdz[inner.usda]`, as in the loader's composition messages — whose
/// bytes are read as written (with `openusd`'s `DefaultResolver`, not through the loader's
/// rewrite). `None` when it cannot be read, is a crate layer, or parses.
pub fn describe_usda_layer_error(layer: &str) -> Option<String> {
    use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
    let resolver = DefaultResolver::new();
    let resolved = resolver
        .resolve(layer)
        .unwrap_or_else(|| ResolvedPath::new(layer));
    let bytes = resolver.open_asset(&resolved).ok()?.read_all().ok()?;
    if bytes.starts_with(openusd::usdc::MAGIC) {
        return None;
    }
    locate_usda_error_in_bytes(&bytes).map(|l| format!("{layer}:{l}"))
}

/// Byte offset of (1-based) `line`, `column` (characters) in `text`, counted as
/// `openusd`'s `ErrorHighlight` counts them (lines split at `\n`).
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let mut start = 0;
    for _ in 1..line {
        match text[start..].find('\n') {
            Some(i) => start += i + 1,
            None => return text.len(),
        }
    }
    text[start..]
        .char_indices()
        .nth(column.saturating_sub(1))
        .map_or(text.len(), |(i, _)| start + i)
}

/// Line, column and line text of byte `offset` of `text`.
fn position(text: &str, offset: usize, message: String) -> UsdaErrorLocation {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = 1 + before.matches('\n').count();
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[line_start..]
        .find('\n')
        .map_or(text.len(), |i| line_start + i);
    UsdaErrorLocation {
        line,
        column: 1 + text[line_start..offset].chars().count(),
        message,
        line_text: text[line_start..line_end].trim_end_matches('\r').to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_cleanly_after_the_compatibility_pass() {
        assert_eq!(
            locate_usda_error(
                "#usda 1.0\n// c\ndef X \"a\" {\n    config Vec3f v = (1, 2, 3)\n}\n"
            ),
            None
        );
    }

    #[test]
    fn columns_are_in_the_original_text() {
        // `config Vec3f` grows by two bytes when rewritten; the bad token after it is still
        // reported where it is written
        let src = "#usda 1.0\ndef X \"a\" {\n    config Vec3f v = (1, 2, 3)\n    float f = $\n}\n";
        let loc = locate_usda_error(src).unwrap();
        assert_eq!((loc.line, loc.column), (4, 15), "{loc:?}");
        assert_eq!(loc.line_text, "    float f = $");
        assert!(
            loc.message.contains("unrecognized token starting with '$'"),
            "{loc}"
        );
        let src = "#usda 1.0\ndef X \"a\" {\n    config Vec3f v = (1, 2, $)\n}\n";
        let loc = locate_usda_error(src).unwrap();
        assert_eq!((loc.line, loc.column), (3, 29), "{loc:?}");
    }

    #[test]
    fn invalid_utf8_and_empty_text() {
        let loc = locate_usda_error_in_bytes(b"#usda 1.0\ndef \xff").unwrap();
        assert_eq!((loc.line, loc.column), (2, 5));
        assert!(locate_usda_error("").is_some());
        assert_eq!(
            describe_usda_error(
                Path::new("s.usda"),
                b"#usda 1.0\ndef X \"a\" {\n    float f = \n}\n"
            )
            .unwrap()
            .split(':')
            .take(3)
            .collect::<Vec<_>>(),
            ["s.usda", "4", "1"]
        );
    }
}
