//! Shared statistical machinery for the lux-sample tests and the `variance` example:
//! a Mitsuba-style χ² goodness-of-fit test on a spherical-cap histogram, the regularised
//! incomplete gamma function for its p-value, closed-form irradiance references, and the
//! variance-ratio configurations of issue 5.
#![allow(dead_code)]

use glam::{DMat4, DVec3};
use lux_math::Frame;
use lux_sample::*;
use std::f64::consts::{PI, TAU};

// The χ² p-value: `lux_sample::stats`.
#[allow(unused_imports)] // (not every test crate that includes this module uses all three)
pub use lux_sample::stats::{chi2_p_value, gamma_q, ln_gamma};

// ---------------------------------------------------------------------------------------------
// χ² histogram test.

/// A spherical cap {ω : ω·axis ≥ cos_min} split into `nt` rings of equal cos-width and `np`
/// azimuth sectors (all bins have equal solid angle).
#[derive(Clone, Copy, Debug)]
pub struct Cap {
    pub axis: DVec3,
    pub cos_min: f64,
    pub nt: usize,
    pub np: usize,
}

impl Cap {
    /// The cap around the direction from `p` to a bounding sphere (centre, radius), with some
    /// margin; the whole sphere when `p` is near or inside.
    pub fn around(p: DVec3, centre: DVec3, radius: f64, nt: usize, np: usize) -> Self {
        let v = centre - p;
        let d = v.length();
        let axis = v / d;
        let cos_min = if d > 1.05 * radius {
            let a = (radius / d).asin() * 1.15 + 1e-3;
            if a < PI { a.cos() } else { -1.0 }
        } else {
            -1.0
        };
        Self {
            axis,
            cos_min,
            nt,
            np,
        }
    }

    pub fn whole_sphere(axis: DVec3, nt: usize, np: usize) -> Self {
        Self {
            axis,
            cos_min: -1.0,
            nt,
            np,
        }
    }

    pub fn bin(&self, frame: &Frame, w: DVec3) -> Option<usize> {
        let l = frame.to_local(w);
        if l.z < self.cos_min {
            return None;
        }
        let t = ((1.0 - l.z) / (1.0 - self.cos_min) * self.nt as f64) as usize;
        let mut ph = l.y.atan2(l.x) / TAU;
        if ph < 0.0 {
            ph += 1.0;
        }
        let p = ((ph * self.np as f64) as usize).min(self.np - 1);
        Some(t.min(self.nt - 1) * self.np + p)
    }

    /// ∫ f dω over bin (t, p) by the midpoint rule on k×k sub-cells (in cos θ and φ).
    fn integrate_bin(
        &self,
        frame: &Frame,
        f: &dyn Fn(DVec3) -> f64,
        t: usize,
        p: usize,
        k: usize,
    ) -> f64 {
        let dc = (1.0 - self.cos_min) / self.nt as f64;
        let dp = TAU / self.np as f64;
        let mut s = 0.0;
        for i in 0..k {
            let c = 1.0 - (t as f64 + (i as f64 + 0.5) / k as f64) * dc;
            let sn = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..k {
                let ph = (p as f64 + (j as f64 + 0.5) / k as f64) * dp;
                let w = frame.to_world(DVec3::new(sn * ph.cos(), sn * ph.sin(), c));
                s += f(w);
            }
        }
        s * dc * dp / (k * k) as f64
    }

    /// ∫ f dω per bin with k×k midpoints.
    pub fn integrate(&self, f: &dyn Fn(DVec3) -> f64, k: usize) -> Vec<f64> {
        let frame = Frame::from_normal(self.axis);
        let mut out = vec![0.0; self.nt * self.np];
        for t in 0..self.nt {
            for p in 0..self.np {
                out[t * self.np + p] = self.integrate_bin(&frame, f, t, p, k);
            }
        }
        out
    }

