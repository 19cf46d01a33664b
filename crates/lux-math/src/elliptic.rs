//! Carlson's symmetric elliptic integrals and the closed forms built on them: ellipsoid surface
//! area, ellipse perimeter, plus the approximations the hdEmbree reference uses.
//!
//! References: B. C. Carlson, "Numerical computation of real or complex elliptic integrals",
//! Numer. Algorithms 10 (1995) — duplication theorem and the truncated Taylor series used here;
//! DLMF §19.16 (R_G in terms of R_F and R_D) and §19.33.2 (ellipsoid area).

use crate::tables::elliptic::{GK_BOUNDS, GK_COEFS, TRACE_EXACT, TRACE_RAMANUJAN};
use core::f64::consts::PI;

/// Relative spread of the duplicated arguments below which the Taylor series (to 7th order,
/// truncation O(ε⁸)) is applied: `ERRTOL_F` for R_F, `ERRTOL_D` for R_D (whose higher-order
/// coefficients are larger). At these spreads the truncation error is below 10⁻¹⁷, under the
/// rounding of the result; measured against 30-digit values (mpmath) on 12,000 ellipsoid-type
/// arguments the largest relative error is 6.9·10⁻¹⁶ (R_F) and 6.5·10⁻¹⁶ (R_D), the same as with
/// the classic 5th-order series at spread 10⁻³, which needs 1.6 more duplication steps on average.
const ERRTOL_F: f64 = 0.02;
const ERRTOL_D: f64 = 0.01;
/// Iteration cap: each duplication step shrinks the spread by 4, so 40 steps cover any
/// finite input's dynamic range.
const MAX_STEPS: usize = 40;

/// Carlson's R_F(x, y, z) and R_D(x, y, z) evaluated together (they share the duplication
/// sequence). Arguments must be ≥ 0 with at most one zero, and `z > 0` for R_D; otherwise the
/// result is non-finite.
///
/// R_F(x,y,z) = ½∫₀^∞ dt / √((t+x)(t+y)(t+z)), R_D(x,y,z) = 3/2 ∫₀^∞ dt / (√((t+x)(t+y)) (t+z)^{3/2}).
pub fn carlson_rf_rd(mut x: f64, mut y: f64, mut z: f64) -> (f64, f64) {
    let mut sum = 0.0;
    let mut fac = 1.0;
    for _ in 0..MAX_STEPS {
        // Convergence test without divisions (they share the unit with the square roots):
        // max|a − ·| ≤ ERRTOL·a for both series' means a.
        let af = (x + y + z) * (1.0 / 3.0);
        let ad = (x + y + 3.0 * z) * 0.2;
        let dev_f = (af - x).abs().max((af - y).abs()).max((af - z).abs());
        let dev_d = (ad - x).abs().max((ad - y).abs()).max((ad - z).abs());
        if dev_f <= ERRTOL_F * af && dev_d <= ERRTOL_D * ad {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lam));
        fac *= 0.25;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
    }
    // R_F series (Carlson's expansion of R_{-a}(b; 1 − Z) = Σ (a)_N/(c)_N T_N(b; Z) to N = 7,
    // in the elementary symmetric functions E2 = XY − Z², E3 = XYZ of the relative deviations
    // X + Y + Z = 0; derived symbolically by `scripts/derive_carlson_series.py`, checked against
    // mpmath):
    // 1 − E2/10 + E3/14 + E2²/24 − 3E2E3/44 − 5E2³/208 + 3E3²/104 + E2²E3/16.
    // (one division per series: 1/A, and A^{-1/2} = √(1/A))
    let inv_a = 1.0 / ((x + y + z) * (1.0 / 3.0));
    let dx = 1.0 - x * inv_a;
    let dy = 1.0 - y * inv_a;
    let dz = -dx - dy;
    let e2 = dx * dy - dz * dz;
    let e3 = dx * dy * dz;
    let rf = (1.0
        + e2 * (-1.0 / 10.0 + e2 * (1.0 / 24.0 - 5.0 / 208.0 * e2))
        + e3 * (1.0 / 14.0 + e2 * (-3.0 / 44.0 + e2 * (1.0 / 16.0)) + 3.0 / 104.0 * e3))
        * inv_a.sqrt();
    // R_D series, the same expansion with a = 3/2, b = (½, ½, 3/2) to N = 7, written in the
    // deviation Z of z and Q = XY (X + Y + 3Z = 0): Σ Qʲ·Pⱼ(Z).
    let inv_a = 1.0 / ((x + y + 3.0 * z) * 0.2);
    let dx = 1.0 - x * inv_a;
    let dy = 1.0 - y * inv_a;
    let z1 = -(dx + dy) * (1.0 / 3.0);
    let q = dx * dy;
    let p0 = 1.0
        + z1 * z1
            * (9.0 / 7.0
                + z1 * (-4.0 / 3.0
                    + z1 * (45.0 / 11.0 + z1 * (-108.0 / 13.0 + z1 * (21.0 - 864.0 / 17.0 * z1)))));
    let p1 = -3.0 / 14.0
        + z1 * (0.5 + z1 * (-18.0 / 11.0 + z1 * (60.0 / 13.0 + z1 * (-13.5 + 1323.0 / 34.0 * z1))));
    let p2 = 9.0 / 88.0 + z1 * (-27.0 / 52.0 + z1 * (2.25 - 585.0 / 68.0 * z1));
    let p3 = -1.0 / 16.0 + 135.0 / 272.0 * z1;
    let series = p0 + q * (p1 + q * (p2 + q * p3));
    let rd = 3.0 * sum + fac * series * (inv_a * inv_a.sqrt());
    (rf, rd)
}

