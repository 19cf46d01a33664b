//! The prepared shaping of one light: evaluation, bounds and integrals.

use crate::angle::AngleMap;
use crate::cone::{Cone, ConeHit};
use crate::error::ShapingError;
use crate::ies::IesPart;
use crate::params::{ShapingOptions, ShapingParams};
use crate::quad;
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use glam::DVec3;
use lux_ies::PhotometricWeb;
use lux_math::{lerp, polar_angle, polar_angles};

/// Relative accuracy requested from the outer (θ) quadrature.
const REL_OUTER: f64 = 1e-10;
/// Relative accuracy requested from the inner (φ) quadrature.
const REL_INNER: f64 = 1e-11;
const MAX_PANELS_OUTER: usize = 20_000;
const MAX_PANELS_INNER: usize = 4_000;
/// Angular slack (radians) added to the θ range of a bound, larger than the error of
/// `acos` near the poles (√(2·2⁻⁵³) ≈ 1.5·10⁻⁸).
const BOUND_SLACK: f64 = 1e-7;

/// `inputs:shaping:focus` / `focusTint`, when active.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Focus {
    exponent: f64,
    tint: [f64; 3],
    pow: Pow,
}

/// `q^n` for 0 ≤ n ≤ 32 by repeated squaring, inlined (`f64::powi` with a run-time exponent
/// is a library call); the common focus exponents 0–4 (n ≤ 2) take at most one multiplication.
#[inline(always)]
fn powi(q: f64, n: i32) -> f64 {
    match n {
        0 => 1.0,
        1 => q,
        2 => q * q,
        _ => {
            let (mut base, mut e, mut acc) = (q, n as u32, 1.0);
            while e > 0 {
                if e & 1 == 1 {
                    acc *= base;
                }
                base *= base;
                e >>= 1;
            }
            acc
        }
    }
}

/// How `|cos θ|^focus` is computed from `cos² θ`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pow {
    /// focus = 2n: `(cos²)^n` by multiplications.
    Even(i32),
    /// focus = 2n + 1: `sqrt(cos²) · (cos²)^n`.
    Odd(i32),
    /// `(cos²)^(focus/2)`.
    General(f64),
}

impl Focus {
    fn new(exponent: f64, tint: [f64; 3]) -> Focus {
        let pow = if exponent.fract() == 0.0 && exponent <= 64.0 {
            let n = exponent as i32;
            if n % 2 == 0 {
                Pow::Even(n / 2)
            } else {
                Pow::Odd(n / 2)
            }
        } else {
            Pow::General(0.5 * exponent)
        };
        Focus {
            exponent,
            tint,
            pow,
        }
    }

    /// The focus factor `|cos θ|^focus` from `q = cos² θ`.
    #[inline(always)]
    fn of_cos2(&self, q: f64) -> f64 {
        match self.pow {
            Pow::Even(n) => powi(q, n),
            Pow::Odd(n) => q.sqrt() * powi(q, n),
            Pow::General(h) => q.powf(h),
        }
    }

    /// `focusColor = lerp(|cos θ|^focus, focusTint, white)` per channel, from `q = cos² θ`.
    #[inline(always)]
    fn color_cos2(&self, q: f64) -> [f64; 3] {
        let f = self.of_cos2(q);
        self.tint.map(|t| lerp(f, t, 1.0))
    }

    /// [`color_cos2`](Self::color_cos2) from cos θ.
    #[inline(always)]
    fn color(&self, cos_theta: f64) -> [f64; 3] {
        self.color_cos2(cos_theta * cos_theta)
    }

    /// Upper bound of the largest channel over polar angles `[lo, hi]`.
    fn max_over(&self, lo: f64, hi: f64) -> f64 {
        let (a, b) = (lo.cos().abs(), hi.cos().abs());
        let cmax = a.max(b);
        let cmin = if lo <= FRAC_PI_2 && hi >= FRAC_PI_2 {
            0.0
        } else {
            a.min(b)
        };
        let fmax = self.of_cos2(cmax * cmax);
        let fmin = self.of_cos2(cmin * cmin);
        self.tint
            .iter()
            .map(|&t| {
                if t <= 1.0 {
                    lerp(fmax, t, 1.0)
                } else {
                    lerp(fmin, t, 1.0)
                }
            })
            .fold(0.0, f64::max)
    }
}