    /// ∫ f dω per bin, adaptively: 8×8 midpoints, refined to 48×48 where the 4×4 and 8×8
    /// results differ by more than `tol` (silhouette bins, where f is discontinuous).
    pub fn integrate_adaptive(&self, f: &dyn Fn(DVec3) -> f64, tol: f64) -> Vec<f64> {
        let frame = Frame::from_normal(self.axis);
        let mut out = vec![0.0; self.nt * self.np];
        for t in 0..self.nt {
            for p in 0..self.np {
                let a = self.integrate_bin(&frame, f, t, p, 4);
                let b = self.integrate_bin(&frame, f, t, p, 8);
                out[t * self.np + p] = if (a - b).abs() > tol {
                    self.integrate_bin(&frame, f, t, p, 48)
                } else {
                    b
                };
            }
        }
        out
    }
}

/// Outcome of a χ² test.
#[derive(Debug)]
pub struct Chi2 {
    pub p_value: f64,
    pub chi2: f64,
    pub dof: usize,
    /// ∫ pdf over the cap (numerical).
    pub mass: f64,
    /// Fraction of samples returning `None` or landing outside the cap.
    pub miss: f64,
}

/// The i-th point of the R2 low-discrepancy sequence (Roberts 2018): frac(½ + i·(1/g, 1/g²))
/// with g the plastic number. Used for quadrature: no alignment with the histogram bins.
#[inline]
pub fn r2(i: usize) -> (f64, f64) {
    const G: f64 = 1.324_717_957_244_746;
    let x = (0.5 + i as f64 / G).fract();
    let y = (0.5 + i as f64 / (G * G)).fract();
    (x, y)
}

/// Expected bin probabilities by quasi-Monte-Carlo quadrature of `pdf` over the cap with
/// `m` R2 points (the bins are rectangles in the cap's (cos θ, φ) square, so each receives its
/// share of points up to O(log m); used for lights at infinity).
pub fn expected_directions(cap: &Cap, pdf: &dyn Fn(DVec3) -> f64, m: usize) -> Vec<f64> {
    let frame = Frame::from_normal(cap.axis);
    let mut out = vec![0.0; cap.nt * cap.np];
    let w = (1.0 - cap.cos_min) * TAU / m as f64;
    for i in 0..m {
        let (s, t) = r2(i);
        let c = 1.0 - s * (1.0 - cap.cos_min);
        let sn = (1.0 - c * c).max(0.0).sqrt();
        let ph = TAU * t;
        let d = frame.to_world(DVec3::new(sn * ph.cos(), sn * ph.sin(), c));
        if let Some(b) = cap.bin(&frame, d) {
            out[b] += pdf(d) * w;
        }
    }
    out
}

/// Expected bin probabilities by quadrature over the light's **surface**: `m` R2 points over a
/// parametrisation (s, t) ↦ (point q, unit normal, dA/(ds dt)) (None = not visible from `p`),
/// each contributing pdf(ω)·cos θₗ/d²·dA to the bin of ω = (q − p)/d. pdf_ω·cos θₗ/d² is the
/// area density, which stays bounded where the direction-space pdf is singular (area sampling
/// at silhouettes) or concentrated (slivers seen edge-on).
pub fn expected_surface(
    cap: &Cap,
    p: DVec3,
    m: usize,
    surface: &dyn Fn(f64, f64) -> Option<(DVec3, DVec3, f64)>,
    pdf: &dyn Fn(DVec3) -> f64,
) -> Vec<f64> {
    let frame = Frame::from_normal(cap.axis);
    let mut out = vec![0.0; cap.nt * cap.np];
    let cell = 1.0 / m as f64;
    for i in 0..m {
        let (s, t) = r2(i);
        let Some((q, nrm, jac)) = surface(s, t) else {
            continue;
        };
        let v = q - p;
        let d2 = v.length_squared();
        let w = v / d2.sqrt();
        let cos = nrm.dot(w).abs();
        if let Some(b) = cap.bin(&frame, w) {
            out[b] += pdf(w) * cos / d2 * jac * cell;
        }
    }
    out
}

