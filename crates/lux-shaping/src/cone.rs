//! `inputs:shaping:cone:angle` and `inputs:shaping:cone:softness`, prepared.

use core::f64::consts::{FRAC_PI_2, PI};
use lux_math::{Profile, lerp, smooth_step_fraction};

/// The prepared cone. θ is the angle off the light's −Z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Cone {
    /// Never cuts (no `ShapingAPI`, or a cone of ≥ 180° whose ramp never reaches θ ≤ π).
    Open,
    /// Emits nothing.
    Closed,
    /// Softness 0: 1 for θ ≤ cut (inclusive, as the schema text says), 0 beyond.
    Hard { cut: f64, cos_cut: f64 },
    /// 0 beyond `cut`; 1 up to `start`; `1 − smoothStep(θ, start, cut)` between. `cos_cut` is
    /// −∞ when cut ≥ π; `cos_start` is +∞ when start < 0 (hdEmbree softness > 1).
    Soft {
        start: f64,
        cut: f64,
        cos_start: f64,
        cos_cut: f64,
        /// 1/(cut − start) (finite: start < cut), so the ramp needs no division.
        inv_width: f64,
    },
}

impl Cone {
    /// `angle_deg` must not be NaN (the caller rejects it).
    pub(crate) fn new(angle_deg: f64, softness: f64, profile: Profile) -> Cone {
        if angle_deg == f64::INFINITY {
            return Cone::Open;
        }
        if angle_deg < 0.0 {
            return Cone::Closed;
        }
        let cut = angle_deg.to_radians();
        let s = if softness.is_nan() { 0.0 } else { softness };
        let s = match profile {
            Profile::Spec => s.clamp(0.0, 1.0),
            Profile::HdEmbree => s,
        };
        if !s.is_finite() {
            // hdEmbree, softness ±∞: the limit of the formula is 0 everywhere
            return Cone::Closed;
        }
        let start = lerp(s, cut, 0.0);
        if start == cut {
            return if cut >= PI {
                Cone::Open
            } else {
                Cone::Hard {
                    cut,
                    cos_cut: cos_of(cut),
                }
            };
        }
        if start > cut {
            // hdEmbree, softness < 0: the smoothstep runs backwards and is 1 on the whole cone
            return Cone::Closed;
        }
        if start >= PI {
            return Cone::Open;
        }
        Cone::Soft {
            start,
            cut,
            inv_width: 1.0 / (cut - start),
            cos_start: if start < 0.0 {
                f64::INFINITY
            } else {
                cos_of(start)
            },
            cos_cut: if cut >= PI {
                f64::NEG_INFINITY
            } else {
                cos_of(cut)
            },
        }
    }

    /// Where the direction with `w = −z` (cos θ·|d|) and `len2 = |d|²` falls: the cosines are
    /// compared on squares, so no square root or division is taken.
    #[inline(always)]
    pub(crate) fn hit(&self, w: f64, len2: f64) -> ConeHit {
        match *self {
            Cone::Open => ConeHit::Full,
            Cone::Closed => ConeHit::Dark,
            Cone::Hard { cos_cut, .. } => {
                if cos_below(w, len2, cos_cut) {
                    ConeHit::Dark
                } else {
                    ConeHit::Full
                }
            }
            Cone::Soft {
                start,
                cos_start,
                cos_cut,
                inv_width,
                ..
            } => {
                if cos_below(w, len2, cos_cut) {
                    ConeHit::Dark
                } else if !cos_below(w, len2, cos_start) {
                    ConeHit::Full
                } else {
                    ConeHit::Ramp { start, inv_width }
                }
            }
        }
    }

    /// The factor at polar angle θ (used by the integrals and bounds): the soft ramp
    /// `1 − smoothStep(θ, start, cut)` computed as a direction's factor computes it, with the
    /// prepared `1/(cut − start)` ([`ConeHit::factor`]) — near the cut `1 − smoothStep`
    /// cancels, and a quotient an ulp away from that product would put a bound below the
    /// factor by more than the bounds' relative slack.
    pub(crate) fn at_theta(&self, theta: f64) -> f64 {
        match *self {
            Cone::Open => 1.0,
            Cone::Closed => 0.0,
            Cone::Hard { cut, .. } => {
                if theta <= cut {
                    1.0
                } else {
                    0.0
                }
            }
            Cone::Soft {
                start,
                cut,
                inv_width,
                ..
            } => {
                if theta > cut {
                    0.0
                } else {
                    ConeHit::Ramp { start, inv_width }.factor(|| theta)
                }
            }
        }
    }

    /// The largest θ at which the factor can be non-zero (π when open, −1 when closed).
    pub(crate) fn reach(&self) -> f64 {
        match *self {
            Cone::Open => PI,
            Cone::Closed => -1.0,
            Cone::Hard { cut, .. } | Cone::Soft { cut, .. } => cut.min(PI),
        }
    }

