//! `inputs:shaping:ies:angleScale`: the map from the light's polar angle to the IES lookup angle.

use crate::error::ShapingError;
use crate::params::AngleScaleFormula;
use core::f64::consts::PI;

/// `applyAngleScale(θ, angleScale)` of `inputs:shaping:ies:angleScale`: the polar angle θies
/// (radians, from the light's −Z) at which the IES profile is sampled for an emission direction
/// at polar angle `theta`.
///
/// [`AngleScaleFormula::TwoBranch`] (UsdLux 26.11): a positive scale `s` divides the angle with
/// the origin at θ = 0 (`θ/s`: `s < 1` narrows a downward beam, `s > 1` widens it); a negative
/// scale divides the distance from θ = π instead (`(θ − π)/(−s) + π`, the same for an upward
/// beam); zero leaves θ unchanged. [`AngleScaleFormula::Legacy`]: `(θ − π)/(1 + s) + π`, with
/// `s = 0` the identity.
///
/// Plain arithmetic, no validation: a NaN scale gives NaN, and the legacy formula at `s = −1`
/// divides by zero. [`Shaping::new`](crate::Shaping::new) rejects both.
///
/// ```
/// use lux_shaping::{AngleScaleFormula, apply_angle_scale};
/// let deg = |d: f64| d.to_radians();
/// // a 60° downward beam (edge at 30°) narrowed by 0.5: the edge is now seen at θ = 15°
/// let t = apply_angle_scale(deg(15.0), 0.5, AngleScaleFormula::TwoBranch);
/// assert!((t - deg(30.0)).abs() < 1e-12);
/// // an upward beam (edge at 150°) widened by −1.5: the edge is now at θ = 135°
/// let t = apply_angle_scale(deg(135.0), -1.5, AngleScaleFormula::TwoBranch);
/// assert!((t - deg(150.0)).abs() < 1e-12);
/// ```
pub fn apply_angle_scale(theta: f64, angle_scale: f64, formula: AngleScaleFormula) -> f64 {
    if angle_scale.is_nan() {
        return f64::NAN;
    }
    match formula {
        AngleScaleFormula::TwoBranch => {
            if angle_scale > 0.0 {
                theta / angle_scale
            } else if angle_scale < 0.0 {
                (theta - PI) / -angle_scale + PI
            } else {
                theta
            }
        }
        AngleScaleFormula::Legacy => {
            if angle_scale == 0.0 {
                theta
            } else {
                (theta - PI) / (1.0 + angle_scale) + PI
            }
        }
    }
}

/// The prepared map θ → θies: `(θ − c)·m + c` (or `(θ − c)/d + c`) with centre `c` = 0 for a
/// positive two-branch scale (θ/s) and π for the others ((θ − π)/d + π). The division of the
/// formulas is a multiplication by the reciprocal (within an ulp of the quotient) unless the
/// divisor is subnormal, whose reciprocal would overflow or lose precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum AngleMap {
    /// θies = θ.
    Identity,
    /// θies = (θ − c)·m + c.
    Scale { c: f64, m: f64 },
    /// θies = (θ − c)/d + c (subnormal d).
    Divide { c: f64, d: f64 },
}

impl AngleMap {
    pub(crate) fn new(s: f64, formula: AngleScaleFormula) -> Result<AngleMap, ShapingError> {
        if !s.is_finite() {
            return Err(ShapingError::InvalidParameter {
                attribute: "inputs:shaping:ies:angleScale",
                value: s.to_string(),
                expected: "a finite number",
            });
        }
        // (centre, divisor)
        let (c, d) = match formula {
            AngleScaleFormula::TwoBranch => {
                if s == 0.0 || s == 1.0 {
                    return Ok(AngleMap::Identity);
                } else if s > 0.0 {
                    (0.0, s)
                } else {
                    (PI, -s)
                }
            }
            AngleScaleFormula::Legacy => {
                let d = 1.0 + s;
                if s == 0.0 {
                    return Ok(AngleMap::Identity);
                } else if d == 0.0 {
                    return Err(ShapingError::InvalidParameter {
                        attribute: "inputs:shaping:ies:angleScale",
                        value: s.to_string(),
                        expected: "a finite number other than -1 (the legacy formula divides by 1 + angleScale)",
                    });
                } else {
                    (PI, d)
                }
            }
        };
        Ok(if d.is_normal() {
            AngleMap::Scale { c, m: 1.0 / d }
        } else {
            AngleMap::Divide { c, d }
        })
    }

