//! Derived photometry: beam (50 %) and field (10 %) angles in the principal plane pairs.

use crate::web::PhotometricWeb;
use core::f64::consts::PI;

/// Full angles (radians) within which the intensity stays at or above a fraction of the plane
/// pair's peak, in the C0–C180 and C90–C270 plane pairs. `None` when the intensity never drops
/// below the fraction on one side within the pair (or the plane pair is dark).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpreadAngles {
    /// In the plane pair φ = 0 / φ = π (C0–C180), radians.
    pub c0_c180: Option<f64>,
    /// In the plane pair φ = π/2 / φ = 3π/2 (C90–C270), radians.
    pub c90_c270: Option<f64>,
}

/// Sampling step of [`spread_angle`] before refinement (degrees).
const STEP_DEG: f64 = 0.05;

/// The full angle (radians) around the peak of the plane pair (φ, φ + π) over which the bilinear
/// intensity stays ≥ `fraction` × that pair's peak. The pair is walked as one curve
/// γ ∈ [−π, π] (γ ≥ 0: plane φ at θ = γ; γ < 0: plane φ + π at θ = −γ), sampled every 0.05° and
/// each crossing refined by bisection to 1e-9 rad. Beam angle: `fraction = 0.5`; field: `0.1`.
pub fn spread_angle(web: &PhotometricWeb, phi: f64, fraction: f64) -> Option<f64> {
    if !(fraction > 0.0 && fraction < 1.0) {
        return None;
    }
    let f = |g: f64| {
        if g >= 0.0 {
            web.intensity(g.min(PI - 1e-12), phi)
        } else {
            web.intensity((-g).min(PI - 1e-12), phi + PI)
        }
    };
    let n = (360.0 / STEP_DEG) as usize;
    let step = 2.0 * PI / n as f64;
    let g = |k: usize| -PI + k as f64 * step;
    let (mut kmax, mut peak) = (0, 0.0);
    for k in 0..=n {
        let val = f(g(k));
        if val > peak {
            peak = val;
            kmax = k;
        }
    }
    if peak <= 0.0 {
        return None;
    }
    let level = fraction * peak;
    let refine = |mut inside: f64, mut outside: f64| {
        for _ in 0..60 {
            let m = 0.5 * (inside + outside);
            if f(m) >= level {
                inside = m;
            } else {
                outside = m;
            }
            if (inside - outside).abs() < 1e-9 {
                break;
            }
        }
        0.5 * (inside + outside)
    };
    let mut right = None;
    for k in kmax + 1..=n {
        if f(g(k)) < level {
            right = Some(refine(g(k - 1), g(k)));
            break;
        }
    }
    let mut left = None;
    for k in (0..kmax).rev() {
        if f(g(k)) < level {
            left = Some(refine(g(k + 1), g(k)));
            break;
        }
    }
    Some(right? - left?)
}

impl PhotometricWeb {
    /// Beam angles (50 % of the peak) in the two principal plane pairs.
    pub fn beam_angles(&self) -> SpreadAngles {
        self.spread(0.5)
    }

    /// Field angles (10 % of the peak) in the two principal plane pairs.
    pub fn field_angles(&self) -> SpreadAngles {
        self.spread(0.1)
    }

    fn spread(&self, fraction: f64) -> SpreadAngles {
        SpreadAngles {
            c0_c180: spread_angle(self, 0.0, fraction),
            c90_c270: spread_angle(self, 0.5 * PI, fraction),
        }
    }
}