/// Carlson's R_G(x, y, z) = (1/4π) ∫ √(x·s₁² + y·s₂² + z·s₃²) dΩ over the unit sphere, for
/// x, y, z ≥ 0 (DLMF 19.16.3). Symmetric; uses 2R_G = z·R_F − (x−z)(y−z)·R_D/3 + √(xy/z) with
/// z the largest argument. Handles up to two zero arguments exactly; all zero gives 0.
pub fn carlson_rg(x: f64, y: f64, z: f64) -> f64 {
    // Sort so that z is the largest, y the middle, x the smallest.
    let mut v = [x, y, z];
    if v[0] > v[1] {
        v.swap(0, 1);
    }
    if v[1] > v[2] {
        v.swap(1, 2);
    }
    if v[0] > v[1] {
        v.swap(0, 1);
    }
    let [x, y, z] = v;
    if z <= 0.0 {
        return 0.0;
    }
    if y <= 0.0 {
        // R_G(0, 0, z) = √z / 2.
        return 0.5 * z.sqrt();
    }
    let (rf, rd) = carlson_rf_rd(x, y, z);
    0.5 * (z * rf - (x - z) * (y - z) * rd * (1.0 / 3.0) + (x * y / z).sqrt())
}

/// Exact surface area of an ellipsoid with semi-axes `a, b, c` (any order, ≥ 0):
/// `S = 4π·R_G(b²c², c²a², a²b²)` (the scaled form of DLMF 19.33.2, S = 4πabc·R_G(a⁻², b⁻², c⁻²),
/// which stays finite when an axis is 0: a flat ellipsoid is a doubly covered ellipse, 2πab).
///
/// The semi-axes are divided by the largest one first and the result multiplied by its square
/// (R_G is homogeneous of degree ½, so `S(ka, kb, kc) = k²·S(a, b, c)`): the fourth powers inside
/// R_G then neither overflow nor underflow for any representable light size. Returns NaN for a
/// NaN or negative input (callers validate first).
pub fn ellipsoid_area(a: f64, b: f64, c: f64) -> f64 {
    let s = a.max(b).max(c);
    if s == 0.0 {
        return 0.0;
    }
    if !(s.is_finite() && a >= 0.0 && b >= 0.0 && c >= 0.0) {
        return f64::NAN;
    }
    let (a, b, c) = (a / s, b / s, c / s);
    let (a2, b2, c2) = (a * a, b * b, c * c);
    4.0 * PI * carlson_rg(b2 * c2, c2 * a2, a2 * b2) * (s * s)
}

