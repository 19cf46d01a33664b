//! Instancing: one bottom-level BVH per prototype (in prototype space) and a top-level BVH over
//! the instances' world boxes.
//!
//! Memory grows with unique geometry: a prototype's triangles are stored once whatever its
//! instance count (≈ 72 bytes per triangle with its BVH); an instance costs one [`Placement`]
//! (two `f64` affine maps and a few scalars, 216 bytes) and its share of the top-level BVH and
//! of its primitive index (≈ 15 bytes): ≈ 230 bytes per instance, measured by the
//! `storage_grows_with_unique_geometry_not_instances` test.
//!
//! **Traversal.** The top-level BVH is traversed with the world ray `o + t·d`. At each instance
//! it meets, the ray is mapped to prototype space by the inverse instance transform `M⁻¹`,
//! `o' = M⁻¹·o`, `d' = M⁻¹·d` (`d'` is *not* renormalised, so that `t` is the same parameter
//! in both spaces: `M⁻¹·(o + t·d) = o' + t·d'`), and the prototype's BVH is traversed with the
//! current closest `t` as its `tmax`; a closer hit there shrinks the top-level ray too. Shadow
//! queries stop at the first occluder of any instance.
//!
//! **Sides.** Prototype triangles are wound with `(b − a) × (c − a)` towards the front in
//! prototype space, `n = (b − a) × (c − a)`. Mapped by `M` the winding normal becomes
//! `(Mb − Ma) × (Mc − Ma) = det(M)·M⁻ᵀ·n`, while the front normal (a normal, carried by the
//! inverse transpose) is `M⁻ᵀ·n`: a mirroring instance (`det M < 0`) has its front opposite to
//! its world-space winding. Back-face culling needs no correction in prototype space:
//! `(M⁻ᵀn)·d = n·(M⁻¹d) = n·d'`.

use super::blas::Blas;
use super::{Hit, Region, exact_hit, offset_scale};
use glam::{DAffine3, DMat3, DVec3, Vec3, Vec3A};
use lux_usd::Scene;
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::{Ray, RayHit};
use std::time::Duration;

/// Whether an instance of transform `to_world` can be drawn: finite, and its linear part of
/// finite non-zero determinant. (An instance is also left out when it lands outside the `f32`
/// range or its prototype has no valid triangle.)
pub fn drawable_transform(to_world: &glam::DMat4) -> bool {
    let det = DMat3::from_mat4(*to_world).determinant();
    to_world.is_finite() && det != 0.0 && det.is_finite()
}

/// One drawn instance: where its prototype's BVH sits in the world.
#[derive(Clone, Copy, Debug)]
struct Placement {
    /// Index into `Scene::instances`.
    instance: u32,
    /// Index into [`Instances::blas`].
    blas: u32,
    /// Prototype → world: the affine part of `Instance::to_world`, applied exactly as
    /// `DMat4::transform_point3` does (same operations, same bits).
    to_world: DAffine3,
    /// World → prototype, `to_world⁻¹`.
    from_world: DAffine3,
    /// `det M < 0`: the front side is opposite to the world-space winding.
    mirror: bool,
    /// `M = s·Q`, `Q` orthogonal (within 1e-9 relative): a similarity (rotation, mirror,
    /// uniform scale `s` = `stretch`), under which shadow regions map to prototype space.
    similar: bool,
    /// `s = √‖MᵀM‖_∞` (the largest absolute row sum of `MᵀM`, `M` the linear part): no
    /// prototype-space length grows by more than `s` in world space, as
    /// `σ_max(M)² = ρ(MᵀM) ≤ ‖MᵀM‖_∞`. Exact (1, up to rounding) for rotations, and at most
    /// `√3·σ_max` in general.
    stretch: f64,
}