    /// Angles in (0, π) where the factor has a kink or a jump.
    pub(crate) fn kinks(&self) -> [f64; 2] {
        match *self {
            Cone::Open | Cone::Closed => [f64::NAN; 2],
            Cone::Hard { cut, .. } => [cut, f64::NAN],
            Cone::Soft { start, cut, .. } => [start, cut],
        }
    }
}

/// What the cone does to one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ConeHit {
    /// Factor 0.
    Dark,
    /// Factor 1.
    Full,
    /// Factor `1 − smoothStep(θ, start, cut)`, with `inv_width` = 1/(cut − start).
    Ramp { start: f64, inv_width: f64 },
}

impl ConeHit {
    /// The factor, given the polar angle θ (only used on the ramp).
    #[inline(always)]
    pub(crate) fn factor(self, theta: impl FnOnce() -> f64) -> f64 {
        match self {
            ConeHit::Dark => 0.0,
            ConeHit::Full => 1.0,
            // smoothStep(θ, start, cut) with the division by cut − start prepared
            ConeHit::Ramp { start, inv_width } => {
                1.0 - smooth_step_fraction((theta() - start) * inv_width)
            }
        }
    }
}

/// `w/√len2 < k` (cos θ below the cosine `k`) without the square root; `k` may be ±∞.
#[inline(always)]
pub(crate) fn cos_below(w: f64, len2: f64, k: f64) -> bool {
    if k > 0.0 {
        w < 0.0 || w * w < k * k * len2
    } else {
        w < 0.0 && w * w > k * k * len2
    }
}

/// cos of an angle in \[0, π\], with cos(FRAC_PI_2) = 0 exactly: `radians(90)` in f64 is
/// 6·10⁻¹⁷ below π/2, so plain `cos` would put the equator (`acos(0) == FRAC_PI_2`) outside a
/// 90° cone, against the schema's inclusive edge.
fn cos_of(a: f64) -> f64 {
    if a == FRAC_PI_2 { 0.0 } else { a.cos() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prepared_variants() {
        let sp = Profile::Spec;
        let hd = Profile::HdEmbree;
        assert_eq!(Cone::new(180.0, 0.0, sp), Cone::Open);
        assert_eq!(Cone::new(f64::INFINITY, 0.5, sp), Cone::Open);
        assert_eq!(Cone::new(-1.0, 0.0, sp), Cone::Closed);
        assert_eq!(Cone::new(f64::NEG_INFINITY, 0.0, sp), Cone::Closed);
        assert!(matches!(Cone::new(90.0, 0.0, sp), Cone::Hard { .. }));
        assert!(matches!(Cone::new(90.0, f64::NAN, hd), Cone::Hard { .. }));
        assert!(matches!(Cone::new(90.0, -3.0, sp), Cone::Hard { .. }));
        assert_eq!(Cone::new(90.0, -0.5, hd), Cone::Closed);
        assert_eq!(Cone::new(90.0, f64::INFINITY, hd), Cone::Closed);
        assert!(matches!(Cone::new(90.0, 5.0, sp), Cone::Soft { start, .. } if start == 0.0));
        assert!(
            matches!(Cone::new(90.0, 1.5, hd), Cone::Soft { start, cos_start, .. }
            if start < 0.0 && cos_start == f64::INFINITY)
        );
        // a 300° cone with softness 0.1 starts its ramp at 270°: never reached
        assert_eq!(Cone::new(300.0, 0.1, sp), Cone::Open);
        // a 200° cone with softness 0.5 ramps from 100°, never cuts
        assert!(
            matches!(Cone::new(200.0, 0.5, sp), Cone::Soft { cos_cut, .. } if cos_cut == f64::NEG_INFINITY)
        );
    }

    #[test]
    fn cos_and_theta_paths_agree() {
        for (a, s, p) in [
            (45.0, 0.3, Profile::Spec),
            (120.0, 1.0, Profile::Spec),
            (200.0, 0.5, Profile::Spec),
            (60.0, 1.7, Profile::HdEmbree),
            (30.0, 0.0, Profile::Spec),
        ] {
            let c = Cone::new(a, s, p);
            for k in 0..=1000 {
                let th = PI * k as f64 / 1000.0;
                // stay away from the exact edge of a hard cone
                if let Cone::Hard { cut, .. } = c
                    && (th - cut).abs() < 1e-9
                {
                    continue;
                }
                for len in [1.0, 1e-3, 7.5e4] {
                    let v = c.hit(th.cos() * len, len * len).factor(|| th);
                    assert!((v - c.at_theta(th)).abs() < 1e-7, "{a} {s} {th}");
                }
            }
        }
    }
}