/// [`ellipsoid_area`] from the **squared** semi-axes `a², b², c²` (≥ 0, finite), as they come
/// out of an eigen-decomposition (no square roots needed): scaled by the largest, then
/// `4π·R_G(b²c², c²a², a²b²)`. Returns 0 when all are 0 and NaN for NaN or negative input.
pub(crate) fn ellipsoid_area_from_squares(a2: f64, b2: f64, c2: f64) -> f64 {
    let s2 = a2.max(b2).max(c2);
    if s2 == 0.0 {
        return 0.0;
    }
    if !(s2.is_finite() && a2 >= 0.0 && b2 >= 0.0 && c2 >= 0.0) {
        return f64::NAN;
    }
    // Scale by the power of two 2^−e nearest below 1/s2 (exact, no division): the largest
    // square lands in [1, 2), the products inside R_G in [0, 4), and R_G(k²·…) = k·R_G(…) is
    // undone by the exact 2^e.
    let e = ((s2.to_bits() >> 52) & 0x7ff).clamp(1, 2045);
    let k = f64::from_bits((2046 - e) << 52);
    let inv_k = f64::from_bits(e << 52);
    let (a2, b2, c2) = (a2 * k, b2 * k, c2 * k);
    4.0 * PI * carlson_rg(b2 * c2, c2 * a2, a2 * b2) * inv_k
}

/// Thomsen's exponent as the hdEmbree reference uses it (Thomsen's own optimum is p ≈ 1.6075).
pub const THOMSEN_P: f64 = 1.6;

/// Knud Thomsen's approximation of the ellipsoid area,
/// `S ≈ 4π·((aᵖbᵖ + aᵖcᵖ + bᵖcᵖ)/3)^{1/p}` with `p = 1.6` ([`THOMSEN_P`]) as the hdEmbree
/// reference uses it. Exact for spheres.
///
/// Accuracy with p = 1.6 (measured against [`ellipsoid_area`], see the tests): within 1.1 % for
/// every ellipsoid whose smallest-to-largest semi-axis ratio is at least 1/30; the error grows
/// to its supremum 1 − 4·(2/3)^{1/p}/π = 1.178 % (an under-estimate) in the needle limit
/// a ≫ b = c. (The often-quoted "1.061 %" is for p = 1.6075.)
pub fn ellipsoid_area_thomsen(a: f64, b: f64, c: f64) -> f64 {
    const P: f64 = THOMSEN_P;
    let (ap, bp, cp) = (a.powf(P), b.powf(P), c.powf(P));
    4.0 * PI * ((ap * bp + ap * cp + bp * cp) / 3.0).powf(1.0 / P)
}

/// Largest h = ((a − b)/(a + b))² handled by [`gauss_kummer`] (semi-axis ratio b/a ≥ 0.0406).
pub(crate) const GAUSS_KUMMER_MAX_H: f64 = 0.85;

/// The Gauss–Kummer function GK(h) = ₂F₁(−½, −½; 1; h) = Σₙ C(½, n)² hⁿ, with which the ellipse
/// perimeter is `P = π(a + b)·GK(h)`, `h = ((a − b)/(a + b))²`; for 0 ≤ h ≤
/// [`GAUSS_KUMMER_MAX_H`], `None` beyond (and for NaN).
///
/// A piecewise polynomial: on each of four intervals of h the Chebyshev interpolant of degree
/// 11–14, converted to powers of the interval's variable t (coefficients computed by us at 40
/// digits with mpmath's `hyp2f1`: `GK_BOUNDS`, `GK_COEFS` in `src/tables/elliptic.rs`, generated
/// by `scripts/gen_elliptic_tables.py`). Its
/// truncation error is below 2·10⁻¹⁷ relative; the Estrin evaluation adds about an ulp. No
/// square root, no loop: the AGM needs a dependent square root per step.
#[inline]
pub(crate) fn gauss_kummer(h: f64) -> Option<f64> {
    let i = if h <= 0.25 {
        if h < 0.0 {
            return None;
        }
        0
    } else if h <= 0.5 {
        1
    } else if h <= 0.7 {
        2
    } else if h <= GAUSS_KUMMER_MAX_H {
        3
    } else {
        return None; // also NaN
    };
    let (lo, hi) = GK_BOUNDS[i];
    let c = &GK_COEFS[i];
    let t = (2.0 * h - (lo + hi)) * (1.0 / (hi - lo));
    // Estrin's scheme (depth 4 instead of Horner's 15): pairs, then powers t², t⁴, t⁸.
    let t2 = t * t;
    let t4 = t2 * t2;
    let p = |k: usize| c[k] + c[k + 1] * t;
    let q0 = p(0) + p(2) * t2;
    let q1 = p(4) + p(6) * t2;
    let q2 = p(8) + p(10) * t2;
    let q3 = p(12) + p(14) * t2;
    Some((q0 + q1 * t4) + (q2 + q3 * t4) * (t4 * t4))
}