/// Draws `n` samples, histograms their directions on `cap`, and compares with `n·expected`.
/// Bins expecting < 5 samples are pooled; the samples that failed or fell outside the cap form
/// one more bin whose expectation is n·(1 − Σ expected).
pub fn chi2_test(
    cap: Cap,
    n: usize,
    seed: u64,
    sample: &dyn Fn([f64; 2]) -> Option<DVec3>,
    expected: &[f64],
) -> Chi2 {
    let frame = Frame::from_normal(cap.axis);
    let mut obs = vec![0.0f64; cap.nt * cap.np];
    let mut other = 0.0;
    let mut rng = SplitMix64::new(seed);
    for _ in 0..n {
        match sample(rng.next_2d()).and_then(|w| cap.bin(&frame, w)) {
            Some(b) => obs[b] += 1.0,
            None => other += 1.0,
        }
    }
    let mass: f64 = expected.iter().sum();
    let mut cells: Vec<(f64, f64)> = obs
        .iter()
        .zip(expected)
        .map(|(&o, &e)| (o, e * n as f64))
        .collect();
    cells.push((other, ((1.0 - mass) * n as f64).max(0.0)));
    let (mut po, mut pe) = (0.0, 0.0);
    let mut chi2 = 0.0;
    let mut used = 0;
    for (o, e) in cells {
        if e < 5.0 {
            po += o;
            pe += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            used += 1;
        }
    }
    if pe >= 5.0 {
        chi2 += (po - pe) * (po - pe) / pe;
        used += 1;
    } else if po > 20.0 {
        // Many samples where the pdf says there should be none: fail loudly.
        chi2 += (po - pe) * (po - pe) / pe.max(1.0);
        used += 1;
    }
    let dof = used.max(2) - 1;
    Chi2 {
        p_value: chi2_p_value(chi2, dof),
        chi2,
        dof,
        mass,
        miss: other / n as f64,
    }
}

/// Significance level: reject when p < 1e-4 (with ~40 χ² tests in the suite, a false alarm
/// has probability ~0.4 % over the whole suite; seeds are fixed, so results are reproducible).
pub const ALPHA: f64 = 1e-4;

/// Runs the χ² test of `light` from `r` against `expected` bin probabilities and asserts
/// acceptance; also checks that the `pdf` reported by each sample equals `light.pdf(wi)`.
pub fn check_light(
    name: &str,
    light: &Light,
    r: &Reference,
    cap: Cap,
    n: usize,
    expected: &[f64],
) -> Chi2 {
    let res = chi2_test(
        cap,
        n,
        0x5eed ^ n as u64,
        &|u| light.sample(r, u).map(|s| s.wi),
        expected,
    );
    assert!(
        res.p_value > ALPHA,
        "{name}: χ² rejected: p = {:.3e}, χ² = {:.1}, dof = {}, mass = {:.5}, miss = {:.5}",
        res.p_value,
        res.chi2,
        res.dof,
        res.mass,
        res.miss
    );
    let mut rng = SplitMix64::new(99);
    let mut checked = 0;
    for _ in 0..20_000 {
        let u = rng.next_2d();
        if let Some(s) = light.sample(r, u) {
            // Meshes: a direction may cross several triangles; the sample's pdf is the density
            // of (direction, triangle), which is what `pdf_triangle` returns.
            let p = match light {
                Light::Mesh(m) => {
                    let (_, tri) = m.sample_with_index(r, u).unwrap();
                    m.pdf_triangle(r, tri, s.wi)
                }
                _ => light.pdf(r, s.wi),
            };
            // Grazing directions (pdf > 10³ sr⁻¹) lose digits in the ill-conditioned
            // ray–surface intersection; elsewhere the two must agree to 1e-6.
            let tol = if s.pdf > 1e3 { 1e-4 } else { 1e-6 };
            assert!(
                (p - s.pdf).abs() <= tol * s.pdf,
                "{name}: sample pdf {} vs pdf(wi) {} at wi = {:?}",
                s.pdf,
                p,
                s.wi
            );
            assert!((s.wi.length() - 1.0).abs() < 1e-12);
            if s.distance.is_finite() {
                assert!((r.p + s.wi * s.distance - s.point).length() < 1e-9 * (1.0 + s.distance));
            }
            checked += 1;
        }
    }
    assert!(
        checked > 100,
        "{name}: too few successful samples ({checked})"
    );
    res
}

// ---------------------------------------------------------------------------------------------
// Surface parametrisations of the light shapes (world point, world unit normal, dA/(ds dt)).

fn area_jacobian(m: &LightTransform, n_local: DVec3) -> (DVec3, f64) {
    let nt = m.linear().inverse().transpose() * n_local;
    (nt.normalize(), m.abs_det() * nt.length())
}

