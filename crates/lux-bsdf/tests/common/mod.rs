//! Shared helpers of the statistical tests: a small deterministic RNG, closure builders,
//! the furnace estimator and the chi-square test of `sample` against `pdf`.
#![allow(dead_code)]

use glam::{DVec2, DVec3};
use lux_bsdf::*;
use std::f64::consts::PI;

/// SplitMix64: deterministic, good enough for tests.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

pub fn frame() -> Frame {
    Frame::new(DVec3::Z, DVec3::X)
}

/// `wo` at `theta` degrees from the normal, azimuth `phi` degrees.
pub fn dir(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

pub fn single(c: Closure, wo: DVec3) -> Bsdf {
    let mut b = Bsdf::new(wo, DVec3::Z, true, false);
    b.push(Node::Closure(c)).unwrap();
    b
}

pub fn lambert(color: DVec3) -> Closure {
    Closure::OrenNayar {
        weight: 1.0,
        color,
        roughness: 0.0,
        energy_compensation: false,
        frame: frame(),
    }
}

pub fn conductor(ior: DVec3, k: DVec3, a: DVec2) -> Closure {
    Closure::Conductor {
        weight: 1.0,
        ior,
        extinction: k,
        alpha: a,
        retroreflective: false,
        thinfilm: ThinFilm::default(),
        frame: frame(),
    }
}

pub fn dielectric(ior: f64, a: DVec2, mode: ScatterMode) -> Closure {
    Closure::Dielectric {
        weight: 1.0,
        tint: DVec3::ONE,
        ior,
        alpha: a,
        retroreflective: false,
        thinfilm: ThinFilm::default(),
        mode,
        frame: frame(),
    }
}

pub fn schlick(color0: DVec3, color82: DVec3, a: DVec2, mode: ScatterMode) -> Closure {
    Closure::GeneralizedSchlick {
        weight: 1.0,
        color0,
        color82,
        color90: DVec3::ONE,
        exponent: 5.0,
        alpha: a,
        retroreflective: false,
        thinfilm: ThinFilm::default(),
        mode,
        frame: frame(),
    }
}

fn uniform_sphere(u: [f64; 2]) -> DVec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let p = 2.0 * PI * u[1];
    DVec3::new(r * p.cos(), r * p.sin(), z)
}

/// `∫ eval(ωi) dωi` over the sphere by defensive importance sampling: half the samples
/// uniform on the sphere (stratified), half from `Bsdf::sample`, each weighted by
/// `eval / (½ · 1/(4π) + ½ · pdf)`. Unbiased whenever `pdf` is `sample`'s density (checked
/// separately by the chi-square tests) and covers the sphere through its uniform half.
/// Returns the mean and its standard error per channel.
pub fn furnace(b: &Bsdf, n: usize, seed: u64) -> (DVec3, DVec3) {
    let mut rng = Rng(seed);
    let side = (n as f64).sqrt() as usize;
    let n = side * side;
    let mut sum = DVec3::ZERO;
    let mut sum2 = DVec3::ZERO;
    for k in 0..n {
        // Stratified uniform part paired with a BSDF sample (pairs are i.i.d. across strata
        // up to the stratification, which only lowers the variance the error estimate sees).
        let (i, j) = (k / side, k % side);
        let u = [
            (i as f64 + rng.next()) / side as f64,
            (j as f64 + rng.next()) / side as f64,
        ];
        let wu = uniform_sphere(u);
        let mix = |w: DVec3| 0.5 / (4.0 * PI) + 0.5 * b.pdf(w);
        let e = b.eval(wu);
        let mut v = (e.diffuse + e.specular) / mix(wu);
        if let Some(s) = b.sample(rng.next(), [rng.next(), rng.next()])
            && s.kind != LobeKind::Specular
        {
            let e = b.eval(s.wi);
            v += (e.diffuse + e.specular) / mix(s.wi);
        }
        let v = v * 0.5;
        sum += v;
        sum2 += v * v;
    }
    let m = sum / n as f64;
    let var = (sum2 / n as f64 - m * m).max(DVec3::ZERO);
    (m, (var / n as f64).map(f64::sqrt))
}

