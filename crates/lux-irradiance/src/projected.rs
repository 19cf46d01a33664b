//! Projected solid angles: the unshadowed irradiance of a uniform emitter of unit radiance on a
//! Lambertian receiver, in closed form.
//!
//! For a receiver at `p` with unit normal `n` and an emitter occupying the solid angle Ω seen
//! from `p`, the **projected solid angle** is
//!
//! ```text
//! Π = ∫_Ω max(0, n·ω) dω        (sr; irradiance E = L·Π for uniform radiance L)
//! ```
//!
//! It is evaluated on the boundary of the emitter clipped to the receiver's upper half-space,
//! by the vector-irradiance identity (Lambert 1760, Arvo 1995 "Applications of irradiance
//! tensors"): `∫_Ω ω dω = ½ ∮_∂ r × dr / |r|²` for the curve `r(t)` relative to `p`, so that
//! `Π = ½ |n · ∮ r × dr / |r|²|`. A straight edge from `r₁` to `r₂` contributes
//! `θ · n·(r₁ × r₂)/|r₁ × r₂|` (θ the angle between them, Lambert's polygon formula); a circular
//! arc `r(t) = d + R(u cos t + v sin t)` contributes a rational trigonometric integral, done in
//! closed form (see [`disk`]).
//!
//! These are what a renderer uses as a control variate: with `g(ω) = L·max(0, n·ω)` the
//! unshadowed integrand of a light sample `ω ~ pdf`, the estimator
//! `L·Π − (1 − V(ω))·g(ω)/pdf(ω)` of the shadowed irradiance is unbiased for any sampler
//! covering the emitter and exact wherever the emitter is unoccluded.

use core::f64::consts::{PI, TAU};
use glam::DVec3;

/// Π of the planar convex or non-convex polygon `verts` (world points, in order around its
/// boundary, at most 16) from the receiver `(p, n)`: the polygon is clipped to `n·(x − p) ≥ 0`
/// and Lambert's formula summed over the clipped edges. Both faces count (a one-sided emitter
/// checks its side before calling). 0 for a polygon wholly below the horizon or seen edge-on.
pub fn polygon(p: DVec3, n: DVec3, verts: &[DVec3]) -> f64 {
    debug_assert!(verts.len() <= 16);
    // Clip (Sutherland–Hodgman against one plane): at most one more vertex than the input.
    let mut clipped = [DVec3::ZERO; 17];
    let mut m = 0;
    let k = verts.len();
    for i in 0..k {
        let a = verts[i] - p;
        let b = verts[(i + 1) % k] - p;
        let (ha, hb) = (n.dot(a), n.dot(b));
        if ha >= 0.0 {
            clipped[m] = a;
            m += 1;
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            let t = ha / (ha - hb);
            // The crossing, put exactly on the horizon plane's side (n·r ≥ 0 up to rounding).
            clipped[m] = a + (b - a) * t;
            m += 1;
        }
    }
    if m < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..m {
        sum += edge(n, clipped[i], clipped[(i + 1) % m]);
    }
    0.5 * sum.abs()
}

/// `n · ∫ r × dr/|r|²` along the straight edge from `a` to `b` (relative to the receiver):
/// `θ · n·(a × b)/|a × b|`, θ = atan2(|a × b|, a·b).
#[inline]
fn edge(n: DVec3, a: DVec3, b: DVec3) -> f64 {
    let c = a.cross(b);
    let s = c.length();
    if crate::not_positive(s) {
        return 0.0;
    }
    s.atan2(a.dot(b)) * n.dot(c) / s
}

