//! usdrecord's defaults where a stage is silent (OpenUSD `usdAppUtils/frameRecorder.cpp`): a
//! camera that frames the renderable geometry when the stage has none, and a camera light
//! (headlight) when it has no light.
//!
//! The framing camera is usdrecord's `_ComputeCameraToFrameStage`: a default `GfCamera`
//! (perspective, focal length 50, aperture 20.955 × 15.2908, so a horizontal field of view of
//! 2·atan(20.955 / 100) ≈ 23.5°) looking down −Z for a Y-up stage, or rotated +90° about X to
//! look down +Y for a Z-up stage, at the distance where the bounding box's half diagonal across
//! the image plane fills half the horizontal field of view, backed up by half the box's depth:
//!
//! ```text
//! r = ½·|(size_x, size_up)|      d = r / tan(½·fov_h) + ½·size_depth
//! Y up: eye = centre + (0, 0, d)      Z up: eye = centre − (0, d, 0)
//! ```
//!
//! Where lux departs: usdrecord keeps `GfCamera`'s clipping range (1, 10⁶), which clips all of a
//! scene smaller than a unit across; lux sets near = min(1, d/1000) and far = max(10⁶, 4·(d + r)).
//!
//! The camera light: usdrecord lights the stage with a positional GL light at the camera
//! without falloff (`GlfSimpleLight`); lux's physical stand-in is a DistantLight along the
//! camera's view direction with angle 0 (a delta light: its intensity is the illuminance) and
//! intensity π, so a white Lambertian surface facing the camera has radiance 1·cos θ — what the
//! GL diffuse term gives. The two differ only in that lux's light arrives parallel.

use crate::light::Light;
use crate::{Camera, Scene, UpAxis};
use glam::{DMat4, DQuat, DVec2, DVec3};
use lux_math::LightShape;

/// Prim path given to the framing camera (not a prim of the stage).
pub const FRAMING_CAMERA_PATH: &str = "/__lux_default_camera";
/// Prim path given to the camera light (not a prim of the stage).
pub const CAMERA_LIGHT_PATH: &str = "/__lux_camera_light";

/// World-space axis-aligned bounds `(min, max)` of everything drawn: the geometry
/// ([`geometry_bounds`]) and the boundable lights' extents (rect, disk, sphere, cylinder).
/// `None` for a stage with nothing drawn.
pub fn world_bounds(scene: &Scene) -> Option<(DVec3, DVec3)> {
    let mut b = Grow::EMPTY;
    if let Some((lo, hi)) = geometry_bounds(scene) {
        b.add(lo);
        b.add(hi);
    }
    for l in &scene.lights {
        let local: Option<(DVec3, DVec3)> = match l.shape {
            LightShape::Rect { width, height } => Some((
                DVec3::new(-width / 2.0, -height / 2.0, 0.0),
                DVec3::new(width / 2.0, height / 2.0, 0.0),
            )),
            LightShape::Disk { radius } => Some((
                DVec3::new(-radius, -radius, 0.0),
                DVec3::new(radius, radius, 0.0),
            )),
            LightShape::Sphere { radius } => Some((DVec3::splat(-radius), DVec3::splat(radius))),
            LightShape::Cylinder { radius, length } => Some((
                DVec3::new(-length / 2.0, -radius, -radius),
                DVec3::new(length / 2.0, radius, radius),
            )),
            _ => None,
        };
        if let Some((lo, hi)) = local {
            corners(lo, hi).for_each(|c| b.add(l.light_to_world.transform_point3(c)));
        }
    }
    b.get()
}

/// World-space axis-aligned bounds `(min, max)` of the drawn geometry, as the scene holds it
/// (after subdivision refinement when [`Scene::refine_subdivision`] ran, posed skinned
/// meshes, curves and points): the vertices of world meshes, and for every instance the
/// transformed corners of its prototype's box (as `UsdGeomBBoxCache` aligns transformed
/// boxes). Lights and cameras are not geometry. `None` when nothing is drawn.
pub fn geometry_bounds(scene: &Scene) -> Option<(DVec3, DVec3)> {
    let mut world = Grow::EMPTY;
    let mut proto_bounds = vec![Grow::EMPTY; scene.prototypes.len()];
    for m in &scene.meshes {
        // Every point, as UsdGeom's extent counts them.
        let b = match m.prototype {
            None => Some(&mut world),
            Some(pi) => proto_bounds.get_mut(pi),
        };
        if let Some(b) = b {
            m.positions.iter().for_each(|&p| b.add(p));
        }
    }
    for inst in &scene.instances {
        if let Some((l, h)) = proto_bounds.get(inst.prototype).and_then(|b| b.get()) {
            corners(l, h).for_each(|c| world.add(inst.to_world.transform_point3(c)));
        }
    }
    world.get()
}

/// An axis-aligned box grown point by point; non-finite points are left out.
#[derive(Clone, Copy)]
struct Grow {
    lo: DVec3,
    hi: DVec3,
}

