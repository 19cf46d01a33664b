//! Primitive warps from the unit square, each with its density and its inverse.
//!
//! Directions are in a local frame whose +Z is the pole (hemisphere normal or cone axis). Every
//! `sample_*` maps `u ∈ [0,1)²` bijectively (up to measure zero) onto its domain, the matching
//! `*_pdf` is the density with respect to solid angle (or area for the disk), and `invert_*`
//! returns the `u` that produces a given point, so that `invert(sample(u)) = u`.

use core::f64::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI, TAU};
use glam::{DVec2, DVec3};

/// Concentric disk mapping (Shirley & Chiu 1997): square → unit disk, preserving area ratios
/// (density 1/π) and keeping strata compact.
#[inline]
pub fn sample_concentric_disk(u: [f64; 2]) -> DVec2 {
    concentric_disk(u).0
}

/// [`sample_concentric_disk`] with the point's radius `r = max(|2u₀ − 1|, |2u₁ − 1|)`,
/// exactly: the mapping takes the square's ring of half-width r onto the circle of radius r.
#[inline(always)]
fn concentric_disk(u: [f64; 2]) -> (DVec2, f64) {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    if a == 0.0 && b == 0.0 {
        return (DVec2::ZERO, 0.0);
    }
    // θ = π/4 · b/a, or π/2 − π/4 · a/b, whose sine and cosine are those of π/4 · a/b
    // swapped: either way the sine and cosine of an angle in [−π/4, π/4]. Written as selects
    // around one division (the two cases are equally likely, so a branch mispredicts half
    // the time); the same operations as the two branches, so the same bits.
    let wide = a.abs() > b.abs();
    let (num, den) = if wide { (b, a) } else { (a, b) };
    let (s, c) = sin_cos_quarter(FRAC_PI_4 * (num / den));
    let (x, y) = (den * c, den * s);
    let d = if wide {
        DVec2::new(x, y)
    } else {
        DVec2::new(y, x)
    };
    (d, den.abs())
}

/// `(sin x, cos x)` for |x| ≤ π/4 from their Taylor series, through x¹⁵ and x¹⁶: the first
/// terms left out, x¹⁷/17! and x¹⁸/18!, stay below 5·10⁻¹⁷ there, so the result is within 2
/// ulp of `f64::sin_cos` without its argument reduction and library call, which the
/// concentric mapping of every disk, cap and cosine-hemisphere sample paid (a path traced
/// through the Cornell box 4 % faster; BENCHMARKS.md).
#[inline(always)]
fn sin_cos_quarter(x: f64) -> (f64, f64) {
    // (±1/n! for the odd and the even n, as polynomials in x²; plain products and sums,
    // since a `mul_add` without the FMA target feature is a library call)
    const S: [f64; 7] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 1_307_674_368_000.0,
    ];
    const C: [f64; 8] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 20_922_789_888_000.0,
    ];
    // Estrin's scheme (pairs, then pairs of pairs) keeps the chain of dependent operations
    // short.
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let s = (S[0] + S[1] * x2) + x4 * (S[2] + S[3] * x2) + x8 * ((S[4] + S[5] * x2) + x4 * S[6]);
    let c = (C[0] + C[1] * x2)
        + x4 * (C[2] + C[3] * x2)
        + x8 * ((C[4] + C[5] * x2) + x4 * (C[6] + C[7] * x2));
    (x + x * x2 * s, 1.0 + x2 * c)
}

/// Inverse of [`sample_concentric_disk`] for a point of the closed unit disk.
#[inline]
pub fn invert_concentric_disk(p: DVec2) -> [f64; 2] {
    let r = p.length();
    if r == 0.0 {
        return [0.5, 0.5];
    }
    // φ in (−π, π]; the square's four triangular sectors map to the four quarter-turn wedges
    // centred on ±x and ±y.
    let phi = p.y.atan2(p.x);
    let (a, b) = if phi.abs() <= FRAC_PI_4 {
        (r, r * phi / FRAC_PI_4)
    } else if phi.abs() >= 3.0 * FRAC_PI_4 {
        let t = if phi > 0.0 { phi - PI } else { phi + PI };
        (-r, -r * t / FRAC_PI_4)
    } else if phi > 0.0 {
        (r * (FRAC_PI_2 - phi) / FRAC_PI_4, r)
    } else {
        (-r * (-FRAC_PI_2 - phi) / FRAC_PI_4, -r)
    };
    [0.5 * (a + 1.0), 0.5 * (b + 1.0)]
}