/// The `ShapingAPI` of one light, prepared for evaluation: the RGB multiplier that focus,
/// focusTint, the cone and an IES profile apply to the light's emission in a given direction,
/// with bounds and integrals of it.
///
/// Immutable after construction; `Clone + Debug + Send + Sync`. Directions are in the light's
/// local space, pointing **from the light towards the receiver** (the schema's
/// `emissionDirection`); the light's axis is its local −Z.
///
/// The factor, for a direction at angle θ off −Z and IES azimuth φ
/// ([`lux_math::light_polar`]), is the product, in this order, of
/// 1. the focus colour `lerp(|cos θ|^focus, focusTint, white)` when `focus` > 0
///    (`inputs:shaping:focus`, `inputs:shaping:focusTint`),
/// 2. the cone `θ > θcut ? 0 : 1 − smoothStep(θ, lerp(softness, θcut, 0), θcut)`
///    (`inputs:shaping:cone:angle`, `inputs:shaping:cone:softness`),
/// 3. the IES sample `I(applyAngleScale(θ), φ)` in candela, divided by the profile's mean
///    intensity when `ies:normalize` is on (`inputs:shaping:ies:file`, `…:angleScale`,
///    `…:normalize`).
#[derive(Clone, Debug)]
pub struct Shaping {
    params: ShapingParams,
    options: ShapingOptions,
    focus: Option<Focus>,
    cone: Cone,
    ies: Option<IesPart>,
    max_factor: f32,
    emission_half_angle: f64,
    identity: bool,
}

impl Default for Shaping {
    /// [`Shaping::identity`].
    fn default() -> Self {
        Shaping::identity()
    }
}

impl Shaping {
    /// The shaping of a light **without** `ShapingAPI`: no focus, no cone, no IES profile; the
    /// factor is 1 in every direction. [`params`](Self::params) reports
    /// [`ShapingParams::NO_SHAPING`].
    pub fn identity() -> Shaping {
        Shaping {
            params: ShapingParams::NO_SHAPING,
            options: ShapingOptions::default(),
            focus: None,
            cone: Cone::Open,
            ies: None,
            max_factor: 1.0,
            emission_half_angle: PI,
            identity: true,
        }
    }