/// Furnace including the delta lobes: the non-delta integral plus the delta lobes' expected
/// sampled weight (`E[weight · 1_delta]`).
pub fn furnace_with_delta(b: &Bsdf, n: usize, seed: u64) -> (DVec3, DVec3) {
    let (m, se) = furnace(b, n, seed);
    let mut rng = Rng(seed ^ 0xABCD);
    let mut s = DVec3::ZERO;
    let mut s2 = DVec3::ZERO;
    for _ in 0..n {
        let v = match b.sample(rng.next(), [rng.next(), rng.next()]) {
            Some(x) if x.kind == LobeKind::Specular => x.weight,
            _ => DVec3::ZERO,
        };
        s += v;
        s2 += v * v;
    }
    let md = s / n as f64;
    let vd = (s2 / n as f64 - md * md).max(DVec3::ZERO) / n as f64;
    (m + md, (se * se + vd).map(f64::sqrt))
}

/// Regularized upper incomplete gamma `Q(a, x)` (series / continued fraction, Numerical
/// Recipes' scheme written out).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    fn ln_gamma(x: f64) -> f64 {
        let c = [
            76.18009172947146,
            -86.50532032941677,
            24.01409824083091,
            -1.231739572450155,
            0.1208650973866179e-2,
            -0.5395239384953e-5,
        ];
        let mut y = x;
        let t = x + 5.5;
        let t = t - (x + 0.5) * t.ln();
        let mut s = 1.000000000190015;
        for ci in c {
            y += 1.0;
            s += ci / y;
        }
        -t + (2.5066282746310005 * s / x).ln()
    }
    if x <= 0.0 {
        return 1.0;
    }
    if x < a + 1.0 {
        let mut sum = 1.0 / a;
        let mut del = sum;
        let mut ap = a;
        for _ in 0..1000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - ln_gamma(a)).exp()
    } else {
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / 1e-300;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < 1e-300 {
                d = 1e-300;
            }
            c = b + an / c;
            if c.abs() < 1e-300 {
                c = 1e-300;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - ln_gamma(a)).exp() * h
    }
}

pub struct Chi2 {
    pub p_value: f64,
    pub dof: usize,
    /// `∫ pdf` over the sphere.
    pub pdf_integral: f64,
    /// Fraction of samples that were delta lobes.
    pub delta_fraction: f64,
    /// Fraction of `None` samples.
    pub none_fraction: f64,
    /// Largest relative mismatch of a returned sample's `pdf` / `weight` against
    /// `Bsdf::pdf` / `eval/pdf`.
    pub max_consistency_error: f64,
}

