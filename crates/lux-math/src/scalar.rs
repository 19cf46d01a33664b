//! Scalar helpers with the argument orders of the UsdLux text.

/// `lerp(t, a, b) = (1 − t)·a + t·b`, with `t` first as in the UsdLux ShapingAPI text.
///
/// Exact at both ends: `lerp(0, a, b) == a` and `lerp(1, a, b) == b`.
#[inline]
pub fn lerp(t: f64, a: f64, b: f64) -> f64 {
    (1.0 - t) * a + t * b
}

/// `smoothStep(x, e0, e1)` of the UsdLux ShapingAPI text (x first): the Hermite cubic
/// `3t² − 2t³` on `t = clamp((x − e0)/(e1 − e0), 0, 1)`.
///
/// When `e0 == e1` the step is a hard edge: 0 for `x < e0`, 1 otherwise (the limit of the cubic).
/// A NaN argument gives 0.
#[inline]
pub fn smooth_step(x: f64, e0: f64, e1: f64) -> f64 {
    let w = e1 - e0;
    if w == 0.0 {
        return if x >= e0 { 1.0 } else { 0.0 };
    }
    smooth_step_fraction((x - e0) / w)
}

/// The cubic of [`smooth_step`] at the unclamped fraction `t = (x − e0)/(e1 − e0)`:
/// `3t² − 2t³` on `clamp(t, 0, 1)`, 0 for NaN. For callers that prepare `1/(e1 − e0)` once
/// and multiply (the ShapingAPI cone ramp `smoothStep(θ, start, cut)` per direction).
#[inline]
pub fn smooth_step_fraction(t: f64) -> f64 {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lerp_ends_and_middle() {
        assert_eq!(lerp(0.0, 2.0, 5.0), 2.0);
        assert_eq!(lerp(1.0, 2.0, 5.0), 5.0);
        assert_eq!(lerp(0.5, 2.0, 5.0), 3.5);
    }

    #[test]
    fn smooth_step_values() {
        assert_eq!(smooth_step(-1.0, 0.0, 1.0), 0.0);
        assert_eq!(smooth_step(2.0, 0.0, 1.0), 1.0);
        assert_eq!(smooth_step(0.5, 0.0, 1.0), 0.5);
        // t = 0.25 -> 3/16 - 2/64 = 0.15625
        assert!((smooth_step(0.25, 0.0, 1.0) - 0.15625).abs() < 1e-15);
        assert!((smooth_step(1.5, 1.0, 3.0) - 0.15625).abs() < 1e-15);
        // hard edge
        assert_eq!(smooth_step(0.9, 1.0, 1.0), 0.0);
        assert_eq!(smooth_step(1.0, 1.0, 1.0), 1.0);
        assert_eq!(smooth_step(f64::NAN, 0.0, 1.0), 0.0);
    }
}
