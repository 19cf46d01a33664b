//! Affine light-to-world transforms and the change of solid-angle measure they induce.
//!
//! Every finite light is sampled in its **local** space (where its shape is canonical: a
//! `width × height` rectangle, a round disk, a sphere, a cylinder along X) from the reference
//! point mapped into that space, and the sampled point is mapped back. Affine maps preserve
//! straight lines, so visibility and the set of directions hitting the light are preserved; only
//! the solid-angle measure changes. For the linear part `L` and a unit local direction `w'`, the
//! world direction is `w = Lw'/|Lw'|` and
//!
//! ```text
//! dω / dω' = |det L| / |L w'|³        (so pdf_world = pdf_local · |L w'|³ / |det L|)
//! ```
//!
//! (the Jacobian used for linearly transformed cosines, Heitz et al. 2016, eq. 18). This gives
//! exact densities under non-uniform scale and shear. All geometry is in `f64`.

use crate::error::SampleError;
use glam::{DMat3, DMat4, DVec3};
use lux_math::AFFINE_TOLERANCE;

/// A validated, invertible affine light-to-world transform `x ↦ L·x + t`.
///
/// Built from a glam `DMat4` in glam's column convention (`m.transform_point3(p_local)` is the
/// world point), i.e. the USD row-vector matrix with its rows as glam columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTransform {
    linear: DMat3,
    inverse: DMat3,
    /// L⁻ᵀ, for normals.
    inverse_t: DMat3,
    translation: DVec3,
    abs_det: f64,
    /// True when L is a rotation times a uniform scale, so the measure change is 1.
    similarity: bool,
    /// 1/s when L is s times an orthogonal matrix to within a few ulp (so that `L w / s` is a
    /// unit vector to that accuracy for any unit w); 0 otherwise.
    inv_scale: f64,
}

impl Default for LightTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl LightTransform {
    /// The identity transform.
    pub const IDENTITY: Self = Self {
        linear: DMat3::IDENTITY,
        inverse: DMat3::IDENTITY,
        inverse_t: DMat3::IDENTITY,
        translation: DVec3::ZERO,
        abs_det: 1.0,
        similarity: true,
        inv_scale: 1.0,
    };

    /// Validates `m`: finite, affine (bottom row 0 0 0 1 in glam terms) and invertible with a
    /// condition well inside double precision.
    pub fn new(m: DMat4) -> Result<Self, SampleError> {
        if !m.is_finite() {
            return Err(SampleError::BadTransform("non-finite matrix entry"));
        }
        // The last USD column must be (0, 0, 0, 1); a deviation up to AFFINE_TOLERANCE is
        // rounding noise of the exporting application and is ignored (the map used is affine).
        if lux_math::affine_deviation(&m) > AFFINE_TOLERANCE {
            return Err(SampleError::BadTransform(
                "projective matrix (expected last USD column 0 0 0 1)",
            ));
        }
        let linear = DMat3::from_mat4(m);
        let det = linear.determinant();
        let scale = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
        if det.is_nan() || det.abs() <= 1e-12 * scale || scale == 0.0 {
            return Err(SampleError::BadTransform(
                "singular linear part (zero scale)",
            ));
        }
        let inverse = linear.inverse();
        let lx = linear.x_axis.length_squared();
        let tol = 1e-12 * lx;
        let dev = (linear.y_axis.length_squared() - lx)
            .abs()
            .max((linear.z_axis.length_squared() - lx).abs())
            .max(linear.x_axis.dot(linear.y_axis).abs())
            .max(linear.x_axis.dot(linear.z_axis).abs())
            .max(linear.y_axis.dot(linear.z_axis).abs());
        let similarity = dev < tol;
        // orthogonal to a few ulp: the columns' Gram matrix is s²·I within 8ε·s²
        let tight = dev <= 8.0 * f64::EPSILON * lx;
        Ok(Self {
            linear,
            inverse,
            inverse_t: inverse.transpose(),
            translation: m.w_axis.truncate(),
            abs_det: det.abs(),
            similarity,
            inv_scale: if tight { 1.0 / lx.sqrt() } else { 0.0 },
        })
    }

    /// A pure translation.
    pub fn from_translation(t: DVec3) -> Self {
        Self {
            translation: t,
            ..Self::IDENTITY
        }
    }

    /// The linear part L.
    #[inline]
    pub fn linear(&self) -> DMat3 {
        self.linear
    }

    /// True when L is a rotation (possibly mirrored) times a uniform scale.
    #[inline]
    pub fn is_similarity(&self) -> bool {
        self.similarity
    }

