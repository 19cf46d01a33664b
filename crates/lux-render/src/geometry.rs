//! The scene's triangles in an `obvhs` compressed-wide BVH (CWBVH): closest-hit queries for
//! camera and BSDF rays, any-hit queries for shadow rays.
//!
//! Traversal and the first intersection test run in `f32` (what obvhs provides); the hit is then
//! re-intersected in `f64` against the exact triangle so that positions, barycentrics and normals
//! carry double precision. Ray origins are offset along the geometric normal by
//! [`offset_scale`]`(p)`, which bounds the `f32` rounding of vertices and hit distances
//! (a few ulps of the largest coordinate involved), so shadow and continuation rays never
//! re-hit the surface they leave.
//!
//! Back faces: a triangle of a mesh that is not `doubleSided` is invisible from behind to
//! closest-hit queries (UsdGeom: single-sided geometry may be back-face culled), but it
//! occludes shadow rays from both sides, so a one-sided wall still casts a shadow.

use glam::{DVec2, DVec3, Vec3A};
use lux_usd::Scene;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use std::time::Duration;

/// Largest triangle count the renderer accepts (indices are `u32`).
pub const MAX_TRIANGLES: usize = 1 << 28;

/// One triangle's provenance: which mesh, which triangle of it, and its culling flag.
#[derive(Clone, Copy, Debug)]
struct PrimRef {
    mesh: u32,
    tri: u32,
    double_sided: bool,
}

/// A closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f64,
    /// Index into `Scene::meshes`.
    pub mesh: usize,
    /// Triangle index within the mesh.
    pub tri: usize,
    /// Barycentric coordinates of the hit: `p = (1 − b1 − b2)·a + b1·b + b2·c`.
    pub bary: DVec2,
    /// The hit point.
    pub p: DVec3,
    /// Unit geometric normal on the triangle's front side (USD orientation).
    pub ng: DVec3,
    /// True when the ray arrived from the back side (`ng · dir > 0`).
    pub back: bool,
}

/// The scene's triangles and their BVH.
pub struct Geometry {
    bvh: Option<CwBvh>,
    /// Triangles in BVH primitive order (f32, for traversal).
    tris: Vec<Triangle>,
    /// Per BVH primitive: its source.
    prims: Vec<PrimRef>,
}

/// `max(1, max |coordinate|)`-relative offset that clears the `f32` rounding of the BVH
/// triangles and of the `f32` hit distance (≈ 2⁻¹⁵ relative: about 256 ulps of `f32`).
#[inline]
pub fn offset_scale(p: DVec3) -> f64 {
    3.0e-5 * p.abs().max_element().max(1.0)
}

impl Geometry {
    /// Builds the BVH over every triangle of every mesh of `scene` (deterministic: obvhs builds
    /// single-threaded without its `parallel` feature). Degenerate triangles are kept out.
    pub fn new(scene: &Scene) -> Geometry {
        let mut tris = Vec::new();
        let mut prims = Vec::new();
        for (mi, m) in scene.meshes.iter().enumerate() {
            for (ti, t) in m.triangles.iter().enumerate() {
                let v = t.map(|i| m.positions.get(i as usize).copied());
                let [Some(a), Some(b), Some(c)] = v else {
                    continue;
                };
                if !(a.is_finite() && b.is_finite() && c.is_finite())
                    || (b - a).cross(c - a).length_squared() == 0.0
                {
                    continue;
                }
                if tris.len() >= MAX_TRIANGLES {
                    break;
                }
                tris.push(Triangle {
                    v0: a.as_vec3().into(),
                    v1: b.as_vec3().into(),
                    v2: c.as_vec3().into(),
                });
                prims.push(PrimRef {
                    mesh: mi as u32,
                    tri: ti as u32,
                    double_sided: m.double_sided,
                });
            }
        }
        if tris.is_empty() {
            return Geometry {
                bvh: None,
                tris,
                prims,
            };
        }
        let bvh = build_cwbvh_from_tris(
            &tris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        // Lay the triangles out in BVH order so that leaves index them directly.
        let tris_ordered: Vec<Triangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| tris[i as usize])
            .collect();
        let prims_ordered: Vec<PrimRef> = bvh
            .primitive_indices
            .iter()
            .map(|&i| prims[i as usize])
            .collect();
        Geometry {
            bvh: Some(bvh),
            tris: tris_ordered,
            prims: prims_ordered,
        }
    }

