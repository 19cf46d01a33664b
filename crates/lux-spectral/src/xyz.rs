//! Spectrum → CIE XYZ: exact integration against the interpolated colour-matching functions.

use glam::DVec3;

use crate::cie::{CMF_MAX_NM, CMF_MIN_NM, cmf_in_cell, cmf_moments_at};
use crate::interpolation::Interpolation;
use crate::photometry::K_M;
use crate::planck::Blackbody;
use crate::spectrum::SampledSpectrum;

/// 3-point Gauss–Legendre nodes on [−1, 1] and weights (exact for polynomials of degree ≤ 5).
const GL3_X: f64 = 0.774_596_669_241_483_4; // √(3/5)
const GL3_W_END: f64 = 5.0 / 9.0;
const GL3_W_MID: f64 = 8.0 / 9.0;

#[inline]
fn gl3<T>(a: f64, b: f64, f: impl Fn(f64) -> T) -> T
where
    T: core::ops::Add<Output = T> + core::ops::Mul<f64, Output = T>,
{
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    (f(c - h * GL3_X) * GL3_W_END + f(c) * GL3_W_MID + f(c + h * GL3_X) * GL3_W_END) * h
}

/// Photometric tristimulus values of a sampled spectrum:
/// `(X, Y, Z) = 683 · ∫ S(λ) (x̄, ȳ, z̄)(λ) dλ`, so that Y is the luminance in cd/m² (nits) when
/// S is spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹.
///
/// The integral is exact for the model "S interpolated by its own mode, CMFs linearly
/// interpolated between their 1 nm samples", so narrow emission lines between table wavelengths
/// are integrated correctly. Linear and held spectra use compile-time prefix moments of the
/// CMFs, M0(λ) = ∫c and M1(λ) = ∫(λ'−360)c: on a sample interval [a, b] where
/// S = s_a + m(λ − a), ∫ S c = s_a ΔM0 + m (ΔM1 − (a − 360) ΔM0) — O(1) per sample. Cubic spectra
/// walk every breakpoint of both functions with 3-point Gauss–Legendre per piece (exact for
/// cubic × linear). Allocation-free.
pub fn spectrum_to_xyz(s: &SampledSpectrum) -> DVec3 {
    match s.interpolation() {
        Interpolation::Linear | Interpolation::Held => spectrum_to_xyz_moments(s),
        Interpolation::Cubic => spectrum_to_xyz_walk(s),
    }
}

fn spectrum_to_xyz_moments(s: &SampledSpectrum) -> DVec3 {
    let w = s.wavelengths();
    let v = s.values();
    let held = s.interpolation() == Interpolation::Held;
    let mut sum = DVec3::ZERO;
    let mut prev_b = f64::NAN;
    let (mut m0b, mut m1b) = (DVec3::ZERO, DVec3::ZERO);
    for i in 0..w.len() - 1 {
        let (x0, x1) = (w[i], w[i + 1]);
        if x1 <= CMF_MIN_NM {
            continue;
        }
        if x0 >= CMF_MAX_NM {
            break;
        }
        let a = x0.max(CMF_MIN_NM);
        let b = x1.min(CMF_MAX_NM);
        let (m0a, m1a) = if a == prev_b {
            (m0b, m1b)
        } else {
            cmf_moments_at(a)
        };
        (m0b, m1b) = cmf_moments_at(b);
        prev_b = b;
        let d0 = m0b - m0a;
        if held {
            sum += v[i] * d0;
        } else {
            let slope = (v[i + 1] - v[i]) / (x1 - x0);
            let sa = v[i] + slope * (a - x0);
            sum += sa * d0 + slope * ((m1b - m1a) - (a - CMF_MIN_NM) * d0);
        }
    }
    sum * K_M
}