/// Π of the disk of centre `c`, unit normal `axis` and radius `radius` from the receiver
/// `(p, n)`, both faces counted, clipped to the receiver's upper half-space: the arc of the
/// rim above the horizon in closed form plus the chord along the horizon as a straight edge.
/// `None` for a non-positive or non-finite radius or axis.
pub fn disk(p: DVec3, n: DVec3, c: DVec3, axis: DVec3, radius: f64) -> Option<f64> {
    if !(radius > 0.0 && radius.is_finite()) {
        return None;
    }
    let axis = axis.try_normalize()?;
    let (u, v) = axis.any_orthonormal_pair();
    let d = c - p;
    let r = radius;
    let (arc, phi) = rim(n, d, (u, v), r)?;
    // The rim's height above the horizon: h(t) = h0 + hu cos t + hv sin t.
    let h0 = n.dot(d);
    let (hu, hv) = (r * n.dot(u), r * n.dot(v));
    let hr = (hu * hu + hv * hv).sqrt();
    let total = if h0 >= hr {
        arc.full()
    } else if h0 <= -hr {
        return Some(0.0);
    } else {
        // Above the horizon for t ∈ [th − β, th + β].
        let th = hv.atan2(hu);
        let beta = (-h0 / hr).clamp(-1.0, 1.0).acos();
        let (t0, t1) = (th - beta, th + beta);
        // Centre the arc in s = t − φ within (−π, π] so that s stays in (−2π, 2π).
        let mut cs = th - phi;
        cs -= TAU * (cs / TAU).round();
        let (s0, s1) = (cs - beta, cs + beta);
        let rim = |t: f64| {
            let (st, ct) = t.sin_cos();
            d + r * (u * ct + v * st)
        };
        arc.between(s0, s1) + edge(n, rim(t1), rim(t0))
    };
    Some(0.5 * total.abs())
}

/// Π of the sphere of centre `c` and radius `radius` from the receiver `(p, n)`, clipped to
/// the receiver's upper half-space: the sphere seen from `p` is its silhouette disk (centre
/// `p + d(1 − R²/D²)`, radius `R·√(D² − R²)/D`, facing `p`), whose Π is [`disk`]'s. Unclipped it
/// is `π sin²α cos ω` (sin α = R/D). `None` for a receiver inside or on the sphere.
pub fn sphere(p: DVec3, n: DVec3, c: DVec3, radius: f64) -> Option<f64> {
    let d = c - p;
    let d2 = d.length_squared();
    let r2 = radius * radius;
    if !(d2 > r2 && radius > 0.0 && d2.is_finite()) {
        return None;
    }
    let sin2 = r2 / d2;
    let cos_w = n.dot(d) / d2.sqrt();
    // Fully above the horizon (cos ω ≥ sin α): the closed form.
    if cos_w >= 0.0 && cos_w * cos_w >= sin2 {
        return Some(PI * sin2 * cos_w);
    }
    let centre = p + d * (1.0 - sin2);
    let rad = radius * ((d2 - r2) / d2).sqrt();
    disk(p, n, centre, d, rad)
}

/// `n · ∫ r × dr/|r|²` along the circle `r(t) = d + R(u cos t + v sin t)` (relative to the
/// receiver; `u`, `v` orthonormal) for t from `t0` to `t1`, `0 ≤ t1 − t0 < 2π`: the rim term of
/// [`disk`], over an arc of it. `None` where the receiver is on the circle or for bad input.
pub(crate) fn rim_arc(
    n: DVec3,
    d: DVec3,
    (u, v): (DVec3, DVec3),
    r: f64,
    t0: f64,
    t1: f64,
) -> Option<f64> {
    let len = t1 - t0;
    if !(0.0..TAU).contains(&len) {
        return None;
    }
    let (arc, phi) = rim(n, d, (u, v), r)?;
    // s = t − φ from within (−π, π]; past π, the rest one period back.
    let mut s0 = t0 - phi;
    s0 -= TAU * (s0 / TAU).round();
    let s1 = s0 + len;
    Some(if s1 <= PI {
        arc.between(s0, s1)
    } else {
        arc.between(s0, PI) + arc.between(-PI, s1 - TAU)
    })
}

