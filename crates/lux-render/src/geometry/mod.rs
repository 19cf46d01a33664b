//! The scene's triangles in `obvhs` compressed-wide BVHs (CWBVH): closest-hit queries for
//! camera and BSDF rays, any-hit queries for shadow rays. (The analytic area lights have a BVH
//! of their own in the light set, `light/shapes.rs`.)
//!
//! Two levels (`geometry/instances.rs`): the world-space meshes in one BVH
//! (`geometry/blas.rs`), exactly as a scene without instancing; each instanced prototype's
//! meshes in one BVH in prototype space, and a top-level BVH over the instances' world boxes.
//! A query traverses the world BVH, then the instances with the closest distance found so far;
//! the closer hit wins (the world one on a tie).
//!
//! Traversal and the first intersection test run in `f32` (what obvhs provides); the hit is then
//! re-intersected in `f64` against the exact triangle (an instance's prototype triangle mapped to
//! the world in `f64`) so that positions, barycentrics and normals carry double precision. Ray
//! origins are offset along the geometric normal by [`Hit::offset`] (for world geometry
//! [`offset_scale`]`(p)`), which bounds the `f32` rounding of vertices and hit distances (a few
//! ulps of the largest coordinate involved), so shadow and continuation rays never re-hit the
//! surface they leave.
//!
//! Shadow rays ([`Geometry::occluded`], [`Geometry::first_occluder`]) go through the world
//! BVH, or through any other BVH of the same surfaces (`*_through`: the exact visibility's
//! BVH of card outlines, `visibility/shadows.rs`). [`Region`] is the search a region of rays
//! (a cone, a pyramid, a frustum) makes of a BVH's nodes and triangles (`region.rs`).
//!
//! Back faces: a triangle of a mesh that is not `doubleSided` is invisible from behind to
//! closest-hit queries (UsdGeom: single-sided geometry may be back-face culled), but it
//! occludes shadow rays from both sides, so a one-sided wall still casts a shadow.

mod blas;
mod instances;
mod region;

pub(crate) use blas::{Blas, PrimRef, mesh_triangles};
use glam::{DVec2, DVec3, Vec3A};
pub(crate) use instances::Instances;
pub(crate) use instances::drawable_transform;
use lux_usd::Scene;
use obvhs::ray::{Ray, RayHit};
pub use region::Region;
pub(crate) use region::{
    above_all, child_boxes, child_mask, farthest_along, in_node_frame, outside_a_plane,
    region_search,
};

/// Largest triangle count the renderer stores (indices are `u32`): world triangles plus each
/// instanced prototype's triangles once.
pub const MAX_TRIANGLES: usize = 1 << 28;

/// A closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f64,
    /// Index into `Scene::meshes` (for an instance, its prototype's mesh).
    pub mesh: usize,
    /// Triangle index within the mesh.
    pub tri: usize,
    /// Index into `Scene::instances` of the instance hit; `None` for a world-space mesh.
    pub instance: Option<usize>,
    /// Barycentric coordinates of the hit on the mesh's triangle `[a, b, c]` (its own corner
    /// order; for an instance, the prototype triangle mapped to the world):
    /// `p = (1 − b1 − b2)·a + b1·b + b2·c`.
    pub bary: DVec2,
    /// The hit point (world space).
    pub p: DVec3,
    /// Unit geometric normal on the triangle's front side (USD orientation), world space: for
    /// an instance with transform `M`, along `M⁻ᵀ·((b − a) × (c − a))` of the prototype
    /// triangle, i.e. `sign(det M)·(Mb − Ma) × (Mc − Ma)`.
    pub ng: DVec3,
    /// True when the ray arrived from the back side (`ng · dir > 0`).
    pub back: bool,
    /// How far along `±ng` a ray leaving `p` must start to clear the `f32` rounding of the
    /// BVH geometry: [`offset_scale`]`(p)` for world meshes, more for an instance whose
    /// prototype coordinates are large (see the instance hit).
    pub offset: f64,
}

