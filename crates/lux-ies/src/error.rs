//! The one error type of the crate: every refusal names where (line, column) and what was expected.

/// Where in a file an error was found: 1-based line and column (column counted in characters).
///
/// `line == 0` means the value did not come from a file (e.g. an [`IesFile`](crate::IesFile) built
/// in code and validated before expansion).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Position {
    /// 1-based line number (0: not from a file).
    pub line: usize,
    /// 1-based column number in characters (0: not from a file).
    pub column: usize,
}

impl Position {
    /// A position in a file.
    pub const fn new(line: usize, column: usize) -> Position {
        Position { line, column }
    }
}

impl core::fmt::Display for Position {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// Everything that makes an LM-63 file unusable.
///
/// Each variant carries the [`Position`] of the offending token (or of the end of the file) and
/// says what the LM-63 grammar expected there, so that a front end can print `file:line:column`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IesError {
    /// The file ended before all fields were read (LM-63 §"photometric data" counts).
    #[error("{at}: unexpected end of file: expected {expected}")]
    Truncated {
        /// End of the file.
        at: Position,
        /// The field that was still missing, e.g. "candela value 12 of 73 for horizontal angle 5".
        expected: String,
    },
    /// A token that is not a number where the LM-63 grammar requires one (text inside the numbers,
    /// `+ 3.0` with a detached sign, `inf`, `NaN`, ...).
    #[error("{at}: expected {expected}, found {found:?}")]
    NotANumber {
        /// The token.
        at: Position,
        /// The field being read.
        expected: String,
        /// The token text.
        found: String,
    },
    /// A number outside the values the field allows (non-integral counts, unknown photometric
    /// type, NaN/infinite or negative candela, non-positive multiplier, ...).
    #[error("{at}: invalid {field}: {value} (expected {expected})")]
    InvalidValue {
        /// The token.
        at: Position,
        /// The field, e.g. "photometric type".
        field: &'static str,
        /// The value as written.
        value: String,
        /// What the field allows.
        expected: String,
    },
    /// A count larger than any real file needs; refused before anything is allocated.
    #[error("{at}: absurd {field} {value} (at most {max} allowed)")]
    AbsurdCount {
        /// The token.
        at: Position,
        /// The count field.
        field: &'static str,
        /// The count read.
        value: u64,
        /// The cap.
        max: u64,
    },
    /// More numbers than the header's counts declare: numeric data after the last of the
    /// `n_h × n_v` candela values, i.e. the counts and the data disagree (LM-63 "number of
    /// vertical/horizontal angles"). Refused unless [`ParseOptions::lenient`] is set.
    ///
    /// [`ParseOptions::lenient`]: crate::ParseOptions::lenient
    #[error("{at}: count mismatch: found {found:?} after the {expected}")]
    CountMismatch {
        /// The first extra number.
        at: Position,
        /// Its text.
        found: String,
        /// What the header declared, e.g. "73 × 37 = 2701 candela values the header declares".
        expected: String,
    },
    /// Angles that are not strictly increasing.
    #[error("{at}: {field} angles must be strictly increasing: {value} follows {previous}")]
    NonMonotonic {
        /// The offending angle.
        at: Position,
        /// "vertical", "horizontal" or "tilt".
        field: &'static str,
        /// The preceding angle.
        previous: f64,
        /// The offending angle.
        value: f64,
    },
    /// An angle set outside the ranges LM-63 allows for the photometric type and symmetry.
    #[error(
        "{at}: illegal {field} angle range {first}..{last} for photometric type {ptype}: expected {expected}"
    )]
    IllegalAngleRange {
        /// The first angle of the set.
        at: Position,
        /// "vertical" or "horizontal".
        field: &'static str,
        /// First angle (degrees).
        first: f64,
        /// Last angle (degrees).
        last: f64,
        /// "A", "B" or "C".
        ptype: char,
        /// The allowed ranges.
        expected: &'static str,
    },
    /// The header does not contain a `TILT=` line.
    #[error("{at}: no TILT= line found (expected TILT=NONE, TILT=INCLUDE or TILT=<file>)")]
    MissingTilt {
        /// End of the file.
        at: Position,
    },
    /// `TILT=<file>` could not be resolved and the caller asked for the file to be required.
    #[error("{at}: TILT file {name:?} could not be loaded")]
    TiltFileMissing {
        /// The TILT line.
        at: Position,
        /// The file name written after `TILT=`.
        name: String,
    },
    /// An error inside a `TILT=<file>` file (the inner error's position is inside that file).
    #[error("{at}: in TILT file {name:?}: {inner}")]
    TiltFile {
        /// The TILT line of the outer file.
        at: Position,
        /// The TILT file name.
        name: String,
        /// The error inside the TILT file.
        inner: Box<IesError>,
    },
    /// A parsed or hand-built [`IesFile`](crate::IesFile) whose arrays disagree with each other.
    #[error("{at}: {what}")]
    Inconsistent {
        /// Usually `0:0` (built in code).
        at: Position,
        /// What disagrees.
        what: String,
    },
}

impl IesError {
    /// The position the error refers to.
    pub fn position(&self) -> Position {
        match self {
            IesError::Truncated { at, .. }
            | IesError::NotANumber { at, .. }
            | IesError::InvalidValue { at, .. }
            | IesError::AbsurdCount { at, .. }
            | IesError::CountMismatch { at, .. }
            | IesError::NonMonotonic { at, .. }
            | IesError::IllegalAngleRange { at, .. }
            | IesError::MissingTilt { at }
            | IesError::TiltFileMissing { at, .. }
            | IesError::TiltFile { at, .. }
            | IesError::Inconsistent { at, .. } => *at,
        }
    }

    /// 1-based line of the error (0 when not from a file).
    pub fn line(&self) -> usize {
        self.position().line
    }

    /// 1-based column of the error (0 when not from a file).
    pub fn column(&self) -> usize {
        self.position().column
    }
}