/// The rim `r(t) = d + R(u cos t + v sin t)` of a disk (relative to the receiver; `u`, `v`
/// orthonormal) as [`Arc`]'s integrand `n·(r × r')/|r|²` in `s = t − φ`, with φ: writing
/// `n·(r × r') = a0 + a1 cos t + a2 sin t` and `|r|² = b0 + b1 cos t + b2 sin t`, the shift by
/// φ = atan2(b2, b1) makes the denominator `b0 + ρ cos s`. `None` where the receiver is on the
/// rim (b0 ≤ ρ: the integrand is singular there) or for NaN input.
fn rim(n: DVec3, d: DVec3, (u, v): (DVec3, DVec3), r: f64) -> Option<(Arc, f64)> {
    let a0 = r * r * n.dot(u.cross(v));
    let a1 = r * n.dot(d.cross(v));
    let a2 = -r * n.dot(d.cross(u));
    let b0 = d.length_squared() + r * r;
    let (b1, b2) = (2.0 * r * d.dot(u), 2.0 * r * d.dot(v));
    let rho = (b1 * b1 + b2 * b2).sqrt();
    if b0.is_nan() || rho.is_nan() || b0 <= rho {
        return None;
    }
    let phi = if rho > 0.0 { b2.atan2(b1) } else { 0.0 };
    let (sp, cp) = phi.sin_cos();
    let arc = Arc {
        a0,
        a: a1 * cp + a2 * sp,
        b: a2 * cp - a1 * sp,
        b0,
        rho,
    };
    Some((arc, phi))
}

/// `∫ (a0 + a cos s + b sin s)/(b0 + ρ cos s) ds` with b0 > ρ ≥ 0, in forms that stay accurate
/// as ρ → 0 (the receiver near the disk's axis).
struct Arc {
    a0: f64,
    a: f64,
    b: f64,
    b0: f64,
    rho: f64,
}

impl Arc {
    /// Over a whole period: `2π (a0 − aρ/(k + b0)) / k`, k = √(b0² − ρ²).
    fn full(&self) -> f64 {
        let k = self.k();
        TAU * (self.a0 - self.a * self.rho / (k + self.b0)) / k
    }

    fn k(&self) -> f64 {
        ((self.b0 - self.rho) * (self.b0 + self.rho)).sqrt()
    }