/// The first triangle on a shadow ray ([`Geometry::first_occluder_at`]): its distance and
/// which geometry it belongs to (for shadow linking).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occluder {
    /// The `f32` traversal distance along the (unit) ray direction.
    pub t: f64,
    /// Index into `Scene::meshes` (for an instance, its prototype's mesh).
    pub mesh: usize,
    /// Index into `Scene::instances`; `None` for a world-space mesh.
    pub instance: Option<usize>,
}

/// The scene's triangles and their BVHs.
pub struct Geometry {
    /// The world-space meshes (`Mesh::prototype == None`).
    world: Option<Blas>,
    /// Instanced prototypes and their placements.
    instances: Option<Instances>,
}

/// The indices of the world-space meshes of `scene` (those not in a prototype), in order.
pub(crate) fn world_meshes(scene: &Scene) -> impl Iterator<Item = usize> + Clone + '_ {
    (0..scene.meshes.len()).filter(|&i| scene.meshes[i].prototype.is_none())
}

/// `max(1, max |coordinate|)`-relative offset that clears the `f32` rounding of the BVH
/// triangles and of the `f32` hit distance (≈ 2⁻¹⁵ relative: about 256 ulps of `f32`).
#[inline]
pub fn offset_scale(p: DVec3) -> f64 {
    3.0e-5 * p.abs().max_element().max(1.0)
}

/// Part of a shadow ray's length kept clear before the light point it ends at: the `f32`
/// traversal's hit distances are approximate (measured: an emitting triangle returned up to
/// 2.6e-5 of the distance before its exact hit), and a mesh light is geometry, so without it
/// its own triangles would shadow it.
pub const SHADOW_CLEARANCE: f64 = 1e-4;

/// The `tmax` of a shadow ray towards the light point `point` at distance `dist`: short of it
/// by [`SHADOW_CLEARANCE`]`·dist` and [`offset_scale`]`(point)`, so that the surface the
/// point lies on never occludes it (occluders closer to a light than that are ignored).
#[inline]
pub fn shadow_tmax(dist: f64, point: DVec3) -> f64 {
    dist * (1.0 - SHADOW_CLEARANCE) - offset_scale(point)
}

/// The shadow ray from `origin` to the point `point` of an emitting surface that is geometry
/// (a mesh light): its unit direction and `tmax` ([`shadow_tmax`] of its length); `None` when
/// the two points coincide or the length is not finite.
///
/// A light sample's direction `wi` is taken from the shading point `p`, while shadow rays start
/// at `origin = p + δ·ng` ([`Hit::offset`]). Along `wi` from there a ray meets the emitter's
/// plane (normal `n`) `δ·|n·ng| / |n·wi|` before the sampled point: at grazing angles, and far
/// from the world origin where `δ` grows with the coordinates, more than the clearance
/// [`shadow_tmax`] keeps, and the emitter shadowed its own sample (measured: an emissive quad
/// 20 units from the origin lit the floor under it to 68 % of the closed form, at 100 units to
/// 0.6 %). Aimed at the point from `origin`, the ray meets the plane at its end.
#[inline]
pub fn shadow_ray_to(origin: DVec3, point: DVec3) -> Option<(DVec3, f64)> {
    let d = point - origin;
    let dist = d.length();
    (dist > 0.0 && dist.is_finite()).then(|| (d / dist, shadow_tmax(dist, point)))
}

/// The `f64` re-intersection of a ray with a triangle.
struct ExactHit {
    t: f64,
    p: DVec3,
    bary: DVec2,
    ng: DVec3,
    back: bool,
}