    /// θies for the light's polar angle θ.
    #[inline(always)]
    pub(crate) fn apply(self, theta: f64) -> f64 {
        match self {
            AngleMap::Identity => theta,
            AngleMap::Scale { c, m } => (theta - c) * m + c,
            AngleMap::Divide { c, d } => (theta - c) / d + c,
        }
    }

    /// The θ that maps to `t` (affine inverse).
    pub(crate) fn inverse(self, t: f64) -> f64 {
        match self {
            AngleMap::Identity => t,
            AngleMap::Scale { c, m } => (t - c) / m + c,
            AngleMap::Divide { c, d } => (t - c) * d + c,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use AngleScaleFormula::{Legacy, TwoBranch};

    #[test]
    fn two_branch_and_legacy_values() {
        let d = |x: f64| x.to_radians();
        assert_eq!(apply_angle_scale(1.0, 0.0, TwoBranch), 1.0);
        assert_eq!(apply_angle_scale(1.0, 1.0, TwoBranch), 1.0);
        assert_eq!(apply_angle_scale(1.0, 0.5, TwoBranch), 2.0);
        assert!((apply_angle_scale(d(165.0), -0.5, TwoBranch) - d(150.0)).abs() < 1e-12);
        // legacy: (θ − π)/(1 + s) + π; s = 1 halves the distance from π
        assert!((apply_angle_scale(d(90.0), 1.0, Legacy) - d(135.0)).abs() < 1e-12);
        assert_eq!(apply_angle_scale(0.7, 0.0, Legacy), 0.7);
        assert!(apply_angle_scale(0.7, f64::NAN, TwoBranch).is_nan());
    }

    #[test]
    fn prepared_map_agrees_and_inverts() {
        for formula in [TwoBranch, Legacy] {
            for s in [-3.0, -1.5, -0.5, -1e-3, 0.0, 1e-3, 0.25, 1.0, 2.0] {
                let m = AngleMap::new(s, formula).unwrap();
                for k in 0..=20 {
                    let th = PI * k as f64 / 20.0;
                    let a = apply_angle_scale(th, s, formula);
                    let b = m.apply(th);
                    assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{s} {th}");
                    assert!((m.inverse(b) - th).abs() < 1e-9, "{s} {th}");
                }
            }
        }
        assert!(AngleMap::new(-1.0, Legacy).is_err());
        assert!(AngleMap::new(-1.0, TwoBranch).is_ok());
        assert!(AngleMap::new(f64::INFINITY, TwoBranch).is_err());
        assert!(AngleMap::new(f64::NAN, Legacy).is_err());
        assert_eq!(AngleMap::new(1.0, TwoBranch).unwrap(), AngleMap::Identity);
        // subnormal divisors keep the division
        let div = |c: f64, d: f64| AngleMap::Divide { c, d };
        assert_eq!(AngleMap::new(1e-310, TwoBranch).unwrap(), div(0.0, 1e-310));
        assert_eq!(AngleMap::new(-1e-310, TwoBranch).unwrap(), div(PI, 1e-310));
        let scale = |c: f64, m: f64| AngleMap::Scale { c, m };
        assert_eq!(AngleMap::new(0.5, TwoBranch).unwrap(), scale(0.0, 2.0));
        assert_eq!(AngleMap::new(1.0, Legacy).unwrap(), scale(PI, 0.5));
        assert_eq!(AngleMap::new(-4.0, TwoBranch).unwrap(), scale(PI, 0.25));
        let m = AngleMap::new(1e-310, TwoBranch).unwrap();
        assert_eq!(m.apply(1e-300), 1e-300 / 1e-310);
        assert_eq!(m.apply(0.0), 0.0);
    }
}
