//! One set of triangles in one space and its obvhs CWBVH: the world-space meshes, or the
//! meshes of one instancing prototype in prototype space (a bottom-level BVH).
//!
//! Triangles are stored once, in `f32`, in BVH leaf order; each keeps a [`PrimRef`] back to its
//! mesh and triangle so that hits are re-intersected in `f64` against the scene's own vertices.

use super::MAX_TRIANGLES;
use super::Region;
use glam::{DVec3, Vec3A};
use lux_usd::Scene;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use std::time::Duration;

/// One triangle's provenance: which mesh, which triangle of it, and its culling flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PrimRef {
    /// Index into `Scene::meshes`.
    pub mesh: u32,
    /// Triangle index within the mesh (in [`super::Geometry`]'s shadow BVH, for a planar mesh
    /// it replaced by its outline, the index of the outline's fan triangle: never shaded).
    pub tri: u32,
    /// The mesh's `doubleSided`: false = invisible from behind to closest-hit queries.
    pub double_sided: bool,
}

/// The triangles of mesh `mi` of `scene` whose indices are in range, with their provenance.
pub(crate) fn mesh_triangles(
    scene: &Scene,
    mi: usize,
) -> impl Iterator<Item = (PrimRef, [DVec3; 3])> + '_ {
    let m = &scene.meshes[mi];
    m.triangles.iter().enumerate().filter_map(move |(ti, t)| {
        let [Some(a), Some(b), Some(c)] = t.map(|i| m.positions.get(i as usize).copied()) else {
            return None;
        };
        let prim = PrimRef {
            mesh: mi as u32,
            tri: ti as u32,
            double_sided: m.double_sided,
        };
        Some((prim, [a, b, c]))
    })
}

/// Triangles of some meshes, in their meshes' common space, and their BVH.
pub(crate) struct Blas {
    bvh: CwBvh,
    /// Triangles in BVH primitive order (`f32`, for traversal), with their normals.
    tris: Vec<RayTriangle>,
    /// Per BVH primitive: its source.
    pub prims: Vec<PrimRef>,
    /// `f64` bounds of the stored triangles' vertices (the meshes' space).
    pub bounds: (DVec3, DVec3),
    /// How many distinct triangles it holds (`tris` may hold a large one more than once: the
    /// pieces of its box that [`SMALL_BVH`]'s pre-splitting made).
    count: usize,
}

/// Triangles up to which a BVH is built with obvhs's `very_slow_build` (large triangles'
/// boxes pre-split, every node reinserted where it lowers the SAH cost) rather than its
/// `medium_build`: path-traced render time −6 % on the Cornell box, −3 to −4 % on the
/// clutter scenes, direct light −1 to −3 %, for a build of about 0.13 µs a triangle more
/// (StandardShaderBall, 222,992 triangles: +0.03 s on a 0.18 s load; BENCHMARKS.md, issue 39).
/// Above it the extra build time is not surely won back, and the medium build stays.
pub(crate) const SMALL_BVH: usize = 1 << 16;

impl Blas {
    /// Builds the BVH over every valid triangle of the meshes `meshes` (in order) of `scene`:
    /// triangles with an out-of-range index, a non-finite vertex or zero area are kept out, and
    /// no triangle is stored once `*stored` (the count over every BVH of the scene) reaches
    /// [`MAX_TRIANGLES`]. `None` when no triangle remains. Deterministic: obvhs builds on
    /// rayon's threads (its `parallel` feature) the same BVH for any number of them (test
    /// `bvh_builds_are_the_same_for_any_thread_count`).
    pub fn build(
        scene: &Scene,
        meshes: impl Iterator<Item = usize>,
        stored: &mut usize,
    ) -> Option<Blas> {
        Blas::from_triangles(meshes.flat_map(|mi| mesh_triangles(scene, mi)), stored)
    }

