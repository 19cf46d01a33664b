//! The light-to-world transform every lux crate shares: [`LightTransform`].

use glam::{DMat3, DMat4, DVec3};
use thiserror::Error;

/// Why a matrix is not a usable light-to-world transform.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
#[error("transform: {0}")]
pub struct TransformError(pub &'static str);

/// A validated, invertible affine light-to-world transform `x ↦ L·x + t` (the prim's
/// `xformOp`s composed to its local-to-world matrix, spec §2), built from a glam `DMat4` in glam's
/// column convention (`m.transform_point3(p_local)` is the world point), i.e. the USD row-vector
/// matrix with its rows as glam columns ([`crate::usd_matrix`]).
///
/// UsdLux (spec §2) describes every light in its local space — the shape canonical (a
/// `width × height` rectangle in XY, a round disk, a sphere, a cylinder along X), emission
/// along local −Z, the ShapingAPI and IES angles measured from −Z — and places it with the
/// prim's local-to-world matrix, which may scale non-uniformly and shear. A renderer needs
/// four maps between the spaces, one per kind of quantity:
///
/// | quantity | local → world | world → local |
/// |---|---|---|
/// | point | `L p + t` ([`LightTransform::point`]) | `L⁻¹ (p − t)` ([`LightTransform::inv_point`]) |
/// | vector, direction | `L v` ([`LightTransform::vector`]) | `L⁻¹ v` ([`LightTransform::inv_vector`], unit: [`LightTransform::local_direction`]) |
/// | surface normal | `L⁻ᵀ n` ([`LightTransform::normal`]) | `Lᵀ n` ([`LightTransform::inv_normal`]) |
/// | solid-angle density | `· ‖L w'‖³ / abs(det L)` ([`LightTransform::pdf_to_world`]) | its inverse |
///
/// **Emission directions.** The ShapingAPI factor and the IES profile are functions of the
/// direction from the light towards the receiver *in the light's local space*. A world
/// direction `w` (light point → receiver) is a difference of points, so it maps as a vector:
/// `w_local = normalize(L⁻¹ w)` ([`LightTransform::local_direction`]). This is the only
/// mapping under which the lit region is the image of the local one: a receiver at world
/// point `r` is lit exactly as the local receiver `L⁻¹(r − t)` is by the local light, so a
/// cone of half-angle θ becomes the affine image of that cone (an oblique elliptic cone
/// under non-uniform scale or shear). The normal matrix `Lᵀ` would be the mapping for
/// planes, not directions, and disagrees with it as soon as `L` is not a similarity.
///
/// Measure change: for a unit local direction `w'`, the world direction is `w = Lw'/|Lw'|` and
/// `dω / dω' = |det L| / |L w'|³` (the Jacobian of linearly transformed cosines, Heitz et al.
/// 2016, eq. 18).
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

    /// Validates `m`: finite, affine (last USD column `0 0 0 1` to within
    /// [`crate::AFFINE_TOLERANCE`]) and invertible with a condition well inside double
    /// precision (`|det L| > 10⁻¹²·|Lx|·|Ly|·|Lz|`).
    pub fn new(m: DMat4) -> Result<Self, TransformError> {
        if !m.is_finite() {
            return Err(TransformError("non-finite matrix entry"));
        }
        // The last USD column must be (0, 0, 0, 1); a deviation up to AFFINE_TOLERANCE is
        // rounding noise of the exporting application and is ignored (the map used is affine).
        if crate::affine_deviation(&m) > crate::AFFINE_TOLERANCE {
            return Err(TransformError(
                "projective matrix (expected last USD column 0 0 0 1)",
            ));
        }
        let linear = DMat3::from_mat4(m);
        let det = linear.determinant();
        let scale = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
        if det.is_nan() || det.abs() <= 1e-12 * scale || scale == 0.0 {
            return Err(TransformError("singular linear part (zero scale)"));
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

    /// The matrix again (glam column convention): `L` and `t` as a `DMat4`, what the
    /// size-factor functions ([`crate::size_factor`], [`crate::emitted_radiance`]) take.
    #[inline]
    pub fn matrix(&self) -> DMat4 {
        DMat4::from_cols(
            self.linear.x_axis.extend(0.0),
            self.linear.y_axis.extend(0.0),
            self.linear.z_axis.extend(0.0),
            self.translation.extend(1.0),
        )
    }

    /// The linear part L.
    #[inline]
    pub fn linear(&self) -> DMat3 {
        self.linear
    }

    /// The translation t (the light's local origin in world space).
    #[inline]
    pub fn translation(&self) -> DVec3 {
        self.translation
    }

    /// True when L is a rotation (possibly mirrored) times a uniform scale (to 10⁻¹² relative):
    /// angles, and so the shaping cone, are then the same in both spaces.
    #[inline]
    pub fn is_similarity(&self) -> bool {
        self.similarity
    }

    /// `1/s` when L is s times an orthogonal matrix to within a few ulp (a rotation, possibly
    /// mirrored, and a uniform scale): the light is then the same shape scaled by s in world
    /// space, and `L w · (1/s)` is a unit vector for any unit `w`. `None` otherwise.
    #[inline]
    pub fn inverse_uniform_scale(&self) -> Option<f64> {
        (self.inv_scale > 0.0).then_some(self.inv_scale)
    }

    /// |det L|, the volume scale.
    #[inline]
    pub fn abs_det(&self) -> f64 {
        self.abs_det
    }

    /// Local point → world point: `L p + t`.
    #[inline]
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.linear * p + self.translation
    }

    /// World point → local point: `L⁻¹ (p − t)`.
    #[inline]
    pub fn inv_point(&self, p: DVec3) -> DVec3 {
        self.inverse * (p - self.translation)
    }

    /// Local vector → world vector: `L v` (not normalised).
    #[inline]
    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.linear * v
    }

    /// World vector → local vector: `L⁻¹ v` (not normalised).
    #[inline]
    pub fn inv_vector(&self, v: DVec3) -> DVec3 {
        self.inverse * v
    }

    /// The unit light-space **emission direction** of the world direction `w` (from a point of
    /// the light towards the receiver, any length): `normalize(L⁻¹ w)`, the mapping the
    /// ShapingAPI and IES angles are evaluated with (see [`LightTransform`]).
    /// `None` when `L⁻¹ w` is zero or not finite.
    #[inline]
    pub fn local_direction(&self, w: DVec3) -> Option<DVec3> {
        let v = self.inverse * w;
        let len = v.length();
        (len > 0.0 && len.is_finite()).then(|| v / len)
    }

    /// The area scale `‖L t₁ × L t₂‖ = |det L|·‖L⁻ᵀ n‖` of a local surface element whose
    /// orthonormal tangents are `t1`, `t2` (normal `n = t₁ × t₂`): world area per local area.
    #[inline]
    pub fn area_scale(&self, t1: DVec3, t2: DVec3) -> f64 {
        (self.linear * t1).cross(self.linear * t2).length()
    }

    /// Local normal → unit world normal: `normalize(L⁻ᵀ n)`, which keeps the side it points to.
    #[inline]
    pub fn normal(&self, n: DVec3) -> DVec3 {
        (self.inverse_t * n).normalize()
    }

    /// World covector → local covector: `Lᵀ n`, so that `n·(L w') = (Lᵀ n)·w'` (signs of
    /// cosines are preserved). Not normalised.
    #[inline]
    pub fn inv_normal(&self, n: DVec3) -> DVec3 {
        self.linear.transpose() * n
    }

    /// Factor turning a local solid-angle density into a world one for the unit local
    /// direction `w_local`: `|L w'|³ / |det L|` (1 for a similarity).
    #[inline]
    pub fn pdf_to_world(&self, w_local: DVec3) -> f64 {
        if self.similarity {
            return 1.0;
        }
        let l = self.linear.mul_vec3(w_local).length();
        l * l * l / self.abs_det
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        m.z_axis.w = 2.0 * crate::AFFINE_TOLERANCE;
        assert_eq!(
            LightTransform::new(m),
            Err(TransformError(
                "projective matrix (expected last USD column 0 0 0 1)"
            ))
        );
    }

    /// `matrix()` gives back the affine matrix; the point and vector maps invert each other; the
    /// emission direction of the world image of a local direction is that local direction.
    #[test]
    fn maps_invert_each_other() {
        let m = DMat4::from_cols_array(&[
            2.0, 0.3, 0.0, 0.0, 0.5, 0.7, 0.0, 0.0, 0.1, -0.4, 1.5, 0.0, 1.0, 2.0, 3.0, 1.0,
        ]);
        let t = LightTransform::new(m).unwrap();
        assert_eq!(t.matrix(), m);
        assert!(!t.is_similarity() && t.inverse_uniform_scale().is_none());
        let p = DVec3::new(0.3, -1.0, 2.0);
        assert!((t.inv_point(t.point(p)) - p).length() < 1e-12);
        let d = DVec3::new(0.6, 0.0, -0.8);
        let back = t.local_direction(t.vector(d) * 7.0).unwrap();
        assert!((back - d).length() < 1e-12, "{back}");
        assert_eq!(t.local_direction(DVec3::ZERO), None);
        assert_eq!(t.local_direction(DVec3::splat(f64::NAN)), None);
        // n·(L w) = (Lᵀ n)·w
        let n = DVec3::new(0.2, 0.9, -0.4);
        assert!((n.dot(t.vector(d)) - t.inv_normal(n).dot(d)).abs() < 1e-12);
        let s = LightTransform::new(DMat4::from_scale(DVec3::splat(4.0))).unwrap();
        assert_eq!(s.inverse_uniform_scale(), Some(0.25));
        assert_eq!(s.pdf_to_world(DVec3::Z), 1.0);
    }
}
