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