/// Chi-square test of `Bsdf::sample`'s non-delta directions against `Bsdf::pdf`, on a grid of
/// `nt × np` bins in `(cos θ, φ)` about the world y axis; the bins' expected counts integrate the
/// pdf with a `sub × sub` midpoint rule; bins expecting fewer than 5 are pooled, and one
/// extra bin holds the delta and failed samples (expected: `n` minus the pdf's integral).
pub fn chi2(b: &Bsdf, n: usize, seed: u64) -> Chi2 {
    let (nt, np, sub) = (24usize, 48usize, 12usize);
    let mut obs = vec![0.0f64; nt * np + 1];
    let mut rng = Rng(seed);
    let mut deltas = 0usize;
    let mut nones = 0usize;
    let mut max_err: f64 = 0.0;
    for _ in 0..n {
        match b.sample(rng.next(), [rng.next(), rng.next()]) {
            None => {
                nones += 1;
                obs[nt * np] += 1.0;
            }
            Some(s) if s.kind == LobeKind::Specular => {
                deltas += 1;
                obs[nt * np] += 1.0;
            }
            Some(s) => {
                // Bins about the y axis, so that no lobe of a `wo` in the xz-plane sits on a pole.
                let z = s.wi.y.clamp(-1.0, 1.0);
                let ti = (((1.0 - z) / 2.0 * nt as f64) as usize).min(nt - 1);
                let mut phi = s.wi.x.atan2(s.wi.z);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                let pi = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
                obs[ti * np + pi] += 1.0;
                let p = b.pdf(s.wi);
                let e = b.eval(s.wi);
                let w = (e.diffuse + e.specular) / p;
                max_err = max_err.max((s.pdf - p).abs() / p);
                max_err =
                    max_err.max((s.weight - w).abs().max_element() / w.max_element().max(1e-12));
            }
        }
    }
    let mut exp = vec![0.0f64; nt * np + 1];
    let mut total = 0.0;
    for ti in 0..nt {
        for pi in 0..np {
            let cell = |sub: usize| {
                let mut acc = 0.0;
                for a in 0..sub {
                    let z = 1.0 - 2.0 * (ti as f64 + (a as f64 + 0.5) / sub as f64) / nt as f64;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    for c in 0..sub {
                        let phi =
                            2.0 * PI * (pi as f64 + (c as f64 + 0.5) / sub as f64) / np as f64;
                        acc += b.pdf(DVec3::new(r * phi.sin(), z, r * phi.cos()));
                    }
                }
                acc / (sub * sub) as f64
            };
            // Refine until two midpoint rules agree (peaked lobes need fine grids).
            let mut s = sub;
            let mut v0 = cell(s);
            let acc = loop {
                let v1 = cell(2 * s);
                s *= 2;
                if (v1 - v0).abs() <= 1e-4 * v1.abs() + 1e-9 || s >= 96 {
                    break v1;
                }
                v0 = v1;
            };
            let area = 4.0 * PI / (nt * np) as f64;
            let v = acc * area;
            exp[ti * np + pi] = v * n as f64;
            total += v;
        }
    }
    exp[nt * np] = (n as f64 * (1.0 - total)).max(0.0);
    // Pool small bins.
    let (mut chi, mut dof) = (0.0, 0usize);
    let (mut po, mut pe) = (0.0, 0.0);
    let mut idx: Vec<usize> = (0..exp.len()).collect();
    idx.sort_by(|&a, &b| exp[a].partial_cmp(&exp[b]).unwrap());
    for &i in &idx {
        if exp[i] < 5.0 || pe > 0.0 && pe < 5.0 {
            po += obs[i];
            pe += exp[i];
            continue;
        }
        chi += (obs[i] - exp[i]).powi(2) / exp[i];
        dof += 1;
    }
    if pe > 0.0 {
        chi += (po - pe).powi(2) / pe;
        dof += 1;
    }
    if std::env::var("CHI2_DEBUG").is_ok() {
        let mut worst: Vec<(f64, usize)> = (0..exp.len())
            .filter(|&i| exp[i] >= 5.0)
            .map(|i| ((obs[i] - exp[i]).powi(2) / exp[i], i))
            .collect();
        worst.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
        let small: Vec<usize> = (0..exp.len())
            .filter(|&i| exp[i] < 5.0 && obs[i] > 0.0)
            .collect();
        let (so, se): (f64, f64) = small
            .iter()
            .fold((0.0, 0.0), |a, &i| (a.0 + obs[i], a.1 + exp[i]));
        println!(
            "  pooled small bins: obs {so} exp {se:.1} over {} bins",
            small.len()
        );
        for &i in &small {
            println!(
                "    small bin {} (t {}, p {}): obs {} exp {:.2}",
                i,
                i / np,
                i % np,
                obs[i],
                exp[i]
            );
        }
        for &(c, i) in worst.iter().take(6) {
            println!(
                "  bin {} (t {}, p {}): obs {} exp {:.1} chi {:.1}",
                i,
                i / np,
                i % np,
                obs[i],
                exp[i],
                c
            );
        }
    }
    let dof = dof.saturating_sub(1).max(1);
    Chi2 {
        p_value: gamma_q(dof as f64 / 2.0, chi / 2.0),
        dof,
        pdf_integral: total,
        delta_fraction: deltas as f64 / n as f64,
        none_fraction: nones as f64 / n as f64,
        max_consistency_error: max_err,
    }
}