    /// Prepares the shaping of a light with `ShapingAPI` applied, from its authored inputs and,
    /// when `inputs:shaping:ies:file` is set, the profile expanded into a
    /// [`PhotometricWeb`]. The web's candela scale is the one chosen when it was built (build
    /// it with the same [`lux_math::Profile`] as `options.profile`).
    ///
    /// Never panics. Every input value has a documented result; the only errors are values no
    /// formula gives a meaning to. Inputs that have no effect (focusTint while focus ≤ 0,
    /// angleScale without a profile) are not checked.
    ///
    /// | input | value | behaviour |
    /// |---|---|---|
    /// | `focus` | ≤ 0 or NaN | ignored (the schema: "values < 0 are ignored"; 0 is the identity) |
    /// | `focus` | +∞ | the limit: focus factor 1 exactly on the ±Z axis, 0 elsewhere (so the tint) |
    /// | `focusTint` | NaN or ±∞ component (with focus > 0) | [`ShapingError::InvalidParameter`] |
    /// | `focusTint` | negative component | treated as 0 |
    /// | `focusTint` | white (1, 1, 1) | focus disabled (exactly the identity) |
    /// | `cone:angle` | NaN | [`ShapingError::InvalidParameter`] |
    /// | `cone:angle` | < 0 or −∞ | nothing is emitted (θ ≥ 0 > θcut everywhere) |
    /// | `cone:angle` | ≥ 180° with softness 0, or +∞ | no cut-off at all |
    /// | `cone:angle` | > 180° with softness > 0 | as authored: θcut > π never cuts, but the ramp from `(1 − softness)·θcut` may still dim the back |
    /// | `cone:softness` | NaN | 0 |
    /// | `cone:softness` | outside \[0, 1\], [`Profile::Spec`](lux_math::Profile::Spec) | clamped to \[0, 1\], as the schema says |
    /// | `cone:softness` | outside \[0, 1\], [`Profile::HdEmbree`](lux_math::Profile::HdEmbree) | used as authored, like the reference: > 1 moves the ramp start below 0, dimming even the axis to `1 − smoothStep(0, (1−s)θcut, θcut)`; < 0 reverses the ramp, which then makes the whole cone dark; ±∞ (whose formula gives NaN) is taken as its limit, dark |
    /// | `ies:angleScale` | NaN or ±∞ (with a profile) | [`ShapingError::InvalidParameter`] |
    /// | `ies:angleScale` | −1 with [`AngleScaleFormula::Legacy`](crate::AngleScaleFormula::Legacy) | [`ShapingError::InvalidParameter`] (division by 1 + s = 0) |
    /// | `ies:normalize` | profile with zero flux | the IES factor is 0 (not NaN) |
    ///
    /// With softness 0 the cone is inclusive: a direction exactly at θcut is lit (the schema:
    /// "unaltered if emissionOffAxisAngle <= coneAngle").
    pub fn new(
        params: &ShapingParams,
        ies: Option<PhotometricWeb>,
        options: ShapingOptions,
    ) -> Result<Shaping, ShapingError> {
        if params.cone_angle_deg.is_nan() {
            return Err(ShapingError::InvalidParameter {
                attribute: "inputs:shaping:cone:angle",
                value: params.cone_angle_deg.to_string(),
                expected: "an angle in degrees (not NaN)",
            });
        }
        let focus_on = params.focus > 0.0;
        if focus_on && params.focus_tint.iter().any(|t| !t.is_finite()) {
            let [r, g, b] = params.focus_tint;
            return Err(ShapingError::InvalidParameter {
                attribute: "inputs:shaping:focusTint",
                value: format!("({r}, {g}, {b})"),
                expected: "finite colour components",
            });
        }
        let tint = params.focus_tint.map(|t| t.max(0.0));
        let focus = (focus_on && tint != [1.0; 3]).then(|| Focus::new(params.focus, tint));
        let cone = Cone::new(params.cone_angle_deg, params.cone_softness, options.profile);
        let ies = match ies {
            None => None,
            Some(web) => {
                let map = AngleMap::new(params.ies_angle_scale, options.angle_scale)?;
                Some(IesPart::new(
                    web,
                    options.interpolation,
                    map,
                    params.ies_normalize,
                    options.profile,
                ))
            }
        };
        let identity = focus.is_none() && cone == Cone::Open && ies.is_none();
        let mut s = Shaping {
            params: *params,
            options,
            focus,
            cone,
            ies,
            max_factor: 1.0,
            emission_half_angle: PI,
            identity,
        };
        s.max_factor = f32_up(s.bound(0.0, PI));
        s.emission_half_angle = s.reach();
        Ok(s)
    }

    /// The RGB multiplier the shaping applies to the emission towards `dir_light_space` (from
    /// the light towards the receiver, in the light's local space, any length > 0).
    ///
    /// Focus colour × cone × IES factor as described on [`Shaping`]. A zero, NaN or infinite
    /// direction gives `[0, 0, 0]`; the result is never NaN, never negative and never infinite
    /// (values beyond `f32::MAX` saturate). Allocation-free; the cone is tested on the cosine
    /// (no square root or angle unless the direction is inside a soft ramp or an IES profile is
    /// looked up), an integer focus uses multiplications only, the azimuth is computed only for
    /// IES profiles that depend on it, and the angles are those of [`lux_math::light_polar`]
    /// (θ = atan2(√(x² + y²), −z), φ the IES azimuth). A type C
    /// profile with evenly spaced angles and bilinear interpolation is looked up on a copy of
    /// its table with the `ies:normalize` divisor folded in, the cell found by arithmetic
    /// (`u = θies/Δv`, `⌊u⌋`, `u − ⌊u⌋`); the value is the same bilinear interpolant as
    /// [`PhotometricWeb::intensity`] times the scale, to within `4ε·(nv + nh + 2)` of the
    /// largest value (the rounding of `θies/Δv` and of the web's radian knots).
    #[inline]
    pub fn factor(&self, dir_light_space: DVec3) -> [f32; 3] {
        let mut d = dir_light_space;
        let mut len2 = d.length_squared();
        if !(len2 > 1e-280 && len2 < 1e280) {
            match rescale(d) {
                Some(r) => {
                    d = r;
                    len2 = d.length_squared();
                }
                None => return [0.0; 3],
            }
        }
        if self.identity {
            return [1.0; 3];
        }
        match &self.ies {
            None => self.factor_no_ies(d, len2),
            Some(ies) => self.factor_ies(d, len2, ies),
        }
    }

