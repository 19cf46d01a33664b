//! The regions a light's shadow rays from a receiver stay in, for the exact visibility: the
//! ball around a rect, disk or sphere light of uniform radiance, the cone of rays towards it,
//! the pyramid over a rect's (or a disk's square's) corners.

use super::{RayEnds, ShadowCone, ShadowPyramid};
use crate::light::LightFrom;
use glam::DVec3;

/// The region the light's shadow rays from the surface point `p` (unit geometric normal
/// `ng`, rays leaving from `p + ng·offset`) stay in ([`ShadowCone`]), when its light-only
/// estimate from this receiver has a closed form where nothing blocks it
/// ([`LightFrom::unshadowed`]): a uniform sphere drawn from its projected cap (rays end on
/// its near side), or a rect or disk of uniform radiance (no shaping, no texture; a disk
/// under a similarity) inside a ball around it.
#[inline]
pub fn shadow_cone(from: &LightFrom, p: DVec3, ng: DVec3, offset: f64) -> Option<ShadowCone> {
    let (c, r, ends) = shadow_ball(from)?;
    ShadowCone::new(p, ng, offset, c, r, ends)
}

/// The pyramid of a rect or disk light's shadow rays from the surface point `p` (unit
/// geometric normal `ng`, rays leaving from `p + ng·offset`) over its
/// [`shadow_corners`] ([`ShadowPyramid`]), for a light of uniform radiance whose
/// corners all lie above the tangent plane: tighter than the cone of its ball, and there
/// where that ball reaches the horizon.
#[inline]
pub fn shadow_pyramid(from: &LightFrom, p: DVec3, ng: DVec3, offset: f64) -> Option<ShadowPyramid> {
    ShadowPyramid::new(p, ng, offset, &shadow_corners(from)?)
}

/// The corners its shadow rays end inside, when its closed form is searched through its
/// pyramid ([`shadow_pyramid`]): a rect's world corners; for a disk (under a
/// similarity), the square of side `2r` around it in its plane.
#[inline]
pub fn shadow_corners(from: &LightFrom) -> Option<[DVec3; 4]> {
    from.rect_corners().or_else(|| {
        // The square around the disk in its plane: every ray ends on the disk, inside it.
        let (c, axis, r) = from.world_disk()?;
        let (u, v) = axis.any_orthonormal_pair();
        let (u, v) = (u * r, v * r);
        Some([c - u - v, c + u - v, c + u + v, c - u + v])
    })
}

/// The ball holding every point a shadow ray of [`shadow_cone`] ends at, and
/// where in it they end: the sphere light itself (`inputs:radius`, scaled), the rect's
/// circumscribed ball, the disk's. The same from every receiver.
pub fn shadow_ball(from: &LightFrom) -> Option<(DVec3, f64, RayEnds)> {
    match from {
        LightFrom::Sphere(..) => {
            let (c, r, _) = from.sphere_cap()?;
            Some((c, r, RayEnds::NearSide))
        }
        LightFrom::Rect(l, _) if l.uniform_area() => {
            let (c, r) = l.bounding_sphere();
            Some((c, r, RayEnds::Anywhere))
        }
        LightFrom::Disk(..) => {
            let (c, _, r) = from.world_disk()?;
            Some((c, r, RayEnds::Anywhere))
        }
        _ => None,
    }
}