impl Grow {
    /// Holds nothing.
    const EMPTY: Grow = Grow {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    /// Grows to hold `p` (when finite).
    fn add(&mut self, p: DVec3) {
        if p.is_finite() {
            self.lo = self.lo.min(p);
            self.hi = self.hi.max(p);
        }
    }

    /// `(min, max)`, `None` when empty.
    fn get(self) -> Option<(DVec3, DVec3)> {
        (self.lo.x <= self.hi.x).then_some((self.lo, self.hi))
    }
}

/// The 8 corners of the box `lo..hi`.
fn corners(lo: DVec3, hi: DVec3) -> impl Iterator<Item = DVec3> {
    (0..8).map(move |k| {
        DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// usdrecord's camera framing `bounds` (see the module docs); `None` bounds (nothing drawn)
/// give the default camera at the origin looking down −Z (or +Y for Z up).
pub fn framing_camera(bounds: Option<(DVec3, DVec3)>, up: UpAxis) -> Camera {
    let mut cam = Camera::with_defaults(FRAMING_CAMERA_PATH, DMat4::IDENTITY);
    let (centre, size) = match bounds {
        Some((lo, hi)) => ((lo + hi) * 0.5, hi - lo),
        None => (DVec3::ZERO, DVec3::ZERO),
    };
    let corner = match up {
        UpAxis::Y => DVec2::new(size.x, size.y) / 2.0,
        UpAxis::Z => DVec2::new(size.x, size.z) / 2.0,
    };
    let radius = corner.length();
    let half_fov = (cam.horizontal_aperture / (2.0 * cam.focal_length)).atan();
    let mut distance = radius / half_fov.tan();
    distance += match up {
        UpAxis::Y => size.z / 2.0,
        UpAxis::Z => size.y / 2.0,
    };
    cam.camera_to_world = match up {
        UpAxis::Y => DMat4::from_translation(centre + DVec3::new(0.0, 0.0, distance)),
        UpAxis::Z => DMat4::from_rotation_translation(
            DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
            centre + DVec3::new(0.0, -distance, 0.0),
        ),
    };
    let near = if distance > 0.0 {
        (distance / 1000.0).min(1.0)
    } else {
        1.0
    };
    cam.clipping_range = DVec2::new(near, (4.0 * (distance + radius)).max(1.0e6));
    cam
}

/// usdrecord's camera light for `camera`: a DistantLight along the camera's view direction
/// (local −Z), angle 0, intensity π (see the module docs).
pub fn camera_light(camera: &Camera) -> Light {
    let rotation = DQuat::from_mat4(&camera.camera_to_world).normalize();
    let mut l = Light::with_defaults(
        CAMERA_LIGHT_PATH,
        LightShape::Distant { angle_deg: 0.0 },
        DMat4::from_quat(rotation),
    );
    l.params.intensity = std::f64::consts::PI;
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framing_matches_usdrecord() {
        // a 4 × 2 × 1 box centred at (1, 2, 3), Y up
        let b = Some((DVec3::new(-1.0, 1.0, 2.5), DVec3::new(3.0, 3.0, 3.5)));
        let c = framing_camera(b, UpAxis::Y);
        let half_fov = (20.955f64 / 100.0).atan();
        let d = (5.0f64).sqrt() / half_fov.tan() + 0.5;
        let eye = c.camera_to_world.transform_point3(DVec3::ZERO);
        assert!(
            (eye - DVec3::new(1.0, 2.0, 3.0 + d)).length() < 1e-12,
            "{eye}"
        );
        let look = c.camera_to_world.transform_vector3(DVec3::NEG_Z);
        assert!((look - DVec3::NEG_Z).length() < 1e-15);
        // Z up: looks along +Y with +Z up, backed off along −Y by r/tan + size_y/2
        let c = framing_camera(b, UpAxis::Z);
        let d = (4.0f64 + 0.25).sqrt() / half_fov.tan() + 1.0;
        let eye = c.camera_to_world.transform_point3(DVec3::ZERO);
        assert!(
            (eye - DVec3::new(1.0, 2.0 - d, 3.0)).length() < 1e-12,
            "{eye}"
        );
        let look = c.camera_to_world.transform_vector3(DVec3::NEG_Z);
        let up = c.camera_to_world.transform_vector3(DVec3::Y);
        assert!((look - DVec3::Y).length() < 1e-15, "{look}");
        assert!((up - DVec3::Z).length() < 1e-15, "{up}");
    }

    #[test]
    fn camera_light_points_where_the_camera_looks() {
        let cam = framing_camera(Some((DVec3::ZERO, DVec3::ONE)), UpAxis::Z);
        let l = camera_light(&cam);
        assert!((l.axis() - DVec3::Y).length() < 1e-15, "{}", l.axis());
        assert_eq!(l.params.intensity, std::f64::consts::PI);
        assert_eq!(l.shape, LightShape::Distant { angle_deg: 0.0 });
    }
}
