//! What a camera ray meets first, shared by every integrator: a camera-visible light (its
//! front's radiance; its back is black), the background of camera-visible lights at infinity
//! where the ray escapes (opaque where a dome is shown, else alpha 0), or a surface with the
//! glow it shows (a mesh light's, a textured or primvar emission).

use super::{CameraRay, Ctx, closest};
use crate::geometry::Hit;
use crate::light::{Light, Seen};
use crate::visibility::{CameraHit, Visibility};
use crate::world::World;
use glam::DVec3;

/// What a camera ray meets first ([`camera_vertex`]).
pub(super) enum CameraVertex {
    /// The path ends: radiance and alpha.
    Done(DVec3, f64),
    /// A surface hit, with the glow it shows. The caller shades it (`Materials::at`) into its
    /// own frame: a `SurfacePoint` is large enough that moving it out of an enum costs a
    /// `memcpy` per camera ray.
    Surface(Hit, DVec3),
}

/// What the camera ray `ray` meets first in `w`: the tile's hint from `vis` answers when it can
/// (a tile whose rays meet nothing, a short list of triangles), else the BVH.
#[inline(always)]
pub(super) fn camera_vertex(
    w: &World,
    vis: &Visibility,
    ray: &CameraRay,
    ctx: &mut Ctx,
) -> CameraVertex {
    let lights = &w.lights.lights;
    ctx.counters.rays += 1;
    let hit = match vis.camera_hit(w, &ctx.vis.tile, (ray.o, ray.d, ray.tmin, ray.tmax)) {
        // (no triangle, no visible light, no background: what the rest would find)
        CameraHit::Empty => return CameraVertex::Done(DVec3::ZERO, 0.0),
        CameraHit::Known(hit) => hit,
        CameraHit::Trace => closest(w, ray.o, ray.d, ray.tmin, ray.tmax, false),
    };
    let t_best = hit.map_or(ray.tmax, |h| h.t);
    if let Some((i, h)) = w
        .lights
        .closest_light(ray.o, ray.d, ray.tmin, t_best, |l| l.base().camera_visible)
    {
        let rgb = if h.front {
            lights[i].le(h.local, -ray.d, Seen::Camera)
        } else {
            DVec3::ZERO
        };
        return CameraVertex::Done(rgb, 1.0);
    }
    let Some(hit) = hit else {
        let background = &w.lights.background;
        let bg: DVec3 = background.iter().map(|&i| lights[i].le_escape(ray.d)).sum();
        let alpha = if background.is_empty() { 0.0 } else { 1.0 };
        return CameraVertex::Done(bg, alpha);
    };
    let mut glow = DVec3::ZERO;
    if w.textured_emission {
        glow += w.materials.emission(w.scene, &hit);
    }
    // A mesh light's own glow, seen directly.
    if let Some(li) = w.lights.light_of(hit.mesh, hit.instance) {
        let l = &lights[li];
        glow += match l {
            // materialSyncMode: the material's glow, not the light's radiance.
            Light::Mesh(m) if m.glow.is_some() => m.glow.unwrap_or_default(),
            _ => l.le(l.base().to_local(hit.p), -ray.d, Seen::Camera),
        };
    }
    CameraVertex::Surface(hit, glow)
}
