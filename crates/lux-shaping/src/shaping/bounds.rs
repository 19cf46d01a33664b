//! Bounds of the shaping factor: its maximum (over every direction or a cone) and the
//! half-angle outside which it vanishes.

use super::*;

impl Shaping {
    /// The largest factor over every direction and channel: an upper bound of
    /// [`factor`](Self::factor), never below any value it returns.
    ///
    /// The product of per-term maxima, each over the directions the cone lets through: the focus
    /// colour's largest channel (1 when every tint channel is ≤ 1; a tint above 1 brightens off
    /// the axis, up to the tint where |cos θ| is smallest), the cone (1, or less for an hdEmbree
    /// softness > 1), and the IES profile's largest value (candela, or divided by the normalizer)
    /// over the vertical band the cone and angleScale map to. Exact without IES whenever the tint
    /// is ≤ 1 in every channel (all maxima are on the axis); 0 for a light that emits nothing.
    pub fn max_factor(&self) -> f64 {
        self.max_factor
    }

    /// An upper bound of [`factor`](Self::factor) over the directions within `half_angle`
    /// (radians) of `axis_light_space` (any length > 0): for light BVHs and samplers.
    ///
    /// Conservative: never below the factor of any direction in the cone. Built like
    /// [`max_factor`](Self::max_factor) from the range of polar angles the query cone spans:
    /// 0 when it lies entirely outside the shaping cone; the focus and IES maxima over that
    /// θ band only (IES: the vertical grid bands of the profile it maps to, type C). A zero or
    /// non-finite axis, a NaN half-angle, or a half-angle ≥ π gives `max_factor()`; a negative
    /// half-angle counts as 0 (the axis direction alone).
    pub fn max_factor_in_cone(&self, axis_light_space: DVec3, half_angle: f64) -> f64 {
        if self.identity {
            return 1.0;
        }
        let a = axis_light_space;
        if half_angle.is_nan() || half_angle >= PI || !a.is_finite() || a == DVec3::ZERO {
            return self.max_factor;
        }
        let h = half_angle.max(0.0);
        // polar angle of the axis from −Z, accurate near the poles
        let m = a.abs().max_element();
        let a = a / m;
        let alpha = (a.x * a.x + a.y * a.y).sqrt().atan2(-a.z);
        let lo = (alpha - h - BOUND_SLACK).max(0.0);
        let hi = (alpha + h + BOUND_SLACK).min(PI);
        self.bound(lo, hi).min(self.max_factor)
    }

    /// The half-angle θe (radians, in [0, π]) of the cone about the light's −Z outside which the
    /// factor is exactly 0: every direction more than θe off the axis gets `[0, 0, 0]`. For
    /// light BVHs (the emission spread θe of Conty Estevez & Kulla 2018) and samplers.
    ///
    /// Conservative, from the same bounds as [`max_factor_in_cone`](Self::max_factor_in_cone):
    /// the smallest θ with a zero bound over the polar band `[θ, π]`, found by bisection to
    /// 2⁻⁴⁰ rad, plus the bounds' angular slack. It reflects the cone angle
    /// (`inputs:shaping:cone:angle`) and the polar range where the IES profile
    /// (`inputs:shaping:ies:file` after `ies:angleScale`) is non-zero, whichever is narrower;
    /// π for the identity and for any shaping that emits towards +Z; 0 for one that emits
    /// nothing.
    pub fn emission_half_angle(&self) -> f64 {
        self.emission_half_angle
    }

    /// See [`emission_half_angle`](Self::emission_half_angle): bisection on the monotone
    /// predicate "bound over [θ, π] is zero" (the band shrinks as θ grows).
    pub(super) fn reach(&self) -> f64 {
        if self.identity || self.bound(PI, PI) > 0.0 {
            return PI;
        }
        if !(self.bound(0.0, PI) > 0.0) {
            return 0.0;
        }
        let (mut lit, mut dark) = (0.0, PI);
        for _ in 0..40 {
            let mid = 0.5 * (lit + dark);
            if self.bound(mid, PI) > 0.0 {
                lit = mid;
            } else {
                dark = mid;
            }
        }
        (dark + BOUND_SLACK).min(PI)
    }

    /// Upper bound (f64) of every channel of the factor over polar angles `[lo, hi]`.
    pub(super) fn bound(&self, lo: f64, hi: f64) -> f64 {
        let cone = self.cone.at_theta(lo);
        if !(cone > 0.0) {
            return 0.0;
        }
        // `factor` tests the cone on the cosine, which takes directions up to ~1.5·10⁻⁸ rad
        // past the cut as inside: the band reaches that far too (what the IES profile gives
        // there can be anything under a large angle scale).
        let hi = hi.min(self.cone.reach() + BOUND_SLACK).max(lo);
        // A full cone (1) and tint channels ≤ 1 are exactly representable and never exceeded
        // (lerp(f, t, 1) ≤ 1, cone ≤ 1); otherwise leave room for rounding: of the
        // interpolation and the products, and of a soft edge's value, which `factor` computes
        // from the direction's cosine and the bound from the angle (they differ in the last
        // bits; found by the `max_factor_in_cone_is_conservative` proptest).
        const SLACK: f64 = 1.0 + 1e-12;
        let cone = if cone < 1.0 { cone * SLACK } else { cone };
        let focus = self.focus.map_or(1.0, |f| {
            let m = f.max_over(lo, hi);
            if m > 1.0 { m * SLACK } else { m }
        });
        let ies = self.ies.as_ref().map_or(1.0, |p| {
            let cd = p.bound_theta_range(lo, hi);
            p.scale.apply(cd) * SLACK
        });
        let b = cone * focus * ies;
        if b.is_nan() { f64::INFINITY } else { b }
    }
}