    /// [`Blas::build`] over the triangles `items` (each with where it comes from): those with
    /// a non-finite vertex or zero area are kept out.
    pub fn from_triangles(
        items: impl Iterator<Item = (PrimRef, [DVec3; 3])>,
        stored: &mut usize,
    ) -> Option<Blas> {
        let mut tris = Vec::new();
        let mut prims = Vec::new();
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (prim, [a, b, c]) in items {
            if !(a.is_finite() && b.is_finite() && c.is_finite())
                || (b - a).cross(c - a).length_squared() == 0.0
            {
                continue;
            }
            if *stored >= MAX_TRIANGLES {
                break;
            }
            *stored += 1;
            lo = lo.min(a).min(b).min(c);
            hi = hi.max(a).max(b).max(c);
            tris.push(Triangle {
                v0: a.as_vec3().into(),
                v1: b.as_vec3().into(),
                v2: c.as_vec3().into(),
            });
            prims.push(prim);
        }
        if tris.is_empty() {
            return None;
        }
        let params = if tris.len() <= SMALL_BVH {
            BvhBuildParams::very_slow_build()
        } else {
            BvhBuildParams::medium_build()
        };
        let mut bvh = build_cwbvh_from_tris(&tris, params, &mut Duration::default());
        // obvhs reserves one node per primitive; a CWBVH needs about one per 8–16.
        bvh.nodes.shrink_to_fit();
        // Lay the triangles out in BVH order so that leaves index them directly.
        let tris_ordered: Vec<RayTriangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| RayTriangle::new(tris[i as usize]))
            .collect();
        let prims_ordered: Vec<PrimRef> = bvh
            .primitive_indices
            .iter()
            .map(|&i| prims[i as usize])
            .collect();
        Some(Blas {
            bvh,
            tris: tris_ordered,
            prims: prims_ordered,
            bounds: (lo, hi),
            count: tris.len(),
        })
    }

    /// The BVH's nodes (tests of node-level queries).
    #[cfg(test)]
    pub(crate) fn nodes(&self) -> &[obvhs::cwbvh::node::CwBvhNode] {
        &self.bvh.nodes
    }

    /// The `f32` triangles in BVH order (tests).
    #[cfg(test)]
    pub(crate) fn triangles(&self) -> impl Iterator<Item = &Triangle> {
        self.tris.iter().map(|t| &t.tri)
    }

    /// The vertices of triangle `id` (BVH order) as its ray tests see them (`f32`, widened).
    #[inline]
    pub fn vertices(&self, id: u32) -> Option<[DVec3; 3]> {
        let t = &self.tris.get(id as usize)?.tri;
        Some([t.v0, t.v1, t.v2].map(|v| DVec3::new(v.x as f64, v.y as f64, v.z as f64)))
    }

    /// Number of distinct triangles stored.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Bytes held by the BVH, the triangles and their provenance (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.bvh.nodes.capacity() * size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.capacity() * size_of::<u32>()
            + self.tris.capacity() * size_of::<RayTriangle>()
            + self.prims.capacity() * size_of::<PrimRef>()
    }

    /// Closest triangle on `ray` within `[ray.tmin, ray.tmax]`, back faces of single-sided
    /// meshes skipped (the front is the side of `(v1 − v0) × (v2 − v0)`, tested in this BVH's
    /// space). On a hit, `hit` holds the primitive (index into `prims`) and the `f32` distance.
    #[inline]
    pub fn closest(&self, ray: Ray, hit: &mut RayHit) -> bool {
        self.bvh
            .ray_traverse(ray, hit, |r, id| self.cull_back(r, id))
    }

    /// [`Blas::closest`] among the triangles `ids` alone (BVH indices), tested in that order as
    /// the traversal tests its leaves: the closer hit wins, the earlier one on a tie.
    #[inline]
    pub fn closest_among(&self, ids: &[u32], ray: Ray, hit: &mut RayHit) -> bool {
        let mut r = ray;
        for &id in ids {
            let t = self.cull_back(&r, id as usize);
            if t < r.tmax {
                hit.primitive_id = id;
                hit.t = t;
                r.tmax = t;
            }
        }
        hit.t < ray.tmax
    }

    /// Triangle `id`'s distance on `r` (`f32::INFINITY` for a miss), a back face of a
    /// single-sided mesh a miss.
    #[inline(always)]
    fn cull_back(&self, r: &Ray, id: usize) -> f32 {
        let tri = &self.tris[id];
        if self.prims[id].double_sided {
            tri.intersect(r)
        } else {
            tri.intersect_front(r)
        }
    }

    /// Every triangle (BVH index) of a mesh that `casts` which `region` does not rule out, in
    /// traversal order, given to `take` until it returns true: the triangle it did.
    pub fn region_triangles(
        &self,
        region: &impl Region,
        casts: &impl Fn(usize) -> bool,
        mut take: impl FnMut(u32) -> bool,
    ) -> Option<u32> {
        super::region_search(&self.bvh, region, |id| {
            !region.culls_triangle(&self.tris[id].tri)
                && casts(self.prims[id].mesh as usize)
                && take(id as u32)
        })
    }

    /// Closest triangle on `ray`, either side.
    #[inline]
    pub fn nearest(&self, ray: Ray, hit: &mut RayHit) -> bool {
        self.bvh
            .ray_traverse(ray, hit, |r, id| self.tris[id].intersect(r))
    }

    /// True when no triangle of a mesh that `casts` (by `Scene::meshes` index) can stop a
    /// shadow ray inside `cone` (conservative: false when unsure); stops at the first
    /// triangle that might.
    pub fn cone_clear(&self, cone: &impl Region, casts: &impl Fn(usize) -> bool) -> bool {
        self.cone_blocker(cone, casts).is_none()
    }

    /// The first triangle (index into the BVH's triangles) of a mesh that `casts` which
    /// `cone` does not rule out; `None` when it rules out every one ([`Blas::cone_clear`]).
    pub fn cone_blocker(&self, cone: &impl Region, casts: &impl Fn(usize) -> bool) -> Option<u32> {
        self.region_triangles(cone, casts, |_| true)
    }

    /// Whether `cone` rules out triangle `id` (an index into the BVH's triangles).
    #[inline]
    pub fn culls(&self, cone: &impl Region, id: u32) -> bool {
        self.tris
            .get(id as usize)
            .is_none_or(|t| cone.culls_triangle(&t.tri))
    }

    /// [`Blas::any`] among the triangles `ids` alone (BVH indices).
    #[inline]
    pub fn any_among(&self, ids: &[u32], ray: Ray) -> bool {
        ids.iter()
            .any(|&id| self.tris[id as usize].intersect(&ray) < ray.tmax)
    }

    /// True when any triangle (either side) lies on `ray`; stops at the first one found.
    #[inline]
    pub fn any(&self, ray: Ray) -> bool {
        !self
            .bvh
            .ray_traverse_miss(ray, |r, id| self.tris[id].intersect(r))
    }
}