pub fn rect_surface(
    w: f64,
    h: f64,
    m: LightTransform,
) -> impl Fn(f64, f64) -> Option<(DVec3, DVec3, f64)> {
    move |s, t| {
        let (n, j) = area_jacobian(&m, DVec3::NEG_Z);
        Some((
            m.point(DVec3::new((s - 0.5) * w, (t - 0.5) * h, 0.0)),
            n,
            j * w * h,
        ))
    }
}

pub fn disk_surface(r: f64, m: LightTransform) -> impl Fn(f64, f64) -> Option<(DVec3, DVec3, f64)> {
    move |s, t| {
        let (n, j) = area_jacobian(&m, DVec3::NEG_Z);
        let rr = r * s.sqrt();
        let (sn, c) = (TAU * t).sin_cos();
        Some((m.point(DVec3::new(rr * c, rr * sn, 0.0)), n, j * PI * r * r))
    }
}

/// Front-facing part of a sphere seen from `p` (all of it from inside).
pub fn sphere_surface(
    r: f64,
    m: LightTransform,
    p: DVec3,
) -> impl Fn(f64, f64) -> Option<(DVec3, DVec3, f64)> {
    let inside = m.inv_point(p).length() <= r;
    move |s, t| {
        let z = 1.0 - 2.0 * s;
        let rho = (1.0 - z * z).max(0.0).sqrt();
        let (sn, c) = (TAU * t).sin_cos();
        let nl = DVec3::new(rho * c, rho * sn, z);
        let q = m.point(nl * r);
        let (n, j) = area_jacobian(&m, nl);
        (inside || n.dot(p - q) > 0.0).then_some((q, n, j * 4.0 * PI * r * r))
    }
}

/// Front-facing part of a cylinder's lateral surface.
pub fn cylinder_surface(
    r: f64,
    len: f64,
    m: LightTransform,
    p: DVec3,
) -> impl Fn(f64, f64) -> Option<(DVec3, DVec3, f64)> {
    move |s, t| {
        let (sn, c) = (TAU * t).sin_cos();
        let nl = DVec3::new(0.0, c, sn);
        let q = m.point(DVec3::new((s - 0.5) * len, r * c, r * sn));
        let (n, j) = area_jacobian(&m, nl);
        (n.dot(p - q) > 0.0).then_some((q, n, j * TAU * r * len))
    }
}

