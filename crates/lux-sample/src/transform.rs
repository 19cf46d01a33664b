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

use glam::DVec3;
pub use lux_math::LightTransform;

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
    let pdf = if xf.is_similarity() {
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
    let v = xf.vector(w_local);
    let (wi, distance, pdf, normal) = if let Some(k) = xf.inverse_uniform_scale() {
        // s times an orthogonal matrix (to a few ulp): a similarity, measure change 1
        (v * k, t_local / k, pdf_local, xf.vector(n_local) * k)
    } else {
        let l = v.length();
        let pdf = if xf.is_similarity() {
            pdf_local
        } else {
            pdf_local * (l * l * l / xf.abs_det())
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
    let w = xf.local_direction(wi)?;
    Some((w, xf.pdf_to_world(w)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::warp::sample_uniform_sphere;
    use glam::DMat4;

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
