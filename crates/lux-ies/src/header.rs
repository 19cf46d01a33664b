//! The text header: keyword lines (`[KEY] value` with `[MORE]` continuations) and other lines.

/// One line (or `[MORE]`-joined group of lines) of the header before `TILT=`, kept in file order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum HeaderLine {
    /// `[NAME] value`: the keyword name without brackets (case kept) and its trimmed value;
    /// `[MORE]` lines that follow are appended with `"\n"` (LM-63-2002 §5.2).
    Keyword {
        /// Keyword name, e.g. `TEST`, `_NEMATYPE`.
        name: String,
        /// Trimmed value; continuation lines joined with `\n`.
        value: String,
    },
    /// A line that is not a keyword (LM-63-1986 free text, or vendor lines such as Radiance's
    /// `SCCSid`), trimmed.
    Text(String),
}

/// Splits `[NAME] value` into its parts, or `None` for a non-keyword line.
pub(crate) fn split_keyword(line: &str) -> Option<(&str, &str)> {
    let t = line.trim();
    let rest = t.strip_prefix('[')?;
    let close = rest.find(']')?;
    let name = rest[..close].trim();
    if name.is_empty() {
        return None;
    }
    Some((name, rest[close + 1..].trim()))
}

/// Looks a keyword up by name (ASCII case-insensitive); the first occurrence wins.
pub(crate) fn find<'a>(lines: &'a [HeaderLine], key: &str) -> Option<&'a str> {
    lines.iter().find_map(|l| match l {
        HeaderLine::Keyword { name, value } if name.eq_ignore_ascii_case(key) => {
            Some(value.as_str())
        }
        _ => None,
    })
}