/// Uniform hemisphere around +Z: z = u₀, φ = 2πu₁; density 1/(2π).
#[inline]
pub fn sample_uniform_hemisphere(u: [f64; 2]) -> DVec3 {
    let z = u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * u[1]).sin_cos();
    DVec3::new(r * c, r * s, z)
}

/// Density of [`sample_uniform_hemisphere`]: 1/(2π) for z ≥ 0, else 0.
#[inline]
pub fn uniform_hemisphere_pdf(w: DVec3) -> f64 {
    if w.z >= 0.0 { 0.5 * FRAC_1_PI } else { 0.0 }
}

/// Inverse of [`sample_uniform_hemisphere`].
#[inline]
pub fn invert_uniform_hemisphere(w: DVec3) -> [f64; 2] {
    [w.z, azimuth01(w)]
}

/// Uniform sphere: z = 1 − 2u₀, φ = 2πu₁; density 1/(4π).
#[inline]
pub fn sample_uniform_sphere(u: [f64; 2]) -> DVec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * u[1]).sin_cos();
    DVec3::new(r * c, r * s, z)
}

/// Density of [`sample_uniform_sphere`]: 1/(4π).
#[inline]
pub fn uniform_sphere_pdf() -> f64 {
    0.25 * FRAC_1_PI
}

/// Inverse of [`sample_uniform_sphere`].
#[inline]
pub fn invert_uniform_sphere(w: DVec3) -> [f64; 2] {
    [0.5 * (1.0 - w.z), azimuth01(w)]
}

/// Cosine-weighted hemisphere (Malley's method: concentric disk lifted to the hemisphere);
/// density cos θ / π.
#[inline]
pub fn sample_cosine_hemisphere(u: [f64; 2]) -> DVec3 {
    // (the height from the disk point's exact radius, not from its rounded coordinates: no
    // wait for the angle's division and series)
    let (d, r) = concentric_disk(u);
    let z = ((1.0 - r) * (1.0 + r)).max(0.0).sqrt();
    DVec3::new(d.x, d.y, z)
}

/// Density of [`sample_cosine_hemisphere`]: max(cos θ, 0)/π.
#[inline]
pub fn cosine_hemisphere_pdf(w: DVec3) -> f64 {
    w.z.max(0.0) * FRAC_1_PI
}

/// Inverse of [`sample_cosine_hemisphere`] (projects onto the disk, then inverts the disk map).
#[inline]
pub fn invert_cosine_hemisphere(w: DVec3) -> [f64; 2] {
    invert_concentric_disk(DVec2::new(w.x, w.y))
}

/// Uniform cone around +Z with half-angle θmax given by `cos_max`: cos θ = 1 − u₀(1 − cos θmax);
/// density 1/(2π(1 − cos θmax)).
///
/// `one_minus_cos_max` is passed separately so that narrow cones (the sun: θmax ≈ 4.6 mrad)
/// keep full precision; compute it as sin²θmax/(1 + cos θmax) or 2 sin²(θmax/2).
#[inline]
pub fn sample_uniform_cone(u: [f64; 2], one_minus_cos_max: f64) -> DVec3 {
    let omc = u[0] * one_minus_cos_max;
    let z = 1.0 - omc;
    // sin²θ = (1 − cos θ)(1 + cos θ), exact for tiny angles.
    let r = (omc * (2.0 - omc)).max(0.0).sqrt();
    let (s, c) = (TAU * u[1]).sin_cos();
    DVec3::new(r * c, r * s, z)
}

/// Density of [`sample_uniform_cone`]: 1/(2π(1 − cos θmax)) inside the cone, 0 outside.
#[inline]
pub fn uniform_cone_pdf(w: DVec3, one_minus_cos_max: f64) -> f64 {
    if 1.0 - w.z <= one_minus_cos_max {
        1.0 / (TAU * one_minus_cos_max)
    } else {
        0.0
    }
}

/// Inverse of [`sample_uniform_cone`].
#[inline]
pub fn invert_uniform_cone(w: DVec3, one_minus_cos_max: f64) -> [f64; 2] {
    // 1 − cos θ = sin²θ/(1 + cos θ) keeps precision near the axis.
    let s2 = w.x * w.x + w.y * w.y;
    let omc = s2 / (1.0 + w.z);
    [omc / one_minus_cos_max, azimuth01(w)]
}

