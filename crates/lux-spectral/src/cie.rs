//! The CIE 1931 2° standard observer colour-matching functions.

use glam::DVec3;

use crate::tables::cmf::{CMF_1931_2DEG, CMF_START_NM};

/// First wavelength of the colour-matching-function table, nm.
pub const CMF_MIN_NM: f64 = CMF_START_NM;
/// Last wavelength of the colour-matching-function table, nm.
pub const CMF_MAX_NM: f64 = CMF_START_NM + (CMF_1931_2DEG.len() - 1) as f64;

/// The CIE 1931 2° colour-matching functions (x̄, ȳ, z̄)(λ): the 1 nm table (360–830 nm)
/// linearly interpolated, zero outside it.
pub fn cmf(lambda_nm: f64) -> DVec3 {
    if !(CMF_MIN_NM..=CMF_MAX_NM).contains(&lambda_nm) {
        return DVec3::ZERO;
    }
    let k = ((lambda_nm - CMF_MIN_NM) as usize).min(CMF_1931_2DEG.len() - 2);
    cmf_in_cell(k, lambda_nm)
}

/// Interpolate the table inside cell k = [360 + k, 361 + k] nm.
#[inline]
pub(crate) fn cmf_in_cell(k: usize, lambda_nm: f64) -> DVec3 {
    let t = lambda_nm - (CMF_MIN_NM + k as f64);
    let a = DVec3::from_array(CMF_1931_2DEG[k]);
    let b = DVec3::from_array(CMF_1931_2DEG[k + 1]);
    a + t * (b - a)
}

/// The raw table: (x̄, ȳ, z̄) at 360 + i nm.
pub fn cmf_table() -> &'static [[f64; 3]] {
    &CMF_1931_2DEG
}

/// Per-cell polynomial form of the prefix moments of the interpolated CMFs. For λ = 360 + k + t
/// (t ∈ [0, 1]), with c = a + d·t on cell k:
/// `M0(λ) = ∫_{360}^{λ} c = P0 + t(a + t·d/2)` and
/// `M1(λ) = ∫_{360}^{λ} (λ' − 360) c = P1 + t(k·a + t((k·d + a)/2 + t·d/3))`.
/// Row layout per cell: [P0, a, d/2, P1, k·a, (k·d + a)/2, d/3], each per channel. Computed at
/// compile time; they make ∫ S·c for piecewise-linear S O(1) work per sample.
static CMF_MOMENT_CELLS: [[[f64; 3]; 7]; CMF_1931_2DEG.len() - 1] = cmf_moment_cells();

const fn cmf_moment_cells() -> [[[f64; 3]; 7]; CMF_1931_2DEG.len() - 1] {
    let mut m = [[[0.0; 3]; 7]; CMF_1931_2DEG.len() - 1];
    let mut p0 = [0.0; 3];
    let mut p1 = [0.0; 3];
    let mut k = 0;
    while k + 1 < CMF_1931_2DEG.len() {
        let kf = k as f64;
        let mut ch = 0;
        while ch < 3 {
            let a = CMF_1931_2DEG[k][ch];
            let d = CMF_1931_2DEG[k + 1][ch] - a;
            m[k][0][ch] = p0[ch];
            m[k][1][ch] = a;
            m[k][2][ch] = d / 2.0;
            m[k][3][ch] = p1[ch];
            m[k][4][ch] = kf * a;
            m[k][5][ch] = (kf * d + a) / 2.0;
            m[k][6][ch] = d / 3.0;
            // Whole cell (t = 1).
            p0[ch] += a + d / 2.0;
            p1[ch] += kf * a + (kf * d + a) / 2.0 + d / 3.0;
            ch += 1;
        }
        k += 1;
    }
    m
}

/// (M0, M1)(λ) = (∫_{360}^{λ} c, ∫_{360}^{λ} (λ' − 360) c dλ') for λ in [360, 830].
#[inline]
pub(crate) fn cmf_moments_at(lambda_nm: f64) -> (DVec3, DVec3) {
    let x = (lambda_nm - CMF_MIN_NM).clamp(0.0, CMF_MAX_NM - CMF_MIN_NM);
    let k = (x as usize).min(CMF_MOMENT_CELLS.len() - 1);
    let t = x - k as f64;
    let c = &CMF_MOMENT_CELLS[k];
    let v = |i: usize| DVec3::from_array(c[i]);
    let m0 = v(0) + t * (v(1) + t * v(2));
    let m1 = v(3) + t * (v(4) + t * (v(5) + t * v(6)));
    (m0, m1)
}
