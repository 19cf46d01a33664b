//! Exact penumbrae of sphere lights behind a few triangles.
//!
//! A uniform sphere light seen whole above a Lambertian point's horizon is drawn from its
//! projected cap, so each light sample returns the unshadowed integral `L·Π` or, blocked,
//! nothing: the estimate is `L·Π` times the fraction of samples that pass, and its only noise
//! is that fraction's. When every triangle that can block the point's shadow rays is known
//! and few (the point's patch of surface, integrator/patches.rs), the fraction has a closed
//! form: the cap's Π less what each triangle hides of it (`lux_sample::hidden`), provided the
//! triangles lie in front of the sphere (every ray through them meets them before the light)
//! and their projections do not overlap (nothing hidden twice). Then the penumbra is exact:
//! no light sample, no shadow ray, no noise.

use crate::geometry::{FewTriangles, Geometry};
use crate::material::SurfacePoint;
use glam::DVec3;
use lux_sample::hidden;

/// The fraction of a uniform sphere light's unshadowed integral that reaches the point `sp`
/// past the triangles `few` (every triangle that can stop its shadow rays:
/// [`Geometry::blockers_in`] of a region holding them): `1 − Σ Hᵢ / Π` with Hᵢ what triangle i
/// hides of the cap ([`hidden::cap_triangle`]), Π the cap's projected solid angle from `sp.p`
/// with the shading normal (`pi`), the sphere of world centre `centre` and radius `radius`;
/// 0 within 10⁻¹² of the whole cap (the rounding of the triangles' sum).
///
/// `None` (sample it instead) unless the cap lies wholly above both the shading and the
/// geometric horizon, every triangle that hides some of it lies on the point's side of the
/// plane through the sphere's nearest point (`(x − p)·a < D − R`, a the unit axis: before any
/// point of the sphere along every ray), and no two of them overlap as seen from the point
/// ([`hidden::apart`]).
pub fn sphere_visible(
    g: &Geometry,
    sp: &SurfacePoint,
    (centre, radius, pi): (DVec3, f64, f64),
    few: &FewTriangles,
) -> Option<f64> {
    let to = centre - sp.p;
    let d = to.length();
    let axis = to / d;
    let sin_a = radius / d;
    if !(pi > 0.0 && sin_a < 1.0 && sp.ng.dot(axis) > sin_a) {
        return None;
    }
    let cos_a = (1.0 - sin_a * sin_a).sqrt();
    let near = d - radius;
    let mut hiding = [[DVec3::ZERO; 3]; FewTriangles::CAP];
    let mut k = 0;
    let mut hidden_sum = 0.0;
    for &id in few.ids() {
        let tri = g.blocker_vertices(id)?;
        let h = hidden::cap_triangle(sp.p, sp.ns, axis, cos_a, &tri)?;
        if h == 0.0 {
            continue;
        }
        if tri.iter().any(|v| (*v - sp.p).dot(axis) >= near) {
            return None;
        }
        if hiding[..k]
            .iter()
            .any(|other| !hidden::apart(sp.p, other, &tri))
        {
            return None;
        }
        hiding[k] = tri;
        k += 1;
        hidden_sum += h;
    }
    // (within rounding of the whole cap, e.g. a quad's two triangles covering it: black, as a
    // hard shadow's samples are)
    let pass = 1.0 - hidden_sum / pi;
    Some(if pass < 1e-12 { 0.0 } else { pass.min(1.0) })
}