/// A world-space triangle.
pub fn triangle_surface(v: [DVec3; 3]) -> impl Fn(f64, f64) -> Option<(DVec3, DVec3, f64)> {
    let nn = (v[1] - v[0]).cross(v[2] - v[0]);
    let area = 0.5 * nn.length();
    move |s, t| {
        let sq = s.sqrt();
        let (b0, b1) = (1.0 - sq, t * sq);
        Some((
            b0 * v[0] + b1 * v[1] + (1.0 - b0 - b1) * v[2],
            nn.normalize(),
            area,
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Closed-form irradiance.

/// Irradiance at `p` (normal `n`) from a uniform Lambertian polygon of radiance 1 fully above
/// the horizon: E = ½ Σ Θᵢ (n · Γᵢ), Θᵢ the angle between consecutive vertex directions and Γᵢ
/// the unit normal of their great-circle plane (Lambert's formula).
pub fn polygon_irradiance(p: DVec3, n: DVec3, verts: &[DVec3]) -> f64 {
    let m = verts.len();
    let mut s = 0.0;
    for i in 0..m {
        let a = (verts[i] - p).normalize();
        let b = (verts[(i + 1) % m] - p).normalize();
        let c = a.cross(b);
        let theta = c.length().atan2(a.dot(b));
        s += theta * n.dot(c.normalize());
    }
    0.5 * s.abs()
}

/// Monte-Carlo irradiance from a light of unit radiance: mean and standard error of
/// max(0, n·wi)/pdf over `n` samples (failed samples count as 0).
pub fn mc_irradiance(light: &Light, r: &Reference, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let v = light
            .sample(r, rng.next_2d())
            .map_or(0.0, |ls| r.n.dot(ls.wi).max(0.0) / ls.pdf);
        s += v;
        s2 += v * v;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

/// Per-sample variance of the irradiance estimator.
pub fn estimator_variance(light: &Light, r: &Reference, n: usize, seed: u64) -> (f64, f64) {
    let (mean, se) = mc_irradiance(light, r, n, seed);
    (mean, se * se * n as f64)
}

pub fn xf(m: DMat4) -> LightTransform {
    LightTransform::new(m).unwrap()
}

/// A transform with non-uniform scale and shear plus a rotation and translation.
pub fn skewed(t: DVec3) -> DMat4 {
    let shear = DMat4::from_cols_array(&[
        1.3, 0.0, 0.0, 0.0, 0.4, 0.8, 0.0, 0.0, 0.0, 0.2, 1.1, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    DMat4::from_translation(t) * DMat4::from_rotation_x(0.3) * shear
}

// ---------------------------------------------------------------------------------------------
// Variance-ratio configurations of issue 5: receiver at the origin facing +Z, light above.

pub struct RatioCase {
    pub name: &'static str,
    pub area: Light,
    pub better: Vec<(&'static str, Light)>,
}

pub fn ratio_cases() -> Vec<RatioCase> {
    let up = |h: f64| xf(DMat4::from_translation(DVec3::new(0.0, 0.0, h)));
    let rect = |h: f64, t| Light::Rect(RectLight::new(1.0, 1.0, up(h), t).unwrap());
    let rect_off = |t| {
        let m = xf(DMat4::from_translation(DVec3::new(0.6, 0.0, 0.25)));
        Light::Rect(RectLight::new(1.0, 1.0, m, t).unwrap())
    };
    let cyl = |t| Light::Cylinder(CylinderLight::new(0.5, 1.0, up(1.0), t).unwrap());
    vec![
        RatioCase {
            name: "rect 1x1 at 0.25",
            area: rect(0.25, RectTechnique::Area),
            better: vec![
                (
                    "spherical rectangle",
                    rect(0.25, RectTechnique::SphericalRectangle),
                ),
                (
                    "spherical rectangle + cosine warp",
                    rect(0.25, RectTechnique::SphericalRectangleCosine),
                ),
            ],
        },
        RatioCase {
            name: "rect 1x1 at 1",
            area: rect(1.0, RectTechnique::Area),
            better: vec![
                (
                    "spherical rectangle",
                    rect(1.0, RectTechnique::SphericalRectangle),
                ),
                (
                    "spherical rectangle + cosine warp",
                    rect(1.0, RectTechnique::SphericalRectangleCosine),
                ),
            ],
        },
        RatioCase {
            // Extra (not in the issue): receiver off-centre, where the corner cosines differ and
            // the bilinear cosine warp has something to fit.
            name: "rect 1x1 at 0.25, off 0.6",
            area: rect_off(RectTechnique::Area),
            better: vec![
                (
                    "spherical rectangle",
                    rect_off(RectTechnique::SphericalRectangle),
                ),
                (
                    "spherical rectangle + cosine warp",
                    rect_off(RectTechnique::SphericalRectangleCosine),
                ),
            ],
        },
        RatioCase {
            name: "sphere r=0.5 at 1.5",
            area: Light::Sphere(SphereLight::new(0.5, up(1.5), SphereTechnique::Area).unwrap()),
            better: vec![(
                "cone",
                Light::Sphere(SphereLight::new(0.5, up(1.5), SphereTechnique::Cone).unwrap()),
            )],
        },
        RatioCase {
            name: "disk r=0.5 at 0.5",
            area: Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::Area).unwrap()),
            better: vec![
                (
                    "elliptic cone",
                    Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::EllipticCone).unwrap()),
                ),
                (
                    "polar chord",
                    Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::PolarChord).unwrap()),
                ),
            ],
        },
        RatioCase {
            name: "cylinder r=0.5 L=1 at 1",
            area: cyl(CylinderTechnique::Area),
            better: vec![
                ("visible area", cyl(CylinderTechnique::VisibleArea)),
                ("solid angle", cyl(CylinderTechnique::SolidAngle)),
            ],
        },
    ]
}

/// The receiver of the variance-ratio cases.
pub fn ratio_receiver() -> Reference {
    Reference::surface(DVec3::ZERO, DVec3::Z)
}