    /// Number of triangles in the BVH.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    fn ray(origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> Option<Ray> {
        let o = origin.as_vec3();
        let d = dir.as_vec3();
        if !(o.is_finite() && d.is_finite()) || d == glam::Vec3::ZERO {
            return None;
        }
        let tmax = if tmax.is_finite() {
            tmax as f32
        } else {
            f32::INFINITY
        };
        Some(Ray::new(Vec3A::from(o), Vec3A::from(d), tmin as f32, tmax))
    }

    /// Closest hit along `origin + t·dir`, `t ∈ (tmin, tmax)`, `dir` unit. Back faces of
    /// single-sided meshes are skipped.
    pub fn intersect(
        &self,
        scene: &Scene,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut hit, |r, id| {
            let tri = &self.tris[id];
            let t = tri.intersect(r);
            if t.is_finite() && !self.prims[id].double_sided {
                let n = (tri.v1 - tri.v0).cross(tri.v2 - tri.v0);
                if n.dot(r.direction) > 0.0 {
                    return f32::INFINITY;
                }
            }
            t
        });
        if !found {
            return None;
        }
        let id = hit.primitive_id as usize;
        let pr = self.prims[id];
        let mesh = &scene.meshes[pr.mesh as usize];
        let [ia, ib, ic] = mesh.triangles[pr.tri as usize];
        let (a, b, c) = (
            mesh.positions[ia as usize],
            mesh.positions[ib as usize],
            mesh.positions[ic as usize],
        );
        let n = (b - a).cross(c - a);
        let ng = n.normalize();
        // Exact f64 re-intersection with the triangle's plane and barycentrics.
        let denom = n.dot(dir);
        let t = if denom != 0.0 {
            n.dot(a - origin) / denom
        } else {
            hit.t as f64
        };
        let t = if t.is_finite() && t > 0.0 {
            t
        } else {
            hit.t as f64
        };
        let p = origin + t * dir;
        let bary = barycentric(p, a, b, c, n);
        Some(Hit {
            t,
            mesh: pr.mesh as usize,
            tri: pr.tri as usize,
            bary,
            p,
            ng,
            back: denom > 0.0,
        })
    }

    /// Distance to the closest triangle (either side) on `origin + t·dir`, `t ∈ (tmin, tmax)`:
    /// the occluder distance of `ShadowAPI`'s shadow distance and falloff.
    pub fn first_occluder(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> Option<f64> {
        let bvh = self.bvh.as_ref()?;
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        let mut hit = RayHit::none();
        bvh.ray_traverse(ray, &mut hit, |r, id| self.tris[id].intersect(r))
            .then_some(hit.t as f64)
    }

    /// True when any triangle (either side) lies on `origin + t·dir`, `t ∈ (tmin, tmax)`.
    pub fn occluded(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let Some(ray) = Self::ray(origin, dir, tmin, tmax) else {
            return false;
        };
        !bvh.ray_traverse_miss(ray, |r, id| self.tris[id].intersect(r))
    }
}

/// Barycentric coordinates (b1, b2) of `p` in triangle (a, b, c) with unnormalised normal `n`.
#[inline]
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3, n: DVec3) -> DVec2 {
    let inv = 1.0 / n.length_squared();
    let b1 = (c - a).cross(p - a).dot(n) * -inv;
    let b2 = (b - a).cross(p - a).dot(n) * inv;
    DVec2::new(b1, b2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_usd::{Mesh, Scene};

    fn quad(double_sided: bool, y: f64) -> Mesh {
        Mesh {
            double_sided,
            ..Mesh::new(
                "/q",
                vec![
                    DVec3::new(-1.0, y, -1.0),
                    DVec3::new(-1.0, y, 1.0),
                    DVec3::new(1.0, y, 1.0),
                    DVec3::new(1.0, y, -1.0),
                ],
                vec![[0, 1, 2], [0, 2, 3]],
            )
        }
    }

    pub(crate) fn scene_with(meshes: Vec<Mesh>) -> Scene {
        Scene {
            meshes,
            ..Scene::empty("test.usda")
        }
    }

    #[test]
    fn closest_hit_culling_and_barycentrics() {
        let scene = scene_with(vec![quad(false, 0.0), quad(true, 1.0)]);
        let g = Geometry::new(&scene);
        assert_eq!(g.triangle_count(), 4);
        // From above: hits the double-sided quad at y = 1 first, from its front.
        let h = g
            .intersect(
                &scene,
                DVec3::new(0.25, 5.0, 0.5),
                DVec3::NEG_Y,
                0.0,
                f64::INFINITY,
            )
            .unwrap();
        assert_eq!(h.mesh, 1);
        assert!((h.t - 4.0).abs() < 1e-12 && !h.back);
        assert!((h.ng - DVec3::Y).length() < 1e-12);
        // Barycentrics reproduce the point.
        let m = &scene.meshes[1];
        let [a, b, c] = m.triangles[h.tri].map(|i| m.positions[i as usize]);
        let q = (1.0 - h.bary.x - h.bary.y) * a + h.bary.x * b + h.bary.y * c;
        assert!((q - h.p).length() < 1e-12, "{q} vs {}", h.p);
        // From below: the single-sided floor is culled from behind; the double-sided quad is hit
        // from its back.
        let h = g
            .intersect(
                &scene,
                DVec3::new(0.25, -5.0, 0.5),
                DVec3::Y,
                0.0,
                f64::INFINITY,
            )
            .unwrap();
        assert_eq!(h.mesh, 1);
        assert!(h.back && (h.t - 6.0).abs() < 1e-12);
        // Shadow rays see both sides.
        assert!(g.occluded(DVec3::new(0.25, -5.0, 0.5), DVec3::Y, 0.0, 5.5));
        assert!(!g.occluded(DVec3::new(0.25, -5.0, 0.5), DVec3::Y, 0.0, 4.5));
        assert!(!g.occluded(DVec3::new(3.0, -5.0, 0.5), DVec3::Y, 0.0, 100.0));
        // tmax bounds the closest-hit query too.
        assert!(
            g.intersect(&scene, DVec3::new(0.25, 5.0, 0.5), DVec3::NEG_Y, 0.0, 3.5)
                .is_none()
        );
    }

    #[test]
    fn empty_and_degenerate_scenes() {
        let scene = scene_with(vec![]);
        let g = Geometry::new(&scene);
        assert!(
            g.intersect(&scene, DVec3::ZERO, DVec3::Y, 0.0, 1.0)
                .is_none()
        );
        assert!(!g.occluded(DVec3::ZERO, DVec3::Y, 0.0, 1.0));
        let mut q = quad(false, 0.0);
        q.positions[2] = DVec3::new(f64::NAN, 0.0, 0.0);
        q.triangles.push([0, 0, 1]);
        q.triangles.push([0, 9, 1]);
        let scene = scene_with(vec![q]);
        let g = Geometry::new(&scene);
        assert_eq!(g.triangle_count(), 0);
        // NaN rays are misses, not panics.
        assert!(
            g.intersect(&scene, DVec3::NAN, DVec3::Y, 0.0, 1.0)
                .is_none()
        );
    }
}