    /// Focus and cone only. The cone tests compare `cos θ = −z/|d|` with the precomputed
    /// cosines on squares, so no square root is taken outside the soft ramp; the focus uses
    /// `cos² θ = z²/|d|²`.
    #[inline(always)]
    fn factor_no_ies(&self, d: DVec3, len2: f64) -> [f32; 3] {
        let w = -d.z;
        let cone = self.cone.hit(w, len2).factor(|| polar_angle(d));
        if cone == 0.0 {
            return [0.0; 3];
        }
        match &self.focus {
            None => [to_f32(cone); 3],
            Some(f) => f.color_cos2(w * w / len2).map(|x| to_f32(x * cone)),
        }
    }

    /// With an IES profile: θ = atan2(√(x² + y²), −z) and φ as [`lux_math::light_polar`]
    /// (φ is not computed for an axially symmetric type C profile),
    /// the cone tested on the cosine as without IES, the profile looked up on its even grid
    /// when it has one (see `IesPart::sample_for_factor`).
    #[inline(always)]
    fn factor_ies(&self, d: DVec3, len2: f64, ies: &IesPart) -> [f32; 3] {
        let w = -d.z;
        let hit = self.cone.hit(w, len2);
        if hit == ConeHit::Dark {
            return [0.0; 3];
        }
        let (theta, phi) = if ies.axial_c {
            (polar_angle(d), 0.0)
        } else {
            polar_angles(d)
        };
        let cone = hit.factor(|| theta);
        let s = cone * ies.sample_for_factor(theta, phi);
        match &self.focus {
            None => [to_f32(s); 3],
            Some(f) => f.color_cos2(w * w / len2).map(|x| to_f32(x * s)),
        }
    }

    /// The factor at light-space polar angles (θ, φ), in f64 (tests).
    #[cfg(test)]
    fn eval_polar(&self, theta: f64, phi: f64) -> [f64; 3] {
        let r = self.radial(theta);
        match &self.ies {
            None => r,
            Some(ies) => {
                let i = ies.sample(theta, phi);
                r.map(|x| x * i)
            }
        }
    }

    /// Focus colour × cone at polar angle θ.
    #[inline]
    fn radial(&self, theta: f64) -> [f64; 3] {
        let cone = self.cone.at_theta(theta);
        if cone == 0.0 {
            return [0.0; 3];
        }
        match &self.focus {
            None => [cone; 3],
            Some(f) => f.color(theta.cos()).map(|x| x * cone),
        }
    }