/// The ellipse perimeter in trace form, for callers that know the squared semi-axes only
/// through invariants: with `T = a² + b²` and `m = ((a² − b²)/T)²`,
/// `P = √T·F(m)`. F is a function of m alone (P is homogeneous of degree 1 and symmetric in
/// a ↔ b, i.e. even in (a² − b²)/T), analytic for m < 1 with its only singularity at m = 1
/// (b = 0). F(0) = π√2 (a circle).
///
/// Both T and a² − b² are polynomials in the entries of a Gram matrix (its trace and the
/// discriminant `(g11 − g22)² + 4g12²`), so m costs one division and no square root: the root
/// √T runs beside it instead of before it, which is what makes the cylinder size factor fast.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TraceForm {
    /// Exact: `F_E(m) = 4a·E(1 − b²/a²)` at T = 1 (complete elliptic integral of the second kind).
    Exact,
    /// Ramanujan's second approximation at T = 1 (the hdEmbree reference's formula, see
    /// [`ellipse_perimeter_ramanujan`]).
    Ramanujan,
}

/// Largest m (exclusive) covered by [`ellipse_perimeter_trace`]'s tables, 51.5/64 (semi-axis
/// ratio b/a > 0.233).
pub(crate) const TRACE_MAX_M: f64 = 51.5 / 64.0;

// F(m) on the 52 intervals [(i − ½)/64, (i + ½)/64] of m (the first clipped at 0): the
// Chebyshev interpolant of degree 7 at 40 digits (mpmath's `ellipe`), in powers of
// s = 64m − i ∈ [−½, ½], lowest first: `TRACE_EXACT` and `TRACE_RAMANUJAN` in
// `src/tables/elliptic.rs`, generated by `scripts/gen_elliptic_tables.py`. Truncation error
// below 8.3·10⁻¹⁸ relative on every interval (the largest on the last).

/// `P = √T·F(m)` of [`TraceForm`] for `T = a² + b²` and `n = (a² − b²)²`, or `None` when m ≥
/// [`TRACE_MAX_M`] (flatter ellipses), T is outside \[10⁻¹⁵⁰, 10¹⁵⁰\] (T² would lose range) or
/// anything is NaN: the caller then takes the semi-axes route.
///
/// Cost: one division and one square root side by side, then a table row and a degree-7
/// Estrin evaluation (depth 3). The row is the nearest integer i to x = 64m, found by adding
/// 1.5·2⁵² (round to nearest; no float → integer conversion on the critical path), and
/// s = x − i is exact.
#[inline(always)]
pub(crate) fn ellipse_perimeter_trace(t: f64, n: f64, form: TraceForm) -> Option<f64> {
    const ROUND: f64 = 6_755_399_441_055_744.0; // 1.5·2⁵²
    if !(t > 1e-150 && t < 1e150) {
        return None;
    }
    let x = (64.0 * n) / (t * t);
    if !(0.0..TRACE_MAX_M * 64.0).contains(&x) {
        return None; // also NaN
    }
    let r = x + ROUND;
    let i = (r.to_bits() & 0x3f) as usize;
    let c = match form {
        TraceForm::Exact => &TRACE_EXACT[i],
        TraceForm::Ramanujan => &TRACE_RAMANUJAN[i],
    };
    let s = x - (r - ROUND);
    let s2 = s * s;
    let q0 = (c[0] + c[1] * s) + (c[2] + c[3] * s) * s2;
    let q1 = (c[4] + c[5] * s) + (c[6] + c[7] * s) * s2;
    Some(t.sqrt() * (q0 + q1 * (s2 * s2)))
}