impl Placement {
    /// The world ray `o + t·d` in prototype space, same `t` (see the module doc), as an `f32`
    /// obvhs ray over `[tmin, tmax]`. `None` when it does not fit in `f32`.
    #[inline]
    fn local_ray(&self, o: DVec3, d: DVec3, tmin: f32, tmax: f32) -> Option<Ray> {
        let lo = self.from_world.transform_point3(o).as_vec3();
        let ld = self.from_world.transform_vector3(d).as_vec3();
        if !(lo.is_finite() && ld.is_finite()) || ld == Vec3::ZERO {
            return None;
        }
        Some(Ray::new(Vec3A::from(lo), Vec3A::from(ld), tmin, tmax))
    }
}

/// A hit found in an instance: which placement, which primitive of its prototype's BVH, and
/// the `f32` ray parameter.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InstanceHit {
    placement: u32,
    prim: u32,
    /// `f32` distance found by the traversal.
    pub t: f32,
}

/// The instances of a scene and the prototypes they draw.
pub(crate) struct Instances {
    /// Top-level BVH over the placements' world boxes.
    pub(crate) tlas: CwBvh,
    /// Placements in top-level BVH primitive order.
    placements: Vec<Placement>,
    /// One BVH per drawn prototype, in prototype space.
    blas: Vec<Blas>,
    /// `f64` world bounds of every placement (each its prototype's box mapped to the world).
    pub bounds: (DVec3, DVec3),
    /// Triangles drawn, counting every instance's (what flattening would store).
    pub drawn_triangles: u64,
}