/// Azimuth of `w` mapped to \[0, 1): atan2(y, x)/(2π) wrapped.
#[inline]
fn azimuth01(w: DVec3) -> f64 {
    let mut t = w.y.atan2(w.x) / TAU;
    if t < 0.0 {
        t += 1.0;
    }
    if t >= 1.0 { 0.0 } else { t }
}

/// Samples x ∈ \[0,1\] with density proportional to the linear function lerp(x, a, b), a, b ≥ 0,
/// a + b > 0 (inverse CDF of the trapezoid).
#[inline]
pub fn sample_linear(u: f64, a: f64, b: f64) -> f64 {
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    // Stable root of (b − a)/2·x² + a·x − u(a + b)/2 = 0.
    let x = u * (a + b) / (a + (crate::lerp(u, a * a, b * b)).sqrt());
    x.min(1.0)
}

/// Density of [`sample_linear`]: 2·lerp(x, a, b)/(a + b) on \[0,1\].
#[inline]
pub fn linear_pdf(x: f64, a: f64, b: f64) -> f64 {
    if !(0.0..=1.0).contains(&x) {
        return 0.0;
    }
    2.0 * crate::lerp(x, a, b) / (a + b)
}

/// Inverse of [`sample_linear`]: the CDF x((2 − x)a + x·b)/(a + b).
#[inline]
pub fn invert_linear(x: f64, a: f64, b: f64) -> f64 {
    x * (a * (2.0 - x) + b * x) / (a + b)
}

/// Samples the unit square with density proportional to the bilinear interpolation of the corner
/// weights `w = [w00, w10, w01, w11]` (index = x + 2y), all ≥ 0 with a positive sum
/// (Hart et al. 2020, "Practical product sampling by fitting and composing warps", §4).
/// The y coordinate is drawn from its linear marginal, then x from the conditional.
#[inline]
pub fn sample_bilinear(u: [f64; 2], w: [f64; 4]) -> [f64; 2] {
    let y = sample_linear(u[1], w[0] + w[1], w[2] + w[3]);
    let x = sample_linear(u[0], crate::lerp(y, w[0], w[2]), crate::lerp(y, w[1], w[3]));
    [x, y]
}

/// Density of [`sample_bilinear`]: 4·bilerp(p)/(w00 + w10 + w01 + w11).
#[inline]
pub fn bilinear_pdf(p: [f64; 2], w: [f64; 4]) -> f64 {
    if !(0.0..=1.0).contains(&p[0]) || !(0.0..=1.0).contains(&p[1]) {
        return 0.0;
    }
    let [x, y] = p;
    let v =
        (1.0 - x) * (1.0 - y) * w[0] + x * (1.0 - y) * w[1] + (1.0 - x) * y * w[2] + x * y * w[3];
    4.0 * v / (w[0] + w[1] + w[2] + w[3])
}