/// Re-intersects `origin + t·dir` with the plane of triangle `(a, b, c)` in `f64`:
/// `t = n·(a − o) / n·d` with `n = ±(b − a) × (c − a)` the front normal (`−` when `mirror`),
/// falling back to the traversal's `t_approx` when that is not a positive finite number;
/// barycentrics of `p = o + t·d` in the corner order `(a, b, c)`.
#[inline(always)]
fn exact_hit(
    a: DVec3,
    b: DVec3,
    c: DVec3,
    mirror: bool,
    origin: DVec3,
    dir: DVec3,
    t_approx: f32,
) -> ExactHit {
    let n = (b - a).cross(c - a);
    let front = if mirror { -n } else { n };
    // |n|², which `normalize` (the same value for ±n) and the barycentrics share.
    let len2 = n.length_squared();
    let ng = front * (1.0 / len2.sqrt());
    let denom = front.dot(dir);
    let t = if denom != 0.0 {
        front.dot(a - origin) / denom
    } else {
        t_approx as f64
    };
    let t = if t.is_finite() && t > 0.0 {
        t
    } else {
        t_approx as f64
    };
    let p = origin + t * dir;
    ExactHit {
        t,
        p,
        bary: barycentric(p, a, b, c, n, len2),
        ng,
        back: denom > 0.0,
    }
}

impl Geometry {
    /// Builds the world BVH over every triangle of the world-space meshes of `scene`, one BVH per
    /// instanced prototype and the top-level BVH over the instances (deterministic: obvhs builds
    /// single-threaded without its `parallel` feature). Degenerate triangles are kept out.
    pub fn new(scene: &Scene) -> Geometry {
        let mut stored = 0;
        let world = Blas::build(scene, world_meshes(scene), &mut stored);
        let instances = Instances::build(scene, &mut stored);
        Geometry { world, instances }
    }

    /// The world-space meshes' triangles and BVH.
    pub(crate) fn world(&self) -> Option<&Blas> {
        self.world.as_ref()
    }

    /// The instanced prototypes and their placements.
    pub(crate) fn instances(&self) -> Option<&Instances> {
        self.instances.as_ref()
    }

    /// Number of triangles stored in the BVHs: the world meshes' plus each drawn prototype's
    /// once, whatever its instance count.
    pub fn triangle_count(&self) -> usize {
        self.world.as_ref().map_or(0, Blas::len)
            + self
                .instances
                .as_ref()
                .map_or(0, Instances::stored_triangles)
    }

    /// Number of triangles drawn: the world meshes' plus every instance's prototype triangles
    /// (what flattening the instances would store).
    pub fn drawn_triangle_count(&self) -> u64 {
        self.world.as_ref().map_or(0, |w| w.len() as u64)
            + self.instances.as_ref().map_or(0, |i| i.drawn_triangles)
    }

    /// Number of drawn instances (`Scene::instances` minus the undrawable ones: out-of-range or
    /// empty prototype, non-finite or singular transform).
    pub fn instance_count(&self) -> usize {
        self.instances.as_ref().map_or(0, Instances::len)
    }

    /// Bytes held by the BVHs, their triangles and the instance placements.
    pub fn heap_bytes(&self) -> usize {
        self.world.as_ref().map_or(0, Blas::heap_bytes)
            + self.instances.as_ref().map_or(0, Instances::heap_bytes)
    }

    /// World-space bounds `(min, max)` of everything drawn, `None` when nothing is: the exact
    /// box of the world meshes' triangles, joined with each instance's prototype box mapped by
    /// its transform (the box of the 8 mapped corners: it contains the instance, and is exact
    /// for translations, scales and quarter turns).
    pub fn world_bounds(&self) -> Option<(DVec3, DVec3)> {
        let boxes = [
            self.world.as_ref().map(|w| w.bounds),
            self.instances.as_ref().map(|i| i.bounds),
        ];
        boxes
            .into_iter()
            .flatten()
            .reduce(|(l0, h0), (l1, h1)| (l0.min(l1), h0.max(h1)))
    }

