//! LM-63 editions and how each announces itself on the first line.

/// The edition of the LM-63 standard a file follows, from its first line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Edition {
    /// LM-63-1986: no version line; any text may precede `TILT=`.
    Lm63_1986,
    /// LM-63-1991: first line `IESNA91`.
    Lm63_1991,
    /// LM-63-1995: first line `IESNA:LM-63-1995` (also the non-standard `IESNA95`).
    Lm63_1995,
    /// LM-63-2002: first line `IESNA:LM-63-2002`.
    Lm63_2002,
    /// LM-63-2019: first line `IES:LM-63-2019`.
    Lm63_2019,
}

impl Edition {
    /// Recognises a version line. Spaces anywhere, letter case and a trailing `\r` are ignored, so
    /// `IESNA: LM-63-2002 ` is 2002 and `IESNA95` is 1995. `None` means "not a version line":
    /// the file is LM-63-1986 and the line is ordinary header text.
    pub fn detect(line: &str) -> Option<Edition> {
        let compact: String = line
            .chars()
            .filter(|c| !c.is_whitespace() && *c != '\u{feff}')
            .flat_map(char::to_uppercase)
            .collect();
        match compact.as_str() {
            "IESNA91" | "IESNA:LM-63-1991" | "IESNA:LM-63-91" => Some(Edition::Lm63_1991),
            "IESNA95" | "IESNA:LM-63-1995" | "IESNA:LM-63-95" => Some(Edition::Lm63_1995),
            "IESNA02" | "IESNA:LM-63-2002" | "IES:LM-63-2002" => Some(Edition::Lm63_2002),
            "IES:LM-63-2019" | "IESNA:LM-63-2019" | "IES:LM-63-19" => Some(Edition::Lm63_2019),
            _ => None,
        }
    }

    /// The version line this edition writes (`None` for 1986, which has none).
    pub const fn version_line(self) -> Option<&'static str> {
        match self {
            Edition::Lm63_1986 => None,
            Edition::Lm63_1991 => Some("IESNA91"),
            Edition::Lm63_1995 => Some("IESNA:LM-63-1995"),
            Edition::Lm63_2002 => Some("IESNA:LM-63-2002"),
            Edition::Lm63_2019 => Some("IES:LM-63-2019"),
        }
    }

    /// The year of the edition (1986, 1991, 1995, 2002, 2019).
    pub const fn year(self) -> u16 {
        match self {
            Edition::Lm63_1986 => 1986,
            Edition::Lm63_1991 => 1991,
            Edition::Lm63_1995 => 1995,
            Edition::Lm63_2002 => 2002,
            Edition::Lm63_2019 => 2019,
        }
    }

    /// Keywords the edition makes mandatory: 1991 and 1995 `[TEST]`, `[MANUFAC]`; 2002 adds
    /// `[TESTLAB]`, `[ISSUEDATE]`; 2019 further `[LUMCAT]`, `[LUMINAIRE]`, `[LAMP]`, `[LAMPCAT]`.
    /// Missing ones are reported as warnings, never as errors.
    pub const fn required_keywords(self) -> &'static [&'static str] {
        match self {
            Edition::Lm63_1986 => &[],
            Edition::Lm63_1991 | Edition::Lm63_1995 => &["TEST", "MANUFAC"],
            Edition::Lm63_2002 => &["TEST", "TESTLAB", "ISSUEDATE", "MANUFAC"],
            Edition::Lm63_2019 => &[
                "TEST",
                "TESTLAB",
                "ISSUEDATE",
                "MANUFAC",
                "LUMCAT",
                "LUMINAIRE",
                "LAMP",
                "LAMPCAT",
            ],
        }
    }
}

impl core::fmt::Display for Edition {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "LM-63-{}", self.year())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn version_lines() {
        assert_eq!(Edition::detect("IESNA91"), Some(Edition::Lm63_1991));
        assert_eq!(
            Edition::detect("IESNA:LM-63-1995\r"),
            Some(Edition::Lm63_1995)
        );
        assert_eq!(
            Edition::detect("IESNA: LM-63-2002 "),
            Some(Edition::Lm63_2002)
        );
        assert_eq!(Edition::detect("IESNA95"), Some(Edition::Lm63_1995));
        assert_eq!(Edition::detect("IES:LM-63-2019"), Some(Edition::Lm63_2019));
        assert_eq!(Edition::detect("Some luminaire"), None);
        for e in [
            Edition::Lm63_1991,
            Edition::Lm63_1995,
            Edition::Lm63_2002,
            Edition::Lm63_2019,
        ] {
            assert_eq!(Edition::detect(e.version_line().unwrap()), Some(e));
        }
    }
}
