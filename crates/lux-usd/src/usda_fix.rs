//! Work-around for a gap in the `openusd` 0.6 text parser.
//!
//! `openusd` 0.6.0 rejects `asset` attributes whose `timeSamples` hold scalar asset paths
//! (`asset inputs:shaping:ies:file.timeSamples = { 1: @a.ies@ }` fails with "Unsupported property
//! metadata value token"), although the luxtest scenes author exactly that. Before a `.usda`
//! layer reaches the parser, [`rewrite_asset_time_samples`] turns each such sample into a
//! one-element `asset[]` (`1: [@a.ies@]`), which the parser accepts and whose paths the
//! composition engine still resolves against the authoring layer. The loader reads a one-element
//! asset array back as a single asset path.

/// Rewrites every `asset NAME.timeSamples = { t: @path@, … }` block of a `.usda` text so that each
/// sample value is a one-element asset array. Returns `None` when the text needs no change.
///
/// Only declarations whose type token is exactly `asset` are touched; string and comment contents
/// outside those blocks are copied verbatim. Malformed blocks (no closing brace) are left as they
/// are, so the parser reports them.
pub fn rewrite_asset_time_samples(text: &str) -> Option<String> {
    if !text.contains(".timeSamples") || !text.contains("asset") {
        return None;
    }
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len() + 64);
    let mut copied = 0usize;
    let mut changed = false;
    let mut search = 0usize;
    while let Some(rel) = text[search..].find("asset") {
        let start = search + rel;
        search = start + 5;
        // `asset` must be a whole word followed by whitespace (the type of a declaration).
        let before_ok = start == 0 || bytes[start - 1].is_ascii_whitespace();
        let after_ok = bytes
            .get(start + 5)
            .is_some_and(|b| *b == b' ' || *b == b'\t');
        if !before_ok || !after_ok {
            continue;
        }
        // The declaration's name, then `.timeSamples`, `=`, `{` on the same line.
        let line_end = text[start..].find('\n').map_or(text.len(), |e| start + e);
        let line = &text[start + 5..line_end];
        let name_and_rest = line.trim_start();
        let Some(ts) = name_and_rest.find(".timeSamples") else {
            continue;
        };
        let name = &name_and_rest[..ts];
        if name.is_empty() || name.contains(char::is_whitespace) {
            continue;
        }
        let after = name_and_rest[ts + ".timeSamples".len()..].trim_start();
        let Some(after_eq) = after.strip_prefix('=') else {
            continue;
        };
        if !after_eq.trim_start().starts_with('{') {
            continue;
        }
        let brace = start + 5 + line.find('{').unwrap_or(0);
        let Some(close) = find_block_end(bytes, brace) else {
            continue;
        };
        // Copy up to the type token, declare it `asset[]`, then the rewritten block.
        out.push_str(&text[copied..start + 5]);
        out.push_str("[]");
        out.push_str(&text[start + 5..=brace]);
        out.push_str(&wrap_asset_literals(&text[brace + 1..close]));
        copied = close;
        search = close;
        changed = true;
    }
    if !changed {
        return None;
    }
    out.push_str(&text[copied..]);
    Some(out)
}

/// Index of the `}` matching the `{` at `open`, skipping asset literals and strings.
fn find_block_end(bytes: &[u8], open: usize) -> Option<usize> {
    let mut i = open + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'}' => return Some(i),
            b'@' => i = skip_asset_literal(bytes, i)?,
            b'"' | b'\'' => i = skip_string(bytes, i)?,
            _ => i += 1,
        }
    }
    None
}

/// Index just past the asset literal starting at `at` (`@…@` or `@@@…@@@`).
fn skip_asset_literal(bytes: &[u8], at: usize) -> Option<usize> {
    if bytes[at..].starts_with(b"@@@") {
        let rest = &bytes[at + 3..];
        let end = rest.windows(3).position(|w| w == b"@@@")?;
        Some(at + 3 + end + 3)
    } else {
        let end = bytes[at + 1..].iter().position(|b| *b == b'@')?;
        Some(at + 1 + end + 1)
    }
}

/// Index just past the quoted string starting at `at` (single-line quotes, backslash escapes).
fn skip_string(bytes: &[u8], at: usize) -> Option<usize> {
    let quote = bytes[at];
    let mut i = at + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b if b == quote => return Some(i + 1),
            _ => i += 1,
        }
    }
    None
}

/// Wraps every asset literal of a time-sample block body in `[` `]`.
fn wrap_asset_literals(body: &str) -> String {
    let bytes = body.as_bytes();
    let mut out = String::with_capacity(body.len() + 16);
    let mut i = 0;
    let mut copied = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'@' => {
                let Some(end) = skip_asset_literal(bytes, i) else {
                    break;
                };
                out.push_str(&body[copied..i]);
                out.push('[');
                out.push_str(&body[i..end]);
                out.push(']');
                copied = end;
                i = end;
            }
            b'"' | b'\'' => i = skip_string(bytes, i).unwrap_or(bytes.len()),
            _ => i += 1,
        }
    }
    out.push_str(&body[copied..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_scalar_asset_samples_only() {
        let src = "#usda 1.0\ndef X \"a\" {\n    asset inputs:f.timeSamples = {\n        1: @../a.ies@,\n        2: @@@b@c.ies@@@,\n        3: None,\n    }\n    asset inputs:g = @keep.ies@\n    string s.timeSamples = { 1: \"@x@\" }\n}\n";
        let out = rewrite_asset_time_samples(src).expect("changed");
        assert!(out.contains("asset[] inputs:f.timeSamples"));
        assert!(out.contains("1: [@../a.ies@],"));
        assert!(openusd::usda::parse(&out).is_ok());
        assert!(out.contains("2: [@@@b@c.ies@@@],"));
        assert!(out.contains("3: None,"));
        assert!(out.contains("asset inputs:g = @keep.ies@"));
        assert!(out.contains("1: \"@x@\""));
    }

    #[test]
    fn wraps_empty_asset_samples() {
        // the luxtest cylinder scene authors `1: @@` (no profile on frame 1)
        let src = "#usda 1.0\ndef X \"a\" {\n    asset inputs:shaping:ies:file.timeSamples = {\n        1: @@,\n        2: @a.ies@,\n    }\n}\n";
        let out = rewrite_asset_time_samples(src).expect("changed");
        assert!(out.contains("1: [@@],"), "{out}");
        assert!(out.contains("2: [@a.ies@],"), "{out}");
        assert!(openusd::usda::parse(&out).is_ok());
    }

    #[test]
    fn untouched_text_is_not_copied() {
        assert_eq!(
            rewrite_asset_time_samples("#usda 1.0\ndef X \"a\" {}\n"),
            None
        );
        // unterminated block: left for the parser to report
        assert_eq!(
            rewrite_asset_time_samples("asset a.timeSamples = { 1: @x@"),
            None
        );
    }
}
