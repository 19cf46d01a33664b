//! Typed construction errors of every sampler in this crate.

use thiserror::Error;

/// Why a light sampler, distribution or selector could not be built.
///
/// Sampling itself never fails with an error: an impossible configuration (reference point on
/// the non-emitting side, zero solid angle, ...) is reported as `None` from `sample` and a zero
/// density from `pdf`. Errors only come from constructors, which validate their plain data.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SampleError {
    /// A parameter was NaN or infinite.
    #[error("{field}: expected a finite number, got {value}")]
    NonFinite {
        /// The offending field, named after its UsdLux attribute where there is one.
        field: &'static str,
        /// The value received.
        value: f64,
    },
    /// A parameter that must be strictly positive (a size) was zero or negative.
    #[error("{field}: expected a value > 0, got {value}")]
    NonPositive {
        /// The offending field.
        field: &'static str,
        /// The value received.
        value: f64,
    },
    /// A weight (power, luminance, texel) was negative.
    #[error("{field}[{index}]: expected a finite value >= 0, got {value}")]
    BadWeight {
        /// The offending array.
        field: &'static str,
        /// Index of the offending entry.
        index: usize,
        /// The value received.
        value: f64,
    },
    /// The light-to-world transform is singular, projective or non-finite.
    #[error("transform: {0}")]
    BadTransform(&'static str),
    /// An array had the wrong length or an absurd size.
    #[error("{field}: expected {expected}, got {got}")]
    BadSize {
        /// The offending array.
        field: &'static str,
        /// What was expected, in words.
        expected: String,
        /// What was received.
        got: usize,
    },
    /// A triangle index pointed outside the vertex array.
    #[error("indices[{triangle}]: vertex index {index} out of range (have {vertices} vertices)")]
    BadIndex {
        /// The triangle holding the bad index.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A light kind that is not sampled ([`lux_math::LightShape::Portal`]: a PortalLight only
    /// guides the dome light it belongs to and emits nothing itself).
    #[error("{light}: not a light that is sampled")]
    NotSampled {
        /// The USD schema type name.
        light: &'static str,
    },
    /// Every weight was zero, so no distribution exists.
    #[error("{0}: all weights are zero")]
    AllZero(&'static str),
}

/// Checks that `value` is finite and > 0.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<f64, SampleError> {
    if !value.is_finite() {
        return Err(SampleError::NonFinite { field, value });
    }
    if value <= 0.0 {
        return Err(SampleError::NonPositive { field, value });
    }
    Ok(value)
}

/// Checks that `value` is finite.
pub(crate) fn finite(field: &'static str, value: f64) -> Result<f64, SampleError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SampleError::NonFinite { field, value })
    }
}

/// Largest number of entries any table of this crate allocates (2²⁸ ≈ 268 M, e.g. a 16384×16384
/// dome texture); larger requests are rejected instead of exhausting memory.
pub const MAX_ENTRIES: usize = 1 << 28;

impl From<lux_math::TransformError> for SampleError {
    /// A light-to-world matrix [`lux_math::LightTransform::new`] refused.
    fn from(e: lux_math::TransformError) -> Self {
        SampleError::BadTransform(e.0)
    }
}