impl Instances {
    /// Builds the prototype BVHs (only for prototypes that have an instance, in prototype
    /// order) and the top-level BVH over the drawable instances. A mesh belongs to the
    /// prototype named by its `Mesh::prototype`. Instances are skipped when their prototype
    /// index is out of range or has no valid triangle, or their transform is not finite, is
    /// singular, or puts the instance outside the `f32` range. `None` when nothing is drawn.
    pub fn build(scene: &Scene, stored: &mut usize) -> Option<Instances> {
        let np = scene.prototypes.len();
        if scene.instances.is_empty() || np == 0 {
            return None;
        }
        let mut proto_meshes: Vec<Vec<usize>> = vec![Vec::new(); np];
        for (mi, m) in scene.meshes.iter().enumerate() {
            if let Some(p) = m.prototype
                && p < np
            {
                proto_meshes[p].push(mi);
            }
        }
        let usable = |i: &lux_usd::Instance| i.prototype < np && drawable_transform(&i.to_world);
        let mut drawn = vec![false; np];
        for i in scene.instances.iter().take(u32::MAX as usize) {
            if usable(i) {
                drawn[i.prototype] = true;
            }
        }
        let mut blas_of = vec![None; np];
        let mut blas = Vec::new();
        for p in 0..np {
            if drawn[p]
                && let Some(b) = Blas::build(scene, proto_meshes[p].iter().copied(), stored)
            {
                blas_of[p] = Some(blas.len() as u32);
                blas.push(b);
            }
        }
        let mut placements = Vec::new();
        let mut boxes = Vec::new();
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut drawn_triangles = 0u64;
        for (ii, inst) in scene.instances.iter().enumerate().take(u32::MAX as usize) {
            if !usable(inst) {
                continue;
            }
            let Some(bi) = blas_of[inst.prototype] else {
                continue;
            };
            let b = &blas[bi as usize];
            let to_world = DAffine3::from_mat4(inst.to_world);
            let m = to_world.matrix3;
            let mtm = m.transpose() * m;
            let stretch = [mtm.x_axis, mtm.y_axis, mtm.z_axis]
                .map(|r| r.abs().element_sum())
                .into_iter()
                .fold(0.0, f64::max)
                .sqrt();
            let (plo, phi) = b.bounds;
            let (wlo, whi) =
                (0..8).fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), k: u32| {
                    let c = DVec3::select(
                        glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0),
                        phi,
                        plo,
                    );
                    let w = to_world.transform_point3(c);
                    (l.min(w), h.max(w))
                });
            // Pad the box by far more than the f32 rounding of the box itself (2⁻²⁴ relative),
            // of the prototype's f32 triangles seen through M (s · 2⁻²⁴ |p'|) and of the
            // ray mapped into prototype space, so that the f32 top level never misses a hit
            // the prototype level would find.
            let scale = 1.0f64
                .max(wlo.abs().max_element())
                .max(whi.abs().max_element())
                .max(stretch * plo.abs().max(phi.abs()).max_element());
            let pad = DVec3::splat(1e-5 * scale);
            let (flo, fhi) = ((wlo - pad).as_vec3(), (whi + pad).as_vec3());
            if !(flo.is_finite() && fhi.is_finite()) {
                continue;
            }
            lo = lo.min(wlo);
            hi = hi.max(whi);
            drawn_triangles += b.len() as u64;
            boxes.push(Aabb::new(flo.into(), fhi.into()));
            placements.push(Placement {
                instance: ii as u32,
                blas: bi,
                to_world,
                from_world: to_world.inverse(),
                mirror: m.determinant() < 0.0,
                similar: {
                    let s2 = mtm.x_axis.x;
                    let diff = mtm - DMat3::from_diagonal(DVec3::splat(s2));
                    [diff.x_axis, diff.y_axis, diff.z_axis]
                        .iter()
                        .all(|c| c.abs().max_element() <= 1e-9 * s2)
                },
                stretch,
            });
        }
        if placements.is_empty() {
            return None;
        }
        let mut tlas = build_cwbvh(
            &boxes,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        tlas.nodes.shrink_to_fit();
        let placements = tlas
            .primitive_indices
            .iter()
            .map(|&i| placements[i as usize])
            .collect();
        Some(Instances {
            tlas,
            placements,
            blas,
            bounds: (lo, hi),
            drawn_triangles,
        })
    }

    /// Number of drawn instances.
    pub fn len(&self) -> usize {
        self.placements.len()
    }

    /// Triangles stored in the prototype BVHs (each prototype once).
    pub fn stored_triangles(&self) -> usize {
        self.blas.iter().map(Blas::len).sum()
    }

    /// Bytes held by the top-level BVH, the placements and the prototype BVHs.
    pub fn heap_bytes(&self) -> usize {
        self.tlas.nodes.capacity() * size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.tlas.primitive_indices.capacity() * size_of::<u32>()
            + self.placements.capacity() * size_of::<Placement>()
            + self.blas.capacity() * size_of::<Blas>()
            + self.blas.iter().map(Blas::heap_bytes).sum::<usize>()
    }

    /// Closest instanced triangle on the world ray `o + t·d` (`ray` is its `f32` form, its
    /// `tmax` the closest distance found so far); with `cull`, back faces of single-sided
    /// meshes are skipped (closest-hit queries), else either side counts (occluder queries).
    #[inline]
    pub fn closest(&self, o: DVec3, d: DVec3, ray: Ray, cull: bool) -> Option<InstanceHit> {
        let mut best = None;
        let mut top = RayHit::none();
        self.tlas.ray_traverse(ray, &mut top, |r, k| {
            let pl = &self.placements[k];
            let Some(local) = pl.local_ray(o, d, r.tmin, r.tmax) else {
                return f32::INFINITY;
            };
            let blas = &self.blas[pl.blas as usize];
            let mut h = RayHit::none();
            let found = if cull {
                blas.closest(local, &mut h)
            } else {
                blas.nearest(local, &mut h)
            };
            if !found {
                return f32::INFINITY;
            }
            best = Some(InstanceHit {
                placement: k as u32,
                prim: h.primitive_id,
                t: h.t,
            });
            h.t
        });
        best
    }

    /// The mesh (index into `Scene::meshes`) and instance (index into `Scene::instances`) of
    /// an instanced hit.
    #[inline]
    pub fn geometry_of(&self, h: InstanceHit) -> (usize, usize) {
        let pl = &self.placements[h.placement as usize];
        let pr = self.blas[pl.blas as usize].prims[h.prim as usize];
        (pr.mesh as usize, pl.instance as usize)
    }

    /// True when any instanced triangle (either side) lies on `ray`, the `f32` form of
    /// `o + t·d`; stops at the first one found.
    #[inline]
    pub fn any(&self, o: DVec3, d: DVec3, ray: Ray) -> bool {
        !self.tlas.ray_traverse_miss(ray, |r, k| {
            let pl = &self.placements[k];
            match pl.local_ray(o, d, r.tmin, r.tmax) {
                // Any value below tmax ends the traversal.
                Some(local) if self.blas[pl.blas as usize].any(local) => f32::NEG_INFINITY,
                _ => f32::INFINITY,
            }
        })
    }

    /// Whether some instance may block a ray of `region` (conservative: `false` only when none
    /// can). An instance whose (padded, `f32`) world box meets the region is searched inside
    /// when it is a similarity (`Placement::similar`): the region mapped to prototype space
    /// ([`Region::to_prototype`], its margin grown by 1e-5 of the prototype's and the
    /// mapped translation's scale, for the `f32` prototype triangles and the `f32` mapping of
    /// shadow rays), tested against the prototype's triangles; any other counts as a blocker.
    pub fn may_block<R: Region>(&self, region: &R) -> bool {
        super::region_search(&self.tlas, region, |k| {
            let pl = &self.placements[k];
            if !pl.similar {
                return true;
            }
            let blas = &self.blas[pl.blas as usize];
            let (s, t) = (pl.stretch, pl.to_world.translation);
            let (lo, hi) = blas.bounds;
            let scale = lo.abs().max(hi.abs()).max_element().max(1.0) + t.length() / s;
            let local = region.to_prototype(&(pl.from_world.matrix3 * s), t, s, 1e-5 * scale);
            blas.cone_blocker(&local, &|_| true).is_some()
        })
        .is_some()
    }

    /// The exact hit of `h` on `origin + t·dir`: the prototype triangle's vertices mapped to
    /// the world in `f64` (`M·v`, the same bits as flattening the instance), then
    /// [`exact_hit`] with the front flipped for a mirroring instance. The ray clearance is
    /// `max(offset_scale(p), s · offset_scale(p'))`, `p' = M⁻¹p`, `s ≥ σ_max(M)` (see
    /// `Placement::stretch`): the prototype's `f32` rounding is relative to prototype-space
    /// coordinates, and a world distance `h` off the plane is a prototype-space distance
    /// `h·|M⁻ᵀn̂| ≥ h / σ_max(M) ≥ h / s`, so `h = s · offset_scale(p')` clears it as
    /// [`offset_scale`] does for world geometry.
    pub fn hit(&self, scene: &Scene, h: InstanceHit, origin: DVec3, dir: DVec3) -> Hit {
        let pl = &self.placements[h.placement as usize];
        let pr = self.blas[pl.blas as usize].prims[h.prim as usize];
        let mesh = &scene.meshes[pr.mesh as usize];
        let [a, b, c] = mesh.triangles[pr.tri as usize]
            .map(|i| pl.to_world.transform_point3(mesh.positions[i as usize]));
        let e = exact_hit(a, b, c, pl.mirror, origin, dir, h.t);
        let offset =
            offset_scale(e.p).max(pl.stretch * offset_scale(pl.from_world.transform_point3(e.p)));
        Hit {
            t: e.t,
            mesh: pr.mesh as usize,
            tri: pr.tri as usize,
            instance: Some(pl.instance as usize),
            bary: e.bary,
            p: e.p,
            ng: e.ng,
            back: e.back,
            offset,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placement_is_216_bytes() {
        // The per-instance cost the module doc states.
        assert_eq!(size_of::<Placement>(), 216);
    }
}