/// A triangle as ray queries test it: obvhs's [`Triangle`] with its unnormalised normal
/// `n = (v0 − v1) × (v2 − v0)` formed once, where `Triangle::intersect` forms it at every test.
/// The test is that one's Möller–Trumbore arithmetic, operation for operation, so distances
/// and misses are the same bits. One cache line.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct RayTriangle {
    /// The vertices.
    pub tri: Triangle,
    /// `(v0 − v1) × (v2 − v0)`: against the front, `-((v1 − v0) × (v2 − v0))`.
    n: Vec3A,
}

impl RayTriangle {
    fn new(tri: Triangle) -> RayTriangle {
        RayTriangle {
            tri,
            n: (tri.v0 - tri.v1).cross(tri.v2 - tri.v0),
        }
    }

    /// Distance to the triangle along `ray` within `[tmin, tmax]` (`f32::INFINITY` for a
    /// miss), from either side: `Triangle::intersect`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> f32 {
        self.test(ray, self.n.dot(ray.direction))
    }

    /// [`RayTriangle::intersect`] with the back a miss: the ray along the front normal
    /// `(v1 − v0) × (v2 − v0)` (`det = n·d < 0`), known before the rest of the test.
    #[inline(always)]
    pub fn intersect_front(&self, ray: &Ray) -> f32 {
        let det = self.n.dot(ray.direction);
        if det < 0.0 {
            return f32::INFINITY;
        }
        self.test(ray, det)
    }

    /// Möller–Trumbore given `det = n·d`: barycentrics `u`, `v`, `w = 1 − u − v` all of
    /// clear sign bit (so `−0` misses, as in obvhs) and `t = n·(v0 − o)/det` in range.
    #[inline(always)]
    fn test(&self, ray: &Ray, det: f32) -> f32 {
        let t = &self.tri;
        let e1 = t.v0 - t.v1;
        let e2 = t.v2 - t.v0;
        let c = t.v0 - ray.origin;
        let r = ray.direction.cross(c);
        let inv_det = 1.0 / det;
        let u = r.dot(e2) * inv_det;
        let v = r.dot(e1) * inv_det;
        let w = 1.0 - u - v;
        let signs = u.to_bits() | v.to_bits() | w.to_bits();
        if inv_det != 0.0 && signs & 0x8000_0000 == 0 {
            let t = self.n.dot(c) * inv_det;
            if t >= ray.tmin && t <= ray.tmax {
                return t;
            }
        }
        f32::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_sample::SplitMix64;

    /// obvhs's parallel build (PLOC from 500,000 triangles, reinsertion, leaf collapse, radix
    /// sorts) gives the same nodes, triangle order and provenance in pools of 1, 2 and 5
    /// threads, for a small (pre-split) and a large BVH: images do not depend on the machine.
    #[test]
    fn bvh_builds_are_the_same_for_any_thread_count() {
        let mut rng = SplitMix64::new(7);
        // Triangles on a bumpy sheet (many equal Morton codes and box areas: ties for the
        // sorts) with some random ones across it.
        let tris = |n: usize, rng: &mut SplitMix64| -> Vec<(PrimRef, [DVec3; 3])> {
            let side = (n as f64 / 2.0).sqrt().ceil() as usize;
            (0..n)
                .map(|i| {
                    let (x, y) = ((i / 2) % side, (i / 2) / side);
                    let z = |x: usize, y: usize| ((x * 7 + y * 3) % 5) as f64 * 0.25;
                    let p = |x: usize, y: usize| DVec3::new(x as f64, y as f64, z(x, y));
                    let t = if i % 97 == 0 {
                        [0, 1, 2].map(|_| {
                            DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * side as f64
                        })
                    } else if i % 2 == 0 {
                        [p(x, y), p(x + 1, y), p(x, y + 1)]
                    } else {
                        [p(x + 1, y), p(x + 1, y + 1), p(x, y + 1)]
                    };
                    let prim = PrimRef {
                        mesh: 0,
                        tri: i as u32,
                        double_sided: i % 3 == 0,
                    };
                    (prim, t)
                })
                .collect()
        };
        for n in [20_000, 600_000] {
            let items = tris(n, &mut rng);
            let build = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| Blas::from_triangles(items.iter().copied(), &mut 0).unwrap())
            };
            let one = build(1);
            for threads in [2, 5] {
                let b = build(threads);
                assert!(
                    b.bvh == one.bvh,
                    "{n} triangles, {threads} threads: other nodes"
                );
                assert!(b.prims == one.prims, "{n} triangles, {threads} threads");
                let corners = |b: &Blas| -> Vec<[f32; 9]> {
                    b.triangles()
                        .map(|t| {
                            let [a, b, c] = [t.v0, t.v1, t.v2];
                            [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z]
                        })
                        .collect()
                };
                assert!(
                    corners(&b) == corners(&one),
                    "{n} triangles, {threads} threads"
                );
            }
        }
    }

    /// A small BVH is pre-split ([`SMALL_BVH`]): a triangle far larger than the others is
    /// held more than once, yet counted once, and rays meet it (and only it) where it is.
    #[test]
    fn pre_split_triangles_count_once_and_are_hit() {
        let prim = |tri| PrimRef {
            mesh: 0,
            tri,
            double_sided: true,
        };
        // (a sliver along the diagonal: its box is far larger than it, so splitting pays)
        let big = [
            DVec3::new(-100.0, -100.0, 0.0),
            DVec3::new(100.0, 100.0, 0.0),
            DVec3::new(100.0, 98.0, 0.0),
        ];
        let mut items = vec![(prim(0), big)];
        for i in 1..=200u32 {
            let o = DVec3::new(
                (i % 20) as f64 * 3.0 - 30.0,
                (i / 20) as f64 * 3.0 - 15.0,
                5.0,
            );
            let small = [
                o,
                o + DVec3::new(0.1, 0.0, 0.0),
                o + DVec3::new(0.0, 0.1, 0.0),
            ];
            items.push((prim(i), small));
        }
        let mut stored = 0;
        let b = Blas::from_triangles(items.into_iter(), &mut stored).unwrap();
        assert_eq!((b.len(), stored), (201, 201));
        assert!(
            b.tris.len() > 201,
            "no pre-split: {} references",
            b.tris.len()
        );
        // (inside it: below the diagonal y = x, above y = 0.99·x − 1)
        for (x, y) in [
            (0.0, -0.5),
            (50.0, 49.3),
            (-50.0, -50.2),
            (95.0, 94.5),
            (-95.0, -95.02),
        ] {
            let ray = Ray::new(Vec3A::new(x, y, 1.0), Vec3A::NEG_Z, 0.0, f32::INFINITY);
            let mut hit = RayHit::none();
            assert!(b.closest(ray, &mut hit), "({x}, {y})");
            assert_eq!(b.prims[hit.primitive_id as usize].tri, 0, "({x}, {y})");
            assert_eq!(hit.t, 1.0);
        }
        let outside = Ray::new(Vec3A::new(0.0, 0.5, 1.0), Vec3A::NEG_Z, 0.0, f32::INFINITY);
        assert!(!b.closest(outside, &mut RayHit::none()));
    }

    /// `RayTriangle::intersect` is `Triangle::intersect` bit for bit, and `intersect_front`
    /// that with the back faces (`((v1 − v0) × (v2 − v0))·d > 0`) missing, as `Blas` culled
    /// them before: random triangles and rays, rays through vertices and along edges
    /// (`u`, `v` or `w` zero), in the plane (det 0), and `tmin`/`tmax` cutting the hit.
    #[test]
    fn ray_triangle_is_obvhs_triangle_bit_for_bit() {
        let mut rng = SplitMix64::new(7);
        let mut v = || {
            let mut c = || (rng.next_f64() * 4.0 - 2.0) as f32;
            Vec3A::new(c(), c(), c())
        };
        let (mut hits, mut culled) = (0, 0);
        for i in 0..200_000 {
            let tri = Triangle {
                v0: v(),
                v1: v(),
                v2: v(),
            };
            let o = v() * 2.0;
            let target = match i % 5 {
                0 => tri.v1,
                1 => (tri.v0 + tri.v2) * 0.5,
                2 => tri.v0 + (tri.v1 - tri.v0) * 0.25 + (tri.v2 - tri.v0) * 0.5,
                _ => v(),
            };
            let o = if i % 97 == 0 {
                tri.v0 + (tri.v1 - tri.v0) * 3.0
            } else {
                o
            };
            let d = (target - o).normalize_or_zero();
            let (tmin, tmax) = match i % 3 {
                0 => (0.0, f32::INFINITY),
                1 => (0.0, (target - o).length() * 0.999),
                _ => (0.5, 3.0),
            };
            let ray = Ray::new(o, d, tmin, tmax);
            let rt = RayTriangle::new(tri);
            let want = tri.intersect(&ray);
            assert_eq!(rt.intersect(&ray).to_bits(), want.to_bits(), "triangle {i}");
            let back = (tri.v1 - tri.v0).cross(tri.v2 - tri.v0).dot(ray.direction) > 0.0;
            let want_front = if want.is_finite() && back {
                f32::INFINITY
            } else {
                want
            };
            assert_eq!(
                rt.intersect_front(&ray).to_bits(),
                want_front.to_bits(),
                "front {i}"
            );
            hits += want.is_finite() as u32;
            culled += (want.is_finite() && back) as u32;
        }
        // (the cases above do reach both outcomes often)
        assert!(
            hits > 25_000 && culled > 10_000,
            "{hits} hits, {culled} culled"
        );
    }
}
