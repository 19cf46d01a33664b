//! Photometric constants and conversions (683 lm/W).

/// Maximum luminous efficacy of radiation for photopic vision, K_m = 683 lm/W: the factor
/// between ∫ S(λ) ȳ(λ) dλ (W…) and the photometric quantity (lm…). The SI defines 683 lm/W at
/// 540 × 10¹² Hz (≈ 555.016 nm), where the CIE 1931 ȳ ≈ 1.
pub const K_M: f64 = 683.0;

/// xy chromaticity of XYZ tristimulus values: (X/(X+Y+Z), Y/(X+Y+Z)); (0, 0) for a zero sum.
pub fn xy_chromaticity(xyz: glam::DVec3) -> glam::DVec2 {
    let s = xyz.x + xyz.y + xyz.z;
    if s == 0.0 || !s.is_finite() {
        return glam::DVec2::ZERO;
    }
    glam::DVec2::new(xyz.x / s, xyz.y / s)
}

/// CIE 1960 UCS (u, v) of XYZ: u = 4X/(X+15Y+3Z), v = 6Y/(X+15Y+3Z); (0, 0) for a zero sum.
pub fn uv_1960(xyz: glam::DVec3) -> glam::DVec2 {
    let d = xyz.x + 15.0 * xyz.y + 3.0 * xyz.z;
    if d == 0.0 || !d.is_finite() {
        return glam::DVec2::ZERO;
    }
    glam::DVec2::new(4.0 * xyz.x / d, 6.0 * xyz.y / d)
}