fn spectrum_to_xyz_walk(s: &SampledSpectrum) -> DVec3 {
    let w = s.wavelengths();
    let v = s.values();
    let (lo, hi) = s.bounds();
    let lo = lo.max(CMF_MIN_NM);
    let hi = hi.min(CMF_MAX_NM);
    if lo.partial_cmp(&hi) != Some(core::cmp::Ordering::Less) {
        return DVec3::ZERO;
    }
    let Some(mut seg) = s.segment_index(lo) else {
        return DVec3::ZERO;
    };
    let last_cell = (CMF_MAX_NM - CMF_MIN_NM) as usize - 1;
    let mut k = ((lo - CMF_MIN_NM) as usize).min(last_cell);
    let interp = s.interpolation();
    let mut a = lo;
    let mut ca = cmf_in_cell(k, a);
    let mut sa = s.eval_in_segment(seg, a);
    let mut sum = DVec3::ZERO;
    loop {
        let w_next = w[seg + 1];
        let c_next = CMF_MIN_NM + (k + 1) as f64;
        let b = w_next.min(c_next).min(hi);
        let cb = cmf_in_cell(k, b);
        let h = b - a;
        match interp {
            Interpolation::Linear => {
                let sb = s.eval_in_segment(seg, b);
                sum += (h / 6.0) * (ca * (2.0 * sa + sb) + cb * (sa + 2.0 * sb));
                sa = sb;
            }
            Interpolation::Held => {
                sum += (0.5 * h * v[seg]) * (ca + cb);
            }
            Interpolation::Cubic => {
                sum += gl3(a, b, |l| cmf_in_cell(k, l) * s.eval_in_segment(seg, l));
            }
        }
        if b >= hi {
            break;
        }
        if b >= w_next {
            seg += 1;
            if interp == Interpolation::Linear {
                sa = s.eval_in_segment(seg, b);
            }
        }
        if b >= c_next {
            k = (k + 1).min(last_cell);
        }
        a = b;
        ca = cb;
    }
    sum * K_M
}

/// Photometric tristimulus values of a band-limited black body, 683·∫ L(λ,T) (x̄, ȳ, z̄) dλ,
/// by 3-point Gauss–Legendre on every 1 nm CMF cell (relative error far below 10⁻⁸).
pub fn blackbody_to_xyz(b: &Blackbody) -> DVec3 {
    let (lo, hi) = b.bounds();
    let t = b.temperature();
    integrate_cells(lo, hi, |k, l| {
        cmf_in_cell(k, l) * crate::planck::planck_radiance(l, t)
    }) * K_M
}

/// ∫ f(λ) (x̄, ȳ, z̄)(λ) dλ over [lo, hi] ∩ [360, 830] for a smooth f (Gauss–Legendre per
/// 1 nm cell), without the 683 factor.
pub fn integrate_smooth_against_cmf(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> DVec3 {
    integrate_cells(lo, hi, |k, l| cmf_in_cell(k, l) * f(l))
}

fn integrate_cells(lo: f64, hi: f64, f: impl Fn(usize, f64) -> DVec3) -> DVec3 {
    let lo = lo.max(CMF_MIN_NM);
    let hi = hi.min(CMF_MAX_NM);
    if lo.partial_cmp(&hi) != Some(core::cmp::Ordering::Less) {
        return DVec3::ZERO;
    }
    let last_cell = (CMF_MAX_NM - CMF_MIN_NM) as usize - 1;
    let mut k = ((lo - CMF_MIN_NM) as usize).min(last_cell);
    let mut a = lo;
    let mut sum = DVec3::ZERO;
    while a < hi {
        let b = (CMF_MIN_NM + (k + 1) as f64).min(hi);
        sum += gl3(a, b, |l| f(k, l));
        a = b;
        k = (k + 1).min(last_cell);
    }
    sum
}

/// ∫ f(λ) dλ over `bounds` for a smooth f: 3-point Gauss–Legendre on 1 nm pieces (at most
/// 10⁶ pieces; wider bands use proportionally wider pieces).
pub fn integrate_smooth(f: impl Fn(f64) -> f64, bounds: (f64, f64)) -> f64 {
    let (lo, hi) = bounds;
    if lo.partial_cmp(&hi) != Some(core::cmp::Ordering::Less) || !(hi - lo).is_finite() {
        return 0.0;
    }
    let n = ((hi - lo).ceil() as usize).clamp(1, 1_000_000);
    let step = (hi - lo) / n as f64;
    (0..n)
        .map(|i| {
            let a = lo + step * i as f64;
            gl3(a, a + step, &f)
        })
        .sum()
}