    pub(crate) fn ray(origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> Option<Ray> {
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
        self.intersect_with(scene, origin, dir, tmin, tmax, true)
    }

    /// [`Geometry::intersect`] without back-face culling: the closest triangle from either
    /// side, as a shadow ray sees it. The direct integrator's BSDF rays use it, so that a
    /// light they reach is one a shadow ray would reach too (else a single-sided occluder seen
    /// from behind would shadow light samples but not BSDF samples, and MIS would be biased).
    pub fn intersect_any_side(
        &self,
        scene: &Scene,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Hit> {
        self.intersect_with(scene, origin, dir, tmin, tmax, false)
    }

    fn intersect_with(
        &self,
        scene: &Scene,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
        cull: bool,
    ) -> Option<Hit> {
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        if let Some(inst) = &self.instances {
            return self.intersect_instanced(inst, scene, ray, origin, dir, cull);
        }
        // Without instances, the world BVH alone (the code path of a scene without instancing).
        let world = self.world.as_ref()?;
        let mut hit = RayHit::none();
        let found = if cull {
            world.closest(ray, &mut hit)
        } else {
            world.nearest(ray, &mut hit)
        };
        found.then(|| Self::world_hit(world, scene, hit, origin, dir))
    }

    /// [`Geometry::intersect`] with instances: the world BVH, then the instances up to the
    /// world hit's distance; the closer hit wins, the world one on a tie.
    #[inline(never)]
    fn intersect_instanced(
        &self,
        inst: &Instances,
        scene: &Scene,
        ray: Ray,
        origin: DVec3,
        dir: DVec3,
        cull: bool,
    ) -> Option<Hit> {
        let mut hit = RayHit::none();
        let world = self.world.as_ref().filter(|w| {
            if cull {
                w.closest(ray, &mut hit)
            } else {
                w.nearest(ray, &mut hit)
            }
        });
        let mut r = ray;
        if world.is_some() {
            r.tmax = hit.t;
        }
        match inst.closest(origin, dir, r, cull) {
            Some(h) => Some(inst.hit(scene, h, origin, dir)),
            None => world.map(|w| Self::world_hit(w, scene, hit, origin, dir)),
        }
    }

    /// The exact hit of the world BVH's traversal hit `hit`.
    #[inline]
    pub(crate) fn world_hit(
        world: &Blas,
        scene: &Scene,
        hit: RayHit,
        origin: DVec3,
        dir: DVec3,
    ) -> Hit {
        let pr = world.prims[hit.primitive_id as usize];
        let mesh = &scene.meshes[pr.mesh as usize];
        let [ia, ib, ic] = mesh.triangles[pr.tri as usize];
        let (a, b, c) = (
            mesh.positions[ia as usize],
            mesh.positions[ib as usize],
            mesh.positions[ic as usize],
        );
        let e = exact_hit(a, b, c, false, origin, dir, hit.t);
        Hit {
            t: e.t,
            mesh: pr.mesh as usize,
            tri: pr.tri as usize,
            instance: None,
            bary: e.bary,
            p: e.p,
            ng: e.ng,
            back: e.back,
            offset: offset_scale(e.p),
        }
    }

    /// Distance to the closest triangle (either side) on `origin + t·dir`, `t ∈ (tmin, tmax)`:
    /// the occluder distance of `ShadowAPI`'s shadow distance and falloff (the `f32` traversal
    /// distance; for an instance, found in prototype space with the same parameter `t`).
    pub fn first_occluder(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> Option<f64> {
        self.first_occluder_through(self.world.as_ref(), origin, dir, tmin, tmax)
    }

    /// [`Geometry::first_occluder`] with `blockers` standing for the world meshes (a BVH of
    /// the same surfaces: `crate::visibility`'s of flat cards' outlines): the distance of
    /// [`Geometry::first_occluder_at_through`]'s occluder.
    pub(crate) fn first_occluder_through(
        &self,
        blockers: Option<&Blas>,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<f64> {
        self.first_occluder_at_through(blockers, origin, dir, tmin, tmax)
            .map(|o| o.t)
    }

    /// [`Geometry::first_occluder`] with the geometry it met: the closest triangle (either
    /// side) on `origin + t·dir`, `t ∈ (tmin, tmax)`, its mesh and instance (shadow linking
    /// asks whether it casts a light's shadow).
    pub fn first_occluder_at(
        &self,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Occluder> {
        self.first_occluder_at_through(self.world.as_ref(), origin, dir, tmin, tmax)
    }

    /// [`Geometry::first_occluder_at`] through `blockers` ([`Geometry::first_occluder_through`]).
    pub(crate) fn first_occluder_at_through(
        &self,
        blockers: Option<&Blas>,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Occluder> {
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        let mut hit = RayHit::none();
        let world = blockers.filter(|w| w.nearest(ray, &mut hit));
        let mut r = ray;
        if world.is_some() {
            r.tmax = hit.t;
        }
        if let Some(inst) = &self.instances
            && let Some(h) = inst.closest(origin, dir, r, false)
        {
            let (mesh, instance) = inst.geometry_of(h);
            return Some(Occluder {
                t: h.t as f64,
                mesh,
                instance: Some(instance),
            });
        }
        world.map(|w| Occluder {
            t: hit.t as f64,
            mesh: w.prims[hit.primitive_id as usize].mesh as usize,
            instance: None,
        })
    }

    /// True when any triangle (either side) lies on `origin + t·dir`, `t ∈ (tmin, tmax)`.
    pub fn occluded(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> bool {
        self.occluded_through(self.world.as_ref(), origin, dir, tmin, tmax)
    }

    /// [`Geometry::occluded`] through `blockers` ([`Geometry::first_occluder_through`]).
    pub(crate) fn occluded_through(
        &self,
        blockers: Option<&Blas>,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> bool {
        let Some(ray) = Self::ray(origin, dir, tmin, tmax) else {
            return false;
        };
        if let Some(inst) = &self.instances {
            return Self::occluded_instanced(blockers, inst, ray, origin, dir);
        }
        blockers.is_some_and(|w| w.any(ray))
    }

    /// [`Geometry::occluded`] with instances: the world BVH, then the instances.
    #[inline(never)]
    fn occluded_instanced(
        blockers: Option<&Blas>,
        inst: &Instances,
        ray: Ray,
        origin: DVec3,
        dir: DVec3,
    ) -> bool {
        blockers.is_some_and(|w| w.any(ray)) || inst.any(origin, dir, ray)
    }
}

/// Barycentric coordinates (b1, b2) of `p` in triangle (a, b, c) with unnormalised normal `n`
/// of squared length `len2`.
#[inline]
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3, n: DVec3, len2: f64) -> DVec2 {
    let inv = 1.0 / len2;
    let b1 = (c - a).cross(p - a).dot(n) * -inv;
    let b2 = (b - a).cross(p - a).dot(n) * inv;
    DVec2::new(b1, b2)
}

#[cfg(test)]
pub(crate) mod tests {
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

    /// A subdivided floor and a subdivided tilted card (planar tilings) and a bent strip (not
    /// planar): the shadow BVH holds the two cards as 2 triangles each and the strip as it is,
    /// and answers 20,000 shadow rays (from the floor, from above, grazing, through the card's
    /// edges) as the world BVH does, with the same first occluder's mesh and distance.
    /// The exact hit's normal is `normalize(±(b − a) × (c − a))` and its barycentrics use
    /// `1/|n|²`, bit for bit, with the squared length computed once for both.
    #[test]
    fn exact_hit_normal_and_barycentrics() {
        let mut rng = lux_sample::SplitMix64::new(11);
        let mut v = || DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 7.0 - 3.0;
        for i in 0..500 {
            let (a, b, c, o) = (v(), v(), v(), v() * 4.0);
            let target = (a + b + c) / 3.0;
            let dir = (target - o).normalize();
            let mirror = i % 2 == 1;
            let e = exact_hit(a, b, c, mirror, o, dir, 1.0);
            let n = (b - a).cross(c - a);
            let ng = if mirror { -n } else { n }.normalize();
            assert_eq!(
                e.ng.to_array().map(f64::to_bits),
                ng.to_array().map(f64::to_bits)
            );
            let inv = 1.0 / n.length_squared();
            let want = DVec2::new(
                (c - a).cross(e.p - a).dot(n) * -inv,
                (b - a).cross(e.p - a).dot(n) * inv,
            );
            assert_eq!(
                e.bary.to_array().map(f64::to_bits),
                want.to_array().map(f64::to_bits)
            );
        }
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