    /// `(s, t)` when L is s times an orthogonal matrix to within a few ulp (a rotation, possibly
    /// mirrored, and a uniform scale) and t the translation: the light is then the same shape
    /// scaled by s in world space, and rotation-invariant shapes can be sampled there directly.
    #[inline]
    pub(crate) fn uniform_scale_translation(&self) -> Option<(f64, DVec3)> {
        (self.inv_scale > 0.0).then(|| (1.0 / self.inv_scale, self.translation))
    }

    /// |det L|, the volume scale.
    #[inline]
    pub fn abs_det(&self) -> f64 {
        self.abs_det
    }

    /// Local point → world point.
    #[inline]
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.linear * p + self.translation
    }

    /// World point → local point.
    #[inline]
    pub fn inv_point(&self, p: DVec3) -> DVec3 {
        self.inverse * (p - self.translation)
    }

    /// Local vector → world vector (not normalised).
    #[inline]
    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.linear * v
    }

    /// World vector → local vector (not normalised).
    #[inline]
    pub fn inv_vector(&self, v: DVec3) -> DVec3 {
        self.inverse * v
    }

    /// The area scale `‖L t₁ × L t₂‖ = |det L|·‖L⁻ᵀ n‖` of a local surface element whose
    /// orthonormal tangents are `t1`, `t2` (normal `n = t₁ × t₂`): world area per local area.
    #[inline]
    pub fn area_scale(&self, t1: DVec3, t2: DVec3) -> f64 {
        (self.linear * t1).cross(self.linear * t2).length()
    }

    /// Local normal → unit world normal (transformed by L⁻ᵀ, which keeps the side it points to).
    #[inline]
    pub fn normal(&self, n: DVec3) -> DVec3 {
        (self.inverse_t * n).normalize()
    }

    /// World covector → local covector (Lᵀ n): `n·(L w') = (Lᵀ n)·w'`, so signs of cosines
    /// are preserved. Not normalised.
    #[inline]
    pub fn inv_normal(&self, n: DVec3) -> DVec3 {
        self.linear.transpose() * n
    }

    /// Factor turning a local solid-angle density into a world one for the local unit direction
    /// `w_local`: |L w'|³ / |det L|.
    #[inline]
    pub fn pdf_to_world(&self, w_local: DVec3) -> f64 {
        if self.similarity {
            return 1.0;
        }
        let l = self.linear.mul_vec3(w_local).length();
        l * l * l / self.abs_det
    }
}

/// Maps a local sample back to world space: world point, normal, direction, distance and the
/// solid-angle density converted with [`LightTransform::pdf_to_world`].
#[inline]
pub(crate) fn finish_sample(
    xf: &LightTransform,
    p_world: DVec3,
    p_local: DVec3,
    q_local: DVec3,
    n_local: DVec3,
    pdf_local: f64,
) -> Option<crate::LightSample> {
    finish(xf, p_world, p_local, q_local, pdf_local, || {
        xf.normal(n_local)
    })
}

/// [`finish_sample`] for a light whose world normal is fixed (a planar light: computed once,
/// at construction, as `xf.normal(n_local)`).
#[inline]
pub(crate) fn finish_sample_with_normal(
    xf: &LightTransform,
    p_world: DVec3,
    p_local: DVec3,
    q_local: DVec3,
    normal: DVec3,
    pdf_local: f64,
) -> Option<crate::LightSample> {
    finish(xf, p_world, p_local, q_local, pdf_local, || normal)
}

#[inline(always)]
fn finish(
    xf: &LightTransform,
    p_world: DVec3,
    p_local: DVec3,
    q_local: DVec3,
    pdf_local: f64,
    normal: impl FnOnce() -> DVec3,
) -> Option<crate::LightSample> {
    let q = xf.point(q_local);
    let d = q - p_world;
    let distance = d.length();
    if !(distance > 0.0 && pdf_local > 0.0 && pdf_local.is_finite()) {
        return None;
    }
    // A similarity leaves solid angle unchanged: the local direction is not needed.
    let pdf = if xf.similarity {
        pdf_local
    } else {
        let dl = (q_local - p_local).length();
        if dl.is_nan() || dl <= 0.0 {
            return None;
        }
        let w_local = (q_local - p_local) / dl;
        pdf_local * xf.pdf_to_world(w_local)
    };
    if !pdf.is_finite() {
        return None;
    }
    Some(crate::LightSample {
        point: q,
        normal: normal(),
        wi: d * (1.0 / distance),
        distance,
        pdf,
        delta: false,
    })
}