/// Inverse of [`sample_bilinear`].
#[inline]
pub fn invert_bilinear(p: [f64; 2], w: [f64; 4]) -> [f64; 2] {
    let [x, y] = p;
    [
        invert_linear(x, crate::lerp(y, w[0], w[2]), crate::lerp(y, w[1], w[3])),
        invert_linear(y, w[0] + w[1], w[2] + w[3]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
        (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol
    }

    /// The series agrees with `f64::sin_cos` within 2 ulp of 1 over [−π/4, π/4] (2¹⁸ + 1
    /// evenly spaced angles, the ends included), and is odd/even exactly.
    #[test]
    fn quarter_sin_cos_matches_the_library() {
        let n = 1 << 17;
        let mut worst = 0.0f64;
        for i in -n..=n {
            let x = FRAC_PI_4 * i as f64 / n as f64;
            let (s, c) = sin_cos_quarter(x);
            let (ls, lc) = x.sin_cos();
            worst = worst.max((s - ls).abs()).max((c - lc).abs());
            assert_eq!(sin_cos_quarter(-x), (-s, c));
        }
        assert!(worst <= 2.0 * f64::EPSILON, "worst {worst:e}");
        assert_eq!(sin_cos_quarter(0.0), (0.0, 1.0));
    }

    proptest! {
        #[test]
        fn disk_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let p = sample_concentric_disk([u0, u1]);
            prop_assert!(p.length() <= 1.0 + 1e-12);
            prop_assert!(close(invert_concentric_disk(p), [u0, u1], 1e-9));
        }

        #[test]
        fn hemisphere_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let w = sample_uniform_hemisphere([u0, u1]);
            prop_assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0);
            prop_assert!(close(invert_uniform_hemisphere(w), [u0, u1], 1e-9));
        }

        #[test]
        fn sphere_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let w = sample_uniform_sphere([u0, u1]);
            prop_assert!((w.length() - 1.0).abs() < 1e-12);
            prop_assert!(close(invert_uniform_sphere(w), [u0, u1], 1e-9));
        }

        /// The radius the cosine hemisphere lifts by is the disk point's own.
        #[test]
        fn concentric_radius_is_the_points(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let (d, r) = concentric_disk([u0, u1]);
            prop_assert!((d.length() - r).abs() <= 2.0 * f64::EPSILON);
            prop_assert_eq!(r, (2.0 * u0 - 1.0).abs().max((2.0 * u1 - 1.0).abs()));
        }

        #[test]
        fn cosine_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let w = sample_cosine_hemisphere([u0, u1]);
            prop_assert!((w.length() - 1.0).abs() < 1e-12);
            prop_assert!(close(invert_cosine_hemisphere(w), [u0, u1], 1e-7));
        }

        #[test]
        fn cone_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64, t in 1e-4..3.0f64) {
            let omc = 2.0 * (0.5 * t).sin().powi(2);
            let w = sample_uniform_cone([u0, u1], omc);
            prop_assert!((w.length() - 1.0).abs() < 1e-12);
            prop_assert!(uniform_cone_pdf(w, omc * (1.0 + 1e-12)) > 0.0);
            let back = invert_uniform_cone(w, omc);
            prop_assert!((back[0] - u0).abs() < 1e-7);
        }

        #[test]
        fn bilinear_roundtrip(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64,
                              a in 0.01..2.0f64, b in 0.01..2.0f64, c in 0.01..2.0f64, d in 0.01..2.0f64) {
            let w = [a, b, c, d];
            let p = sample_bilinear([u0, u1], w);
            prop_assert!(close(invert_bilinear(p, w), [u0, u1], 1e-9));
        }
    }

    /// ∫ pdf over the domain is 1 (midpoint rule on a fine θ×φ grid).
    #[test]
    fn densities_integrate_to_one() {
        let n = 400;
        let (mut hemi, mut cos, mut cone) = (0.0, 0.0, 0.0);
        let omc = 1.0 - 0.3f64.cos();
        for i in 0..n {
            let theta = (i as f64 + 0.5) / n as f64 * PI;
            let w = DVec3::new(theta.sin(), 0.0, theta.cos());
            let dw = TAU * theta.sin() * PI / n as f64;
            hemi += uniform_hemisphere_pdf(w) * dw;
            cos += cosine_hemisphere_pdf(w) * dw;
            cone += uniform_cone_pdf(w, omc) * dw;
        }
        assert!((hemi - 1.0).abs() < 1e-4, "{hemi}");
        assert!((cos - 1.0).abs() < 1e-4, "{cos}");
        // The cone edge falls between grid nodes: tolerance is one θ cell of the cap.
        assert!((cone - 1.0).abs() < 0.03, "{cone}");
    }

    #[test]
    fn linear_pdf_integrates_and_matches_histogram() {
        let (a, b) = (0.2, 1.7);
        let mut hist = [0usize; 10];
        let n = 100_000;
        for i in 0..n {
            let x = sample_linear((i as f64 + 0.5) / n as f64, a, b);
            hist[((x * 10.0) as usize).min(9)] += 1;
        }
        for (k, &h) in hist.iter().enumerate() {
            // Exact bin mass from the CDF (stratified u ⇒ counts equal it up to ±1).
            let m =
                invert_linear((k + 1) as f64 / 10.0, a, b) - invert_linear(k as f64 / 10.0, a, b);
            assert!(
                (h as f64 - m * n as f64).abs() <= 1.5,
                "bin {k}: {h} vs {}",
                m * n as f64
            );
        }
        assert!((linear_pdf(0.0, a, b) - 2.0 * a / (a + b)).abs() < 1e-15);
    }
}
