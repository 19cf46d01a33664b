//! Errors of [`Shaping::new`](crate::Shaping::new).

/// A `ShapingAPI` input that has no defined meaning, reported by
/// [`Shaping::new`](crate::Shaping::new).
///
/// Only values for which neither the schema nor a limit of its formulas gives an answer are
/// errors (NaN cone angle, non-finite focusTint or angleScale, angleScale −1 with the legacy
/// formula); everything else is mapped to a documented finite behaviour.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ShapingError {
    /// An attribute's value is not usable.
    #[error("{attribute} = {value}: expected {expected}")]
    InvalidParameter {
        /// The UsdLux attribute, e.g. `inputs:shaping:cone:angle`.
        attribute: &'static str,
        /// The offending value as written by Rust's `Display` (e.g. `NaN`, `(0, inf, 1)`).
        value: String,
        /// What would have been accepted.
        expected: &'static str,
    },
}