/// Exact perimeter of an ellipse with semi-axes `a, b` (≥ 0, any order), `P = 4a·E(e)`.
///
/// `P = π(a + b)·GK(h)`, `h = ((a − b)/(a + b))²`, with the piecewise polynomial for the
/// Gauss–Kummer function GK (`gauss_kummer` in the source) when h ≤ 0.85 (b/a ≥ 0.0406);
/// flatter ellipses by the arithmetic–geometric mean (Gauss–Kummer / AGM form) `P = 2π·(a² − Σₙ 2ⁿ⁻¹ cₙ²) / AGM(a, b)`, `c₀² = a² − b²`,
/// `cₙ₊₁ = (aₙ − gₙ)/2`, which converges quadratically (≤ 6 steps in double precision).
/// Against 30-digit values (mpmath, 2000 ratios): the polynomial branch within 3.6·10⁻¹⁶, the
/// AGM within 1.1·10⁻¹⁵ (its a² − Σ… cancels up to two bits). A circle gives exactly 2πa;
/// a segment (b = 0) gives 4a.
pub fn ellipse_perimeter(a: f64, b: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    if a == b {
        return 2.0 * PI * a;
    }
    let s = a + b;
    if s.is_finite() && b > 0.0 {
        let q = (a - b) / s;
        if let Some(g) = gauss_kummer(q * q) {
            return PI * s * g;
        }
    }
    ellipse_perimeter_agm(a, b)
}

/// [`ellipse_perimeter`] by the AGM alone (`a ≥ b` not required). Homogeneous of degree 1:
/// the computation runs on `(1, b/a)` and is multiplied by `a`, so `a²` never overflows.
pub(crate) fn ellipse_perimeter_agm(a: f64, b: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    if a == b {
        return 2.0 * PI * a;
    }
    if b.is_nan() || b <= 0.0 {
        return if a.is_finite() { 4.0 * a } else { f64::NAN };
    }
    if !a.is_finite() {
        return f64::NAN;
    }
    let scale = a;
    let (a, b) = (1.0, b / a);
    let mut an = a;
    let mut gn = b;
    let mut s = 0.5 * (a * a - b * b);
    let mut w = 0.5;
    for _ in 0..8 {
        let cn = 0.5 * (an - gn);
        w *= 2.0;
        s += w * cn * cn;
        let next_a = 0.5 * (an + gn);
        gn = (an * gn).sqrt();
        an = next_a;
        if cn <= 1e-17 * an {
            break;
        }
    }
    2.0 * PI * (a * a - s) / an * scale
}

/// Ramanujan's second approximation of the ellipse perimeter,
/// `P ≈ π(a+b)(1 + 3h/(10 + √(4 − 3h)))`, `h = ((a−b)/(a+b))²`, as the hdEmbree reference uses it.
pub fn ellipse_perimeter_ramanujan(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s == 0.0 {
        return 0.0;
    }
    // The same value multiplied out (s > 0): π·(s + 3d²/(10s + √Q)), d = a − b,
    // Q = 4s² − 3d² ∈ [s², 4s²]; with the denominator rationalised,
    // 3d²/(10s + √Q) = 3d²·(10s − √Q)/(96s² + 3d²), so that the square root and the division
    // run side by side instead of one after the other. 10s − √Q ≥ 8s: nothing cancels.
    let d = a - b;
    let (s2, d2) = (s * s, 3.0 * d * d);
    let root = (4.0 * s2 - d2).sqrt();
    let inv = 1.0 / (96.0 * s2 + d2);
    PI * (s + d2 * (10.0 * s - root) * inv)
}

#[cfg(test)]
mod tests;