    /// The largest factor over every direction and channel: an upper bound of
    /// [`factor`](Self::factor), never below any value it returns.
    ///
    /// The product of per-term maxima, each over the directions the cone lets through: the focus
    /// colour's largest channel (1 when every tint channel is ≤ 1; a tint above 1 brightens off
    /// the axis, up to the tint where |cos θ| is smallest), the cone (1, or less for an hdEmbree
    /// softness > 1), and the IES profile's largest value (candela, or divided by the normalizer)
    /// over the vertical band the cone and angleScale map to. Exact without IES whenever the tint
    /// is ≤ 1 in every channel (all maxima are on the axis); 0 for a light that emits nothing.
    pub fn max_factor(&self) -> f32 {
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
    pub fn max_factor_in_cone(&self, axis_light_space: DVec3, half_angle: f64) -> f32 {
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
        f32_up(self.bound(lo, hi)).min(self.max_factor)
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
    fn reach(&self) -> f64 {
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
    fn bound(&self, lo: f64, hi: f64) -> f64 {
        let cone = self.cone.at_theta(lo);
        if !(cone > 0.0) {
            return 0.0;
        }
        let hi = hi.min(self.cone.reach()).max(lo);
        // Without IES and with every tint channel ≤ 1 the bound is exactly representable and
        // never exceeded (lerp(f, t, 1) ≤ 1, cone ≤ 1); otherwise leave room for the rounding
        // of the interpolation and of the products.
        const SLACK: f64 = 1.0 + 1e-12;
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

    /// `∫_{S²} factor(ω) dω` per channel (steradians; 4π for the identity).
    ///
    /// Computed in θ (polar angle from −Z) as `∫_0^π Φ(θ) sin θ dθ`, `Φ(θ)` being the integral
    /// over φ:
    /// - without IES, `Φ = 2π × focus colour × cone`;
    /// - type C, bilinear: `Φ` is exact, because the bilinear interpolant integrates exactly in
    ///   φ by the trapezoid rule on the profile's own horizontal angles; `Φ` is then the
    ///   φ-integrated profile, piecewise linear in θies;
    /// - type C, bicubic: φ by adaptive Gauss–Kronrod between the horizontal angles;
    /// - types A/B without angleScale: in their own coordinates (`dω = cos V dV dH`), split at
    ///   their grid lines and where the cone edges cross them (closed form);
    /// - types A/B with an angleScale: in (θ, φ), each θ-slice split where it crosses the
    ///   native grid lines (closed form). The slowest case: ~1–2 s for a 45 × 45 grid.
    ///
    /// The θ integral is adaptive Gauss–Kronrod (7/15) split at every kink: the cone edge and
    /// ramp start, π/2, the profile's vertical angles mapped back through angleScale (types A/B:
    /// where θ-circles touch the native grid lines), and, for a focus exponent above 4, at
    /// multiples of 1/√focus near the poles. Requested relative accuracy 10⁻¹⁰; the tests check
    /// 10⁻⁹ against closed forms and exact fluxes.
    pub fn integral_sphere(&self) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &|_| 1.0);
        }
        self.integrate_theta(PI, |t| t.sin())
    }

    /// `∫ factor(ω) cos θ dω` over the emitting hemisphere θ < π/2 (θ off the light's −Z), per
    /// channel: what a flat emitter (rect, disk) radiates relative to an unshaped one, whose value
    /// is π. Same method as [`integral_sphere`](Self::integral_sphere).
    pub fn integral_cos_hemisphere(&self) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &|d| (-d.z).max(0.0));
        }
        self.integrate_theta(FRAC_PI_2, |t| {
            let (s, c) = t.sin_cos();
            s * c
        })
    }

    /// `∫_{S²} factor(ω) · w(ω) dω` per channel, for any weight `w` of the unit light-space
    /// direction ω (e.g. the projected area of a sphere or cylinder emitter towards ω).
    ///
    /// Iterated adaptive Gauss–Kronrod: θ split as in
    /// [`integral_sphere`](Self::integral_sphere), φ split at multiples of π/8 and where the
    /// slice crosses the profile's grid lines (type C: its horizontal angles; types A/B: the
    /// crossings of the θies-circle with the native V and H lines, in closed form; types A/B
    /// without angleScale are integrated in (V, H) as for `integral_sphere`). `w` should be
    /// finite and piecewise smooth: its own kinks are found by bisection only, so their accuracy
    /// depends on the panel budget. Non-finite values of `w` count as 0.
    pub fn integral_weighted(&self, w: impl Fn(DVec3) -> f64) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &w);
        }
        let breaks = self.theta_breaks(PI);
        quad::integrate(
            |theta| {
                let r = self.radial(theta);
                if r == [0.0; 3] {
                    return [0.0; 3];
                }
                let st = theta.sin();
                let phi_breaks = self.phi_breaks(theta);
                let inner = quad::integrate(
                    |phi| {
                        let d = lux_math::light_direction(theta, phi);
                        let i = self.ies.as_ref().map_or(1.0, |p| p.sample(theta, phi));
                        [i * w(d)]
                    },
                    &phi_breaks,
                    REL_INNER,
                    MAX_PANELS_INNER,
                )[0];
                r.map(|x| x * inner * st)
            },
            &breaks,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    /// The IES part when it is of type A/B with angleScale the identity: such profiles are
    /// integrated in their own (V, H) coordinates, where their grid is aligned.
    fn native_ab(&self) -> Option<&IesPart> {
        self.ies
            .as_ref()
            .filter(|p| !p.type_c && p.map == AngleMap::Identity)
    }

    /// Focus colour × cone for cos θ = `c`.
    fn radial_cos(&self, c: f64) -> [f64; 3] {
        let cone = self.cone.at_theta(c.acos());
        if cone == 0.0 {
            return [0.0; 3];
        }
        match &self.focus {
            None => [cone; 3],
            Some(f) => f.color(c).map(|x| x * cone),
        }
    }

    /// `∫ factor · w dω` for a type A/B profile without angle scale, in the profile's native
    /// coordinates: `dω = cos V dV dH` over its measured range (0 outside), V split at the
    /// grid's vertical angles and at ±κ for every cone kink κ < π/2 (where the curve
    /// `cos V cos H = cos κ` turns), H split at the grid's horizontal angles and at the
    /// crossings `H = ±acos(cos κ / cos V)`; near the axis also at the focus peak's scale.
    fn integrate_native(&self, p: &IesPart, w: &dyn Fn(DVec3) -> f64) -> [f64; 3] {
        let v = p.web.vertical_angles();
        let h = p.web.horizontal_angles();
        let type_b = p.web.photometric_type() == lux_ies::PhotometricType::B;
        let kinks: Vec<f64> = self
            .cone
            .kinks()
            .into_iter()
            .filter(|k| *k > 0.0 && *k < FRAC_PI_2)
            .collect();
        let mut peaks = Vec::new();
        if let Some(f) = &self.focus
            && f.exponent > 4.0
            && f.exponent.is_finite()
        {
            let mut x = 1.0 / f.exponent.sqrt();
            while x < FRAC_PI_2 {
                peaks.push(x);
                peaks.push(-x);
                x *= 4.0;
            }
        }
        let finish = |mut b: Vec<f64>, lo: f64, hi: f64| {
            b.retain(|x| x.is_finite() && *x >= lo && *x <= hi);
            b.sort_by(f64::total_cmp);
            b.dedup();
            b
        };
        let mut vb = v.to_vec();
        vb.push(0.0);
        vb.extend(kinks.iter().flat_map(|&k| [k, -k]));
        vb.extend_from_slice(&peaks);
        let vb = finish(vb, v[0], v[v.len() - 1]);
        let (h0, h1) = (h[0], h[h.len() - 1]);
        quad::integrate(
            |vv| {
                let (sv, cv) = vv.sin_cos();
                let mut hb = h.to_vec();
                hb.push(0.0);
                for &k in &kinks {
                    let a = k.cos() / cv;
                    if a.abs() <= 1.0 {
                        let x = a.acos();
                        hb.push(x);
                        hb.push(-x);
                    }
                }
                hb.extend_from_slice(&peaks);
                let hb = finish(hb, h0, h1);
                quad::integrate(
                    |hh| {
                        let (sh, ch) = hh.sin_cos();
                        let r = self.radial_cos((cv * ch).clamp(-1.0, 1.0));
                        if r == [0.0; 3] {
                            return [0.0; 3];
                        }
                        let d = if type_b {
                            DVec3::new(-cv * sh, sv, -cv * ch)
                        } else {
                            DVec3::new(sv, -cv * sh, -cv * ch)
                        };
                        let i = p.scale.apply(p.web.native(vv, hh, p.interp)) * w(d) * cv;
                        r.map(|x| x * i)
                    },
                    &hb,
                    REL_INNER,
                    MAX_PANELS_INNER,
                )
            },
            &vb,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    fn integrate_theta(&self, hi: f64, weight: impl Fn(f64) -> f64) -> [f64; 3] {
        if self.identity {
            // exact: 2π ∫ weight
            return quad::integrate(|t| [TAU * weight(t); 3], &[0.0, hi], REL_OUTER, 64);
        }
        let breaks = self.theta_breaks(hi);
        quad::integrate(
            |theta| {
                let r = self.radial(theta);
                if r == [0.0; 3] {
                    return [0.0; 3];
                }
                let p = self.phi_slice(theta) * weight(theta);
                r.map(|x| x * p)
            },
            &breaks,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    /// `∫_0^{2π} ies(θ, φ) dφ` (scaled); 2π without a profile.
    fn phi_slice(&self, theta: f64) -> f64 {
        let Some(p) = &self.ies else {
            return TAU;
        };
        if p.phi_integral.is_some() {
            return p.scale.apply(p.phi_integrated(p.map.apply(theta)));
        }
        if p.axial_c {
            return TAU * p.sample(theta, 0.0);
        }
        quad::integrate(
            |phi| [p.sample(theta, phi)],
            &self.phi_breaks(theta),
            REL_INNER,
            MAX_PANELS_INNER,
        )[0]
    }

    /// Break points in θ ∈ \[0, hi\]: the kinks and jumps of the factor.
    fn theta_breaks(&self, hi: f64) -> Vec<f64> {
        let mut b = vec![0.0, hi, FRAC_PI_2];
        b.extend(self.cone.kinks());
        b.extend((1..8).map(|k| PI * k as f64 / 8.0));
        if let Some(f) = &self.focus
            && f.exponent > 4.0
            && f.exponent.is_finite()
        {
            // |cos θ|^F ≈ exp(−F θ²/2): resolve the peak at the poles
            let w = 1.0 / f.exponent.sqrt();
            let mut x = w;
            while x < FRAC_PI_2 {
                b.push(x);
                b.push(PI - x);
                x *= 4.0;
            }
        }
        if let Some(p) = &self.ies {
            p.theta_kinks(&mut b);
        }
        b.retain(|x| x.is_finite() && *x >= 0.0 && *x <= hi);
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }

    /// Break points in φ ∈ \[0, 2π\] for the slice at polar angle θ.
    fn phi_breaks(&self, theta: f64) -> Vec<f64> {
        let mut b: Vec<f64> = (0..=16).map(|k| PI * k as f64 / 8.0).collect();
        if let Some(p) = &self.ies {
            p.phi_kinks(theta, &mut b);
        }
        b.retain(|x| (0.0..=TAU).contains(x));
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }

    /// `true` when the factor is 1 in every direction: no focus (or a white tint), no cone (or
    /// one that never cuts), no IES profile.
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// `true` when an IES profile (`inputs:shaping:ies:file`) takes part.
    pub fn has_ies(&self) -> bool {
        self.ies.is_some()
    }

    /// The inputs as authored (before any clamping).
    pub fn params(&self) -> &ShapingParams {
        &self.params
    }

    /// The options the shaping was prepared with.
    pub fn options(&self) -> ShapingOptions {
        self.options
    }

    /// The IES profile (`inputs:shaping:ies:file`), if any.
    pub fn ies(&self) -> Option<&PhotometricWeb> {
        self.ies.as_ref().map(|p| &p.web)
    }

    /// The `inputs:shaping:ies:normalize` divisor: the profile's mean intensity in candela
    /// ([`PhotometricWeb::mean_intensity`] under `options.profile`), `None` without a profile or
    /// with normalize off. When it is 0 the IES factor is 0.
    pub fn ies_normalizer(&self) -> Option<f64> {
        self.ies.as_ref().and_then(|p| p.normalizer)
    }
}

/// A direction whose squared length under- or overflows, scaled by its largest component;
/// `None` for zero or non-finite directions.
#[cold]
fn rescale(d: DVec3) -> Option<DVec3> {
    if !d.is_finite() {
        return None;
    }
    let m = d.abs().max_element();
    if !(m > 0.0) {
        return None;
    }
    Some(d / m)
}

/// f64 → f32, NaN and negatives to 0, saturating at `f32::MAX`.
#[inline(always)]
fn to_f32(x: f64) -> f32 {
    if x >= 0.0 {
        x.min(f32::MAX as f64) as f32
    } else {
        0.0
    }
}

/// f64 → the smallest f32 ≥ x (saturating at `f32::MAX`); NaN gives `f32::MAX`.
fn f32_up(x: f64) -> f32 {
    if x.is_nan() {
        return f32::MAX;
    }
    if x <= 0.0 {
        return 0.0;
    }
    let f = x.min(f32::MAX as f64) as f32;
    if (f as f64) < x {
        f.next_up().min(f32::MAX)
    } else {
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions() {
        assert_eq!(to_f32(f64::NAN), 0.0);
        assert_eq!(to_f32(-1.0), 0.0);
        assert_eq!(to_f32(1e300), f32::MAX);
        assert_eq!(f32_up(0.0), 0.0);
        assert_eq!(f32_up(1e300), f32::MAX);
        assert!(f32_up(0.1) as f64 >= 0.1);
        assert_eq!(f32_up(1.0), 1.0);
        assert_eq!(f32_up(1.0 + 1e-12), 1.0f32.next_up());
        assert_eq!(
            rescale(DVec3::new(1e200, 0.0, -1e200)),
            Some(DVec3::new(1.0, 0.0, -1.0))
        );
        assert_eq!(rescale(DVec3::ZERO), None);
        assert_eq!(rescale(DVec3::new(f64::NAN, 1.0, 0.0)), None);
    }

    #[test]
    fn polar_and_direction_paths_agree() {
        let params = ShapingParams {
            focus: 1.5,
            focus_tint: [0.2, 0.5, 1.5],
            cone_angle_deg: 70.0,
            cone_softness: 0.4,
            ..Default::default()
        };
        let s = Shaping::new(&params, None, ShapingOptions::default()).unwrap();
        for i in 0..50 {
            for j in 0..10 {
                let (t, p) = (PI * i as f64 / 49.0, TAU * j as f64 / 10.0);
                let a = s.factor(lux_math::light_direction(t, p) * 3.0);
                let b = s.eval_polar(t, p);
                for k in 0..3 {
                    assert!((a[k] as f64 - b[k]).abs() < 1e-6, "{t} {p}");
                }
            }
        }
    }

    /// The fast path of `factor` (cone on the cosine, the even-grid lookup) against the polar
    /// path (angles of `light_polar`, the cone on θ, the web's lookup), with IES profiles of
    /// types C and B, bilinear and bicubic, with and without angleScale, cone and focus.
    #[test]
    fn ies_factor_agrees_with_the_polar_path() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ies/");
        let mut next = {
            let mut s = 0x9E3779B97F4A7C15u64;
            move || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64
            }
        };
        let mut worst = 0.0f64;
        for name in [
            "luxtest/bega_omni001_1238lm.ies",
            "luxtest/test_vstripes_hquadrants_nonuniform.ies",
            "luxtest/bega_84693k4.ies",
            "appleseed/test_iesparser_2.ies",
            "mdl-sdk/test.ies",
        ] {
            let text = String::from_utf8_lossy(&std::fs::read(format!("{dir}{name}")).unwrap())
                .into_owned();
            let file = lux_ies::IesFile::parse(&text).unwrap();
            let web = PhotometricWeb::new(&file, lux_math::Profile::Spec).unwrap();
            for (params, interpolation) in [
                (ShapingParams::NO_SHAPING, lux_ies::Interpolation::Bilinear),
                (ShapingParams::NO_SHAPING, lux_ies::Interpolation::Bicubic),
                (
                    ShapingParams {
                        focus: 2.0,
                        focus_tint: [0.2, 0.5, 1.0],
                        cone_angle_deg: 100.0,
                        cone_softness: 0.5,
                        ies_angle_scale: 0.7,
                        ies_normalize: true,
                    },
                    lux_ies::Interpolation::Bilinear,
                ),
                (
                    ShapingParams {
                        ies_angle_scale: -0.6,
                        ..ShapingParams::NO_SHAPING
                    },
                    lux_ies::Interpolation::Bilinear,
                ),
            ] {
                let options = ShapingOptions {
                    interpolation,
                    ..Default::default()
                };
                let s = Shaping::new(&params, Some(web.clone()), options).unwrap();
                // the two bega profiles take the even-grid lookup, the others the web's own
                let grid = s.ies.as_ref().unwrap().grid.is_some();
                let even = name.starts_with("luxtest/bega");
                assert_eq!(
                    grid,
                    even && interpolation == lux_ies::Interpolation::Bilinear
                );
                let m = s.max_factor() as f64;
                for _ in 0..4000 {
                    let z = 2.0 * next() - 1.0;
                    let r = (1.0 - z * z).sqrt();
                    let p = TAU * next();
                    let d = DVec3::new(r * p.cos(), r * p.sin(), z) * (0.5 + 3.0 * next());
                    let (t, p) = lux_math::light_polar(d).unwrap();
                    let a = s.factor(d);
                    let b = s.eval_polar(t, p);
                    for k in 0..3 {
                        let err = (a[k] as f64 - b[k]).abs();
                        // f32 rounding of the result, and the cone edge taken on the cosine
                        assert!(
                            err <= 1e-6 * b[k].abs() + 1e-9 * m,
                            "{name} {params:?} {d}: {a:?} vs {b:?}"
                        );
                        if b[k].abs() > 1e-6 * m {
                            worst = worst.max(err / b[k].abs());
                        }
                    }
                }
            }
        }
        // f32 output: half an ulp is 6·10⁻⁸
        assert!(worst <= 1e-7, "{worst}");
    }
}
