//! Non-fatal findings of the parser.

use crate::edition::Edition;
use crate::error::Position;

/// Something unusual that does not prevent using the file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Warning {
    /// A keyword the edition makes mandatory is absent.
    #[error("{edition} requires keyword [{name}], which is missing")]
    MissingKeyword {
        /// The file's edition.
        edition: Edition,
        /// The keyword.
        name: String,
    },
    /// A line in the keyword block that is not `[KEYWORD] value` (kept as text).
    #[error("line {line}: not a keyword line (kept as text)")]
    NonKeywordLine {
        /// 1-based line.
        line: usize,
    },
    /// `[MORE]` with no keyword before it.
    #[error("line {line}: [MORE] without a preceding keyword")]
    OrphanMore {
        /// 1-based line.
        line: usize,
    },
    /// `TILT=<file>` that the resolver could not supply.
    #[error("line {line}: TILT file {name:?} not loaded")]
    TiltFileUnresolved {
        /// 1-based line.
        line: usize,
        /// The file name.
        name: String,
    },
    /// An integer field written as `2.0` (accepted only with `ParseOptions::lenient`).
    #[error("{at}: {field} written as a decimal number")]
    IntegerWrittenAsDecimal {
        /// Position.
        at: Position,
        /// The field.
        field: &'static str,
    },
    /// Lumens per lamp negative but not −1.
    #[error("{at}: lumens per lamp {value} is negative but not -1 (absolute photometry)")]
    NegativeLumens {
        /// Position.
        at: Position,
        /// The value.
        value: f64,
    },
    /// Tokens after the last candela value, ignored: any non-numeric text, or (with
    /// `ParseOptions::lenient`) numbers, which otherwise are an `IesError::CountMismatch`.
    #[error("{at}: data after the last candela value ignored")]
    TrailingData {
        /// Position of the first extra token.
        at: Position,
    },
}