/// Maps a local sample given by its **direction** back to world space: the sampler found the
/// light point `q_local = p_local + t_local·w_local` (unit `w_local`) and its unit local
/// normal. The world direction is `L w / |L w|` and the distance `t·|L w|` (for a similarity
/// `L = s·R`, orthogonal R to a few ulp: `L w / s` and `t·s`, no square root), rather than the
/// normalised difference of the two world points: the same values up to rounding, without the
/// cancellation of `q − p` far from the light. The density is converted as by
/// [`LightTransform::pdf_to_world`] at `w_local`; the world normal of such a similarity is
/// `L n / s` (= `R n`, what `normal` gives for a unit n), otherwise [`LightTransform::normal`].
#[inline]
pub(crate) fn finish_sample_dir(
    xf: &LightTransform,
    q_local: DVec3,
    n_local: DVec3,
    w_local: DVec3,
    t_local: f64,
    pdf_local: f64,
) -> Option<crate::LightSample> {
    if !(t_local > 0.0 && pdf_local > 0.0 && pdf_local.is_finite()) {
        return None;
    }
    let v = xf.linear * w_local;
    let (wi, distance, pdf, normal) = if xf.inv_scale > 0.0 {
        // s times an orthogonal matrix (to a few ulp): a similarity, measure change 1
        let k = xf.inv_scale;
        (v * k, t_local / k, pdf_local, (xf.linear * n_local) * k)
    } else {
        let l = v.length();
        let pdf = if xf.similarity {
            pdf_local
        } else {
            pdf_local * (l * l * l / xf.abs_det)
        };
        (v * (1.0 / l), t_local * l, pdf, xf.normal(n_local))
    };
    if !(distance > 0.0 && pdf.is_finite()) {
        return None;
    }
    Some(crate::LightSample {
        point: xf.point(q_local),
        normal,
        wi,
        distance,
        pdf,
        delta: false,
    })
}

/// World direction → (unit local direction, world-density factor). `None` for a zero or
/// non-finite direction.
#[inline]
pub(crate) fn local_direction(xf: &LightTransform, wi: DVec3) -> Option<(DVec3, f64)> {
    let v = xf.inv_vector(wi);
    let len = v.length();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let w = v / len;
    Some((w, xf.pdf_to_world(w)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::warp::sample_uniform_sphere;

    #[test]
    fn rejects_bad_matrices() {
        assert!(LightTransform::new(DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_err());
        let mut m = DMat4::IDENTITY;
        m.x_axis.w = 0.5;
        assert!(LightTransform::new(m).is_err());
        m = DMat4::IDENTITY;
        m.y_axis.y = f64::NAN;
        assert!(LightTransform::new(m).is_err());
        // rounding noise in the last column (a DCC export's 1.0000000000000002) is accepted
        m = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0));
        m.w_axis.w = 1.000_000_000_000_000_2;
        m.z_axis.w = 1e-12;
        let t = LightTransform::new(m).expect("noise is not projective");
        assert_eq!(t.point(DVec3::ZERO), DVec3::new(1.0, 2.0, 3.0));
        m.z_axis.w = 2.0 * AFFINE_TOLERANCE;
        assert!(LightTransform::new(m).is_err());
    }

    /// ∫ (dω/dω') dω' over the sphere is 4π for any invertible L (the map is a bijection of the
    /// sphere), checked by Monte Carlo with a sheared, scaled matrix.
    #[test]
    fn measure_change_integrates_to_sphere() {
        let m = DMat4::from_cols_array(&[
            2.0, 0.3, 0.0, 0.0, 0.5, 0.7, 0.0, 0.0, 0.1, -0.4, 1.5, 0.0, 1.0, 2.0, 3.0, 1.0,
        ]);
        let t = LightTransform::new(m).unwrap();
        assert!(!t.is_similarity());
        let mut r = SplitMix64::new(3);
        let n = 400_000;
        let mut s = 0.0;
        let mut s2 = 0.0;
        for _ in 0..n {
            let w = sample_uniform_sphere(r.next_2d());
            let j = 1.0 / t.pdf_to_world(w);
            s += j;
            s2 += j * j;
        }
        let mean = s / n as f64;
        let sigma = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 1.0).abs() < 4.0 * sigma, "{mean} ± {sigma}");
        let p = DVec3::new(0.3, -1.0, 2.0);
        assert!((t.inv_point(t.point(p)) - p).length() < 1e-12);
    }
}
