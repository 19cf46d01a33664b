//! USD matrices in glam.
//!
//! USD stores a 4×4 matrix `M` for **row vectors**: a point transforms as `p' = p · M` and the
//! translation is the last row. glam multiplies column vectors (`p' = G · p`). The two agree when
//! `G = Mᵀ`, i.e. when the glam matrix's *columns* are USD's *rows* — which is exactly what
//! `DMat4::from_cols_array_2d(&usd_rows)` builds, with the same memory order. Composition flips:
//! USD `local · parent` is glam `parent * local`.

use glam::{DMat3, DMat4, DVec3};

/// Converts a USD row-vector matrix, given as its four rows, into a glam `DMat4` that applies it
/// to column vectors: `usd_matrix(rows).transform_point3(p) == p · M` (the columns of the result
/// are the USD rows).
#[inline]
pub fn usd_matrix(rows: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&rows)
}

/// Largest deviation of a matrix's last USD column (glam's bottom row) from `(0, 0, 0, 1)` that
/// counts as rounding noise of the exporting application (`1.0000000000000002`): below it the
/// matrix is affine; above it, projective.
pub const AFFINE_TOLERANCE: f64 = 1e-9;

/// `max(|m₀₃|, |m₁₃|, |m₂₃|, |m₃₃ − 1|)` in USD's row form: how far `m` is from affine.
#[inline]
pub fn affine_deviation(m: &DMat4) -> f64 {
    let r = m.row(3);
    r.x.abs()
        .max(r.y.abs())
        .max(r.z.abs())
        .max((r.w - 1.0).abs())
}

/// The USD rows of a glam matrix built by [`usd_matrix`] (its inverse).
#[inline]
pub fn usd_rows(m: &DMat4) -> [[f64; 4]; 4] {
    m.to_cols_array_2d()
}

/// The linear (3×3) part of an affine light-to-world transform, i.e. how it maps directions
/// and local lengths: the images of the local x, y, z unit vectors are its columns.
#[inline]
pub fn linear_part(m: &DMat4) -> DMat3 {
    DMat3::from_mat4(*m)
}

/// Whether every entry of `m` is finite.
#[inline]
pub fn is_finite_matrix(m: &DMat4) -> bool {
    m.is_finite()
}

/// The world-space image of a local direction `v` under the light-to-world transform (no
/// translation, no normalisation).
#[inline]
pub fn transform_vector(m: &DMat4, v: DVec3) -> DVec3 {
    m.transform_vector3(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_vector_convention() {
        // USD: translate by (1, 2, 3) after scaling x by 2: rows of M.
        let rows = [
            [2.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 2.0, 3.0, 1.0],
        ];
        let m = usd_matrix(rows);
        let p = m.transform_point3(DVec3::new(1.0, 1.0, 1.0));
        assert_eq!(p, DVec3::new(3.0, 3.0, 4.0));
        assert_eq!(usd_rows(&m), rows);
        // a 90 degree rotation about Z in USD row form maps +X to +Y.
        let rz = usd_matrix([
            [0.0, 1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]);
        assert_eq!(transform_vector(&rz, DVec3::X), DVec3::Y);
        // USD local*parent == glam parent*local
        let world = m * rz;
        let q = world.transform_point3(DVec3::X);
        assert_eq!(q, m.transform_point3(rz.transform_point3(DVec3::X)));
        assert_eq!(linear_part(&m).x_axis, DVec3::new(2.0, 0.0, 0.0));
        assert!(is_finite_matrix(&m));
    }
}