    /// Over `[s0, s1]` ⊂ (−2π, 2π), s1 − s0 ≤ 2π. With x = s/2, q = √((b0 − ρ)/(b0 + ρ)):
    /// `∫ 1/D = (2/k)·θq`, θq = atan2(q sin x, cos x); `∫ cos s/D = (s − b0∫1/D)/ρ
    /// = (2/ρ)·atan2((1 − q) sin x cos x, cos²x + q sin²x) − 2ρ θq/(k(b0 + k))`;
    /// `∫ sin s/D = −ln(D)/ρ` (as `ln_1p` of the relative change).
    fn between(&self, s0: f64, s1: f64) -> f64 {
        let (b0, rho) = (self.b0, self.rho);
        let k = self.k();
        let q = ((b0 - rho) / (b0 + rho)).sqrt();
        let one_minus_q = 2.0 * rho / ((b0 + rho) * (1.0 + q));
        let theta_q = |s: f64| {
            let (sx, cx) = (0.5 * s).sin_cos();
            (q * sx).atan2(cx)
        };
        let cos_part = |s: f64| {
            if rho == 0.0 {
                return s.sin() / b0;
            }
            let (sx, cx) = (0.5 * s).sin_cos();
            let delta = (one_minus_q * sx * cx).atan2(cx * cx + q * sx * sx);
            2.0 * delta / rho - 2.0 * rho * theta_q(s) / (k * (b0 + k))
        };
        let inv = (2.0 / k) * (theta_q(s1) - theta_q(s0));
        let cos_int = cos_part(s1) - cos_part(s0);
        let (c0, c1) = (s0.cos(), s1.cos());
        let sin_int = if rho == 0.0 {
            -(c1 - c0) / b0
        } else {
            -(rho * (c1 - c0) / (b0 + rho * c0)).ln_1p() / rho
        };
        self.a0 * inv + self.a * cos_int + self.b * sin_int
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Π by brute force: a fine midpoint rule over the emitter's area,
    /// `∫ max(0, n·ω) |cos θ_l| / |x − p|² dA`.
    fn area_quadrature(
        p: DVec3,
        n: DVec3,
        point: impl Fn(f64, f64) -> (DVec3, DVec3, f64),
        steps: usize,
    ) -> f64 {
        let mut sum = 0.0;
        for i in 0..steps {
            for j in 0..steps {
                let (a, b) = (
                    (i as f64 + 0.5) / steps as f64,
                    (j as f64 + 0.5) / steps as f64,
                );
                let (x, nl, da) = point(a, b);
                let w = x - p;
                let d2 = w.length_squared();
                let wn = w / d2.sqrt();
                sum += n.dot(wn).max(0.0) * nl.dot(wn).abs() / d2 * da;
            }
        }
        sum / (steps * steps) as f64
    }

    #[test]
    fn parallel_rect_from_its_corner_is_the_tabulated_form_factor() {
        // Unit-area receiver under the corner of an a × b rectangle at height h (Howell's
        // catalogue, B-3): F = (1/2π)[X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))].
        let (a, b, h) = (2.0f64, 3.0f64, 1.5f64);
        let (x, y) = (a / h, b / h);
        let f = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
            + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
            / TAU;
        let verts = [
            DVec3::new(0.0, 0.0, h),
            DVec3::new(a, 0.0, h),
            DVec3::new(a, b, h),
            DVec3::new(0.0, b, h),
        ];
        let got = polygon(DVec3::ZERO, DVec3::Z, &verts);
        assert!((got - PI * f).abs() < 1e-14, "{got} vs {}", PI * f);
        // Winding and face do not matter.
        let mut rev = verts;
        rev.reverse();
        assert_eq!(polygon(DVec3::ZERO, DVec3::Z, &rev), got);
    }

    #[test]
    fn disk_on_axis_and_sphere_unclipped_closed_forms() {
        // Disk of radius R facing the receiver at distance h: Π = π R²/(R² + h²).
        for (r, h) in [(1.0, 1.0), (0.5, 3.0), (2.0, 0.1), (1e-3, 10.0)] {
            let got = disk(DVec3::ZERO, DVec3::Z, DVec3::new(0.0, 0.0, h), DVec3::Z, r).unwrap();
            let want = PI * r * r / (r * r + h * h);
            assert!(
                (got - want).abs() <= 1e-14 * want,
                "R {r} h {h}: {got} vs {want}"
            );
        }
        // Sphere tilted but wholly above the horizon: π sin²α cos ω.
        let c = DVec3::new(1.0, 0.5, 2.0);
        let got = sphere(DVec3::ZERO, DVec3::Z, c, 0.4).unwrap();
        let want = PI * 0.16 / c.length_squared() * (2.0 / c.length());
        assert!((got - want).abs() < 1e-15, "{got} vs {want}");
    }

    #[test]
    fn clipped_shapes_match_quadrature() {
        let p = DVec3::new(0.1, -0.2, 0.05);
        let n = DVec3::new(0.3, 0.2, 1.0).normalize();
        // A tilted rect straddling the receiver's horizon.
        let (o, ex, ey) = (
            DVec3::new(-1.0, -0.5, -0.4),
            DVec3::new(2.0, 0.3, 0.2),
            DVec3::new(0.1, 0.4, 1.5),
        );
        let verts = [o, o + ex, o + ex + ey, o + ey];
        let nl = ex.cross(ey);
        let got = polygon(p, n, &verts);
        let want = area_quadrature(
            p,
            n,
            |a, b| (o + ex * a + ey * b, nl.normalize(), nl.length()),
            1500,
        );
        assert!((got - want).abs() < 2e-5 * want, "rect {got} vs {want}");
        // A tilted disk straddling the horizon.
        let (c, axis, r) = (DVec3::new(0.3, 0.8, 0.1), DVec3::new(0.2, -1.0, 0.4), 0.6);
        let (u, v) = axis.normalize().any_orthonormal_pair();
        let got = disk(p, n, c, axis, r).unwrap();
        let want = area_quadrature(
            p,
            n,
            |a, b| {
                // polar map of the unit square: radius √a, angle 2πb (area element πR²)
                let (s, co) = (TAU * b).sin_cos();
                (
                    c + r * a.sqrt() * (u * co + v * s),
                    axis.normalize(),
                    PI * r * r,
                )
            },
            1500,
        );
        assert!((got - want).abs() < 2e-5 * want, "disk {got} vs {want}");
        // A sphere straddling the horizon: Snyder's closed form (1996) for the clipped cap.
        let (c, rad) = (DVec3::new(0.5, 0.2, 0.3), 0.45);
        let got = sphere(p, n, c, rad).unwrap();
        let want = snyder(p, n, c, rad);
        assert!((got - want).abs() < 1e-12 * want, "sphere {got} vs {want}");
    }

    #[test]
    fn near_the_axis_the_arc_stays_accurate() {
        // Receiver tilted so the rim crosses its horizon, moved towards the disk's axis: Π is
        // continuous in the offset (no 0/0 as ρ → 0).
        let n = DVec3::new(1.0, 0.0, 0.2).normalize();
        let c = DVec3::new(0.0, 0.0, 0.3);
        let at = |e: f64| disk(DVec3::new(e, 0.0, 0.0), n, c, DVec3::Z, 1.0).unwrap();
        let base = at(0.0);
        for e in [1e-3, 1e-6, 1e-9, 1e-12] {
            assert!(
                (at(e) - base).abs() < 10.0 * e + 1e-13,
                "{e}: {} vs {base}",
                at(e)
            );
        }
        assert!(base > 0.0 && base < PI);
    }

    #[test]
    fn below_the_horizon_is_zero_and_bad_input_none() {
        let c = DVec3::new(0.0, 0.0, -2.0);
        assert_eq!(disk(DVec3::ZERO, DVec3::Z, c, DVec3::Z, 1.0), Some(0.0));
        assert_eq!(sphere(DVec3::ZERO, DVec3::Z, c, 1.0), Some(0.0));
        assert_eq!(sphere(DVec3::ZERO, DVec3::Z, c, 3.0), None);
        assert_eq!(disk(DVec3::ZERO, DVec3::Z, c, DVec3::ZERO, 1.0), None);
        assert_eq!(disk(DVec3::ZERO, DVec3::Z, c, DVec3::Z, f64::NAN), None);
        let below = [c, c + DVec3::X, c + DVec3::Y];
        assert_eq!(polygon(DVec3::ZERO, DVec3::Z, &below), 0.0);
    }

    /// Snyder's closed form (1996) for a sphere whose cap straddles the horizon.
    fn snyder(p: DVec3, n: DVec3, c: DVec3, rad: f64) -> f64 {
        let d = c - p;
        let sin2 = rad * rad / d.length_squared();
        let cos_t = n.dot(d.normalize());
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        let x = (1.0 / sin2 - 1.0).sqrt();
        let y = -x * cos_t / sin_t;
        let st_y = sin_t * (1.0 - y * y).sqrt();
        (cos_t * y.acos() - x * st_y) * sin2 + (st_y / x).atan()
    }

    proptest::proptest! {
        /// The clipped-arc path of [`disk`] (through [`sphere`]) against Snyder's formula over
        /// random straddling configurations.
        #[test]
        fn straddling_spheres_agree_with_snyder(
            dir in proptest::array::uniform3(-1.0f64..1.0),
            dist in 1.05f64..50.0,
            tilt in -0.999f64..0.999,
        ) {
            let d = DVec3::from(dir);
            proptest::prop_assume!(d.length() > 0.1);
            let d = d.normalize();
            let rad = 1.0;
            let c = d * dist;
            let sin_a = rad / dist;
            // A normal at angle ω from d with |cos ω| < sin α: the cap straddles the horizon.
            let cos_w = tilt * sin_a;
            let (u, _) = d.any_orthonormal_pair();
            let n = d * cos_w + u * (1.0 - cos_w * cos_w).sqrt();
            let got = sphere(DVec3::ZERO, n, c, rad).unwrap();
            let want = snyder(DVec3::ZERO, n, c, rad);
            // Both forms lose digits as the cap sinks (Snyder's by cancellation): compare
            // against the scale of the unclipped value π sin²α.
            proptest::prop_assert!((got - want).abs() <= 1e-12 * PI * sin_a * sin_a,
                "{} vs {}", got, want);
        }
    }
}
