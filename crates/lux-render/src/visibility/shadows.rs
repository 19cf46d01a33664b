//! Shadow rays and the regions they fill, for the exact visibility: a second BVH of the world
//! meshes in which a flat card tiling a convex polygon (`visibility/planar.rs`) stands as its
//! outline's fan (fewer, larger triangles that block exactly what the card's block), each
//! card's outline for the closed-form penumbrae, and the searches of a region of shadow rays
//! ([`Region`]: a cone, a pyramid) for what can block it.
//!
//! Shadow rays of the exact visibility test this BVH ([`Shadows::occluded`]); `rays` visibility
//! tests the world BVH. Both hold the same surfaces.

use super::RayFrustum;
use super::cone::{ConeSearch, INSTANCED};
use super::planar;
use super::solid::Solid;
use crate::geometry::{
    Blas, Geometry, Hit, MAX_TRIANGLES, Occluder, PrimRef, Region, mesh_triangles,
};
use glam::DVec3;
use lux_usd::Scene;
use obvhs::ray::RayHit;
use rayon::prelude::*;

/// A few triangles of the BVH shadow rays query ([`Shadows::blockers_in`]): all that can stop
/// a shadow ray inside some region, those of closed convex meshes (`solid.rs`) as their
/// meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FewTriangles {
    len: u8,
    ids: [u32; FewTriangles::CAP],
    solids: u8,
    solid_ids: [u32; FewTriangles::SOLIDS],
}

impl FewTriangles {
    /// Most triangles held (of meshes not solids): a shadow ray testing more costs about what
    /// the BVH's traversal does.
    pub const CAP: usize = 6;

    /// Most closed convex meshes held.
    pub const SOLIDS: usize = 8;

    /// The triangles of meshes not solids (indices into the shadow rays' BVH).
    pub fn ids(&self) -> &[u32] {
        &self.ids[..self.len as usize]
    }

    /// The closed convex meshes (`Scene::meshes` indices, [`Shadows::solid`]).
    pub fn solids(&self) -> &[u32] {
        &self.solid_ids[..self.solids as usize]
    }
}

/// A planar mesh's convex outline in the shadow BVH (`visibility/planar.rs`): its corners in
/// order, as its fan triangles hold them.
#[derive(Clone, Copy, Debug)]
struct Card {
    len: u8,
    corners: [DVec3; lux_irradiance::hidden::MAX_CORNERS],
}

/// The shadow rays' BVH of flat cards' outlines and the cards.
pub struct ShadowBvh {
    /// What shadow rays test instead of the world BVH when planar tilings of a convex polygon
    /// (`visibility/planar.rs`) make most of it: those meshes as their outlines' fan
    /// triangles, the others as in the world BVH ([`Shadows::shadow_blas`]). `None` otherwise.
    shadow: Option<Blas>,
    /// Per mesh, with `shadow`: the convex outline whose fan stands for it there (corners
    /// rounded as the BVH's triangles are), when it has at most
    /// [`lux_irradiance::hidden::MAX_CORNERS`] corners ([`Shadows::blocker_card`]).
    cards: Vec<Option<Card>>,
    /// Per mesh: the mesh as a closed convex solid, when it is one (`solid.rs`; its vertices
    /// rounded as the BVHs store them), for [`Shadows::solid`].
    solids: Vec<Option<Solid>>,
}

impl ShadowBvh {
    /// No shadow BVH: shadow rays through the world BVH.
    pub const NONE: ShadowBvh = ShadowBvh {
        shadow: None,
        cards: Vec::new(),
        solids: Vec::new(),
    };

    /// The shadow BVH of `scene`'s world meshes as `g` holds them (not when the world BVH
    /// stopped at [`MAX_TRIANGLES`]: shadow rays would see what it left out).
    pub fn new(scene: &Scene, g: &Geometry) -> ShadowBvh {
        let world_meshes = || crate::geometry::world_meshes(scene);
        let mut cards = vec![None; scene.meshes.len()];
        let shadow = g
            .world()
            .filter(|w| w.len() < MAX_TRIANGLES)
            .and_then(|w| Self::shadow_blas(scene, world_meshes(), w.len(), &mut cards));
        if shadow.is_none() {
            cards.clear();
        }
        // (each mesh on its own: in parallel, the same answers in order)
        let small: Vec<usize> = world_meshes()
            .filter(|&mi| scene.meshes[mi].triangles.len() <= super::solid::MAX_SOLID_TRIANGLES)
            .collect();
        let found: Vec<Option<Solid>> = small
            .par_iter()
            .map(|&mi| {
                let tris: Vec<(u32, [DVec3; 3])> = mesh_triangles(scene, mi)
                    .map(|(prim, t)| (prim.tri, t.map(|v| v.as_vec3().as_dvec3())))
                    .collect();
                Solid::new(&tris)
            })
            .collect();
        let mut solids = vec![None; scene.meshes.len()];
        for (mi, solid) in small.into_iter().zip(found) {
            solids[mi] = solid;
        }
        ShadowBvh {
            shadow,
            cards,
            solids,
        }
    }

    /// The shadow BVH of [`Shadows::shadow`]: the meshes `meshes` (the world BVH's, of
    /// `world_len` triangles), each planar tiling of a convex polygon as its outline's fan
    /// (`planar::tiled_hull`). Only when it holds at most a quarter of the world's triangles:
    /// it repeats the other meshes' triangles, so its memory stays under a quarter of the
    /// world BVH's, and it is built only where it saves most of the shadow rays' work.
    fn shadow_blas(
        scene: &Scene,
        meshes: impl Iterator<Item = usize>,
        world_len: usize,
        cards: &mut [Option<Card>],
    ) -> Option<Blas> {
        let mut replaced = false;
        let mut items = Vec::new();
        for mi in meshes {
            let m = &scene.meshes[mi];
            match planar::tiled_hull(&m.positions, &m.triangles) {
                Some(fan) => {
                    replaced = true;
                    // (the fan's corners c₀, c₁ … c_k: each triangle's second corner, then the
                    // last one's third, rounded to f32 as the BVH stores them)
                    let k = fan.len() + 2;
                    if k <= lux_irradiance::hidden::MAX_CORNERS {
                        let mut corners = [DVec3::ZERO; lux_irradiance::hidden::MAX_CORNERS];
                        corners[0] = fan[0][0];
                        for (i, t) in fan.iter().enumerate() {
                            corners[i + 1] = t[1];
                        }
                        corners[k - 1] = fan[fan.len() - 1][2];
                        for c in &mut corners[..k] {
                            *c = c.as_vec3().as_dvec3();
                        }
                        cards[mi] = Some(Card {
                            len: k as u8,
                            corners,
                        });
                    }
                    items.extend(fan.into_iter().enumerate().map(|(k, t)| {
                        let prim = PrimRef {
                            mesh: mi as u32,
                            tri: k as u32,
                            double_sided: m.double_sided,
                        };
                        (prim, t)
                    }));
                }
                None => items.extend(mesh_triangles(scene, mi)),
            }
        }
        // (its own count: these triangles stand for the world's, already counted)
        (replaced && 4 * items.len() <= world_len)
            .then(|| Blas::from_triangles(items.into_iter(), &mut 0))
            .flatten()
    }

    /// The shadow rays of the scene `g` holds, through this BVH.
    pub fn view<'a>(&'a self, g: &'a Geometry) -> Shadows<'a> {
        Shadows { g, bvh: self }
    }
}

/// Shadow rays and shadow-region searches over a scene's geometry, through its [`ShadowBvh`].
#[derive(Clone, Copy)]
pub struct Shadows<'a> {
    g: &'a Geometry,
    bvh: &'a ShadowBvh,
}

impl<'a> Shadows<'a> {
    /// What shadow rays test: the shadow BVH, else the world's.
    #[inline]
    fn blockers(&self) -> Option<&'a Blas> {
        self.bvh.shadow.as_ref().or(self.g.world())
    }

    /// `Geometry::occluded` through the shadow BVH.
    #[inline]
    pub fn occluded(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> bool {
        self.g
            .occluded_through(self.blockers(), origin, dir, tmin, tmax)
    }

    /// `Geometry::first_occluder` through the shadow BVH.
    #[inline]
    pub fn first_occluder(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> Option<f64> {
        self.g
            .first_occluder_through(self.blockers(), origin, dir, tmin, tmax)
    }

    /// `Geometry::first_occluder_at` through the shadow BVH.
    #[inline]
    pub fn first_occluder_at(
        &self,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Occluder> {
        self.g
            .first_occluder_at_through(self.blockers(), origin, dir, tmin, tmax)
    }

    /// The convex outline (its mesh, its corners in order) whose fan holds the triangle `id` of
    /// the BVH shadow rays test ([`Shadows::blocker_vertices`]), when that triangle stands
    /// for a planar mesh there (`visibility/planar.rs`).
    pub fn blocker_card(&self, id: u32) -> Option<(u32, &'a [DVec3])> {
        let mesh = self.bvh.shadow.as_ref()?.prims.get(id as usize)?.mesh;
        let card = self.bvh.cards.get(mesh as usize)?.as_ref()?;
        Some((mesh, &card.corners[..card.len as usize]))
    }

    /// The world mesh `mesh` as a closed convex solid, when it is one (`visibility/solid.rs`).
    #[inline]
    pub fn solid(&self, mesh: u32) -> Option<&'a Solid> {
        self.bvh.solids.get(mesh as usize)?.as_ref()
    }

    /// True when no triangle of a mesh that `casts` (a `Scene::meshes` index: what a light's
    /// shadow linking keeps) can stop a shadow ray inside `cone` ([`ShadowCone`]) — searched in
    /// the BVH shadow rays test (a planar tiling as its outline: fewer, larger triangles, which
    /// a cone drops by its exact triangle test where their bounding spheres reach it) — and no
    /// instance's world box meets it (instances are not searched inside, and are taken to cast
    /// every light's shadow); false when unsure.
    pub fn cone_clear(&self, cone: &impl Region, casts: &impl Fn(usize) -> bool) -> bool {
        self.blockers().is_none_or(|w| w.cone_clear(cone, casts))
            && self.g.instances().is_none_or(|i| !i.may_block(cone))
    }

    /// What can stop the shadow rays inside `cone` ([`ShadowCone`]) among the triangles of
    /// meshes that `casts`: nothing, or the first triangle of the shadow rays' BVH found that
    /// `cone` does not rule out, else [`INSTANCED`] when an instance's world box meets it
    /// ([`ConeSearch`]).
    pub fn cone_search(&self, cone: &impl Region, casts: &impl Fn(usize) -> bool) -> ConeSearch {
        match self.blockers().and_then(|w| w.cone_blocker(cone, casts)) {
            Some(id) => ConeSearch::Blocked(id),
            None if self.g.instances().is_some_and(|i| i.may_block(cone)) => {
                ConeSearch::Blocked(INSTANCED)
            }
            None => ConeSearch::Clear,
        }
    }

    /// Whether `cone` rules out the blocker `id` of a [`ConeSearch::Blocked`]: a triangle of
    /// the shadow rays' BVH, or for [`INSTANCED`] every instance's box.
    #[inline]
    pub fn culls(&self, cone: &impl Region, id: u32) -> bool {
        if id == INSTANCED {
            return self.g.instances().is_none_or(|i| !i.may_block(cone));
        }
        self.blockers().is_none_or(|w| w.culls(cone, id))
    }

    /// The vertices of the triangle `id` of a [`FewTriangles`] ([`Shadows::blockers_in`]), as
    /// shadow rays meet it.
    #[inline]
    pub fn blocker_vertices(&self, id: u32) -> Option<[DVec3; 3]> {
        self.blockers()?.vertices(id)
    }

    /// Every triangle of a mesh that `casts` which can stop a shadow ray inside `region`, among
    /// those shadow rays query (the outlines of flat cards where built: `visibility/planar.rs`), for
    /// [`Shadows::occluded_among`], those of closed convex meshes as their meshes; `None` when
    /// more than [`FewTriangles::CAP`] triangles or [`FewTriangles::SOLIDS`] solids, or with
    /// instances.
    pub fn blockers_in(
        &self,
        region: &impl Region,
        casts: &impl Fn(usize) -> bool,
    ) -> Option<FewTriangles> {
        if self.g.instances().is_some() {
            return None;
        }
        let b = self.blockers()?;
        let mut few = FewTriangles {
            len: 0,
            ids: [0; FewTriangles::CAP],
            solids: 0,
            solid_ids: [0; FewTriangles::SOLIDS],
        };
        let over = b.region_triangles(region, casts, |id| {
            let mesh = b.prims[id as usize].mesh;
            if self.solid(mesh).is_some() {
                if few.solids().contains(&mesh) {
                    return false;
                }
                if few.solids as usize == FewTriangles::SOLIDS {
                    return true;
                }
                few.solid_ids[few.solids as usize] = mesh;
                few.solids += 1;
                return false;
            }
            if few.len as usize == FewTriangles::CAP {
                return true;
            }
            few.ids[few.len as usize] = id;
            few.len += 1;
            false
        });
        over.is_none().then_some(few)
    }

    /// `Geometry::occluded` among the triangles `few` alone: the same answer for a ray inside
    /// the region they were found for ([`Shadows::blockers_in`]), when it was searched for
    /// every mesh that can block it. Through the BVH when they hold solids.
    #[inline]
    pub fn occluded_among(
        &self,
        few: &FewTriangles,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> bool {
        if !few.solids().is_empty() {
            return self.occluded(origin, dir, tmin, tmax);
        }
        let Some(ray) = Geometry::ray(origin, dir, tmin, tmax) else {
            return false;
        };
        self.blockers().is_some_and(|b| b.any_among(few.ids(), ray))
    }

    /// The world triangles a ray inside `frustum` may hit (their BVH indices, in the order
    /// the BVH's traversal along its axis meets them), for [`Shadows::intersect_among`]; `None`
    /// when there are more than `cap`, or the scene has instances (their rays take the BVH).
    pub fn triangles_in(&self, frustum: &RayFrustum, cap: usize) -> Option<Box<[u32]>> {
        if self.g.instances().is_some() {
            return None;
        }
        let world = self.g.world()?;
        let mut ids = Vec::new();
        let over = world.region_triangles(frustum, &|_| true, |id| {
            ids.push(id);
            ids.len() > cap
        });
        over.is_none().then(|| ids.into_boxed_slice())
    }

    /// `Geometry::intersect` of a ray among the world triangles `ids` alone: the same hit
    /// when they hold every triangle the ray can reach ([`Shadows::triangles_in`] of a frustum
    /// holding the ray), back faces of single-sided meshes skipped.
    #[inline]
    pub fn intersect_among(
        &self,
        scene: &Scene,
        ids: &[u32],
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Hit> {
        let ray = Geometry::ray(origin, dir, tmin, tmax)?;
        let world = self.g.world()?;
        let mut hit = RayHit::none();
        world
            .closest_among(ids, ray, &mut hit)
            .then(|| Geometry::world_hit(world, scene, hit, origin, dir))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tests::scene_with;
    use crate::geometry::{offset_scale, region_search};
    use crate::visibility::{ConeSearch, RayEnds, ShadowCone, ShadowPyramid};
    use lux_usd::Mesh;

    #[test]
    fn shadow_bvh_of_planar_tilings_answers_as_the_meshes() {
        let grid = |path: &str, n: u32, map: &dyn Fn(f64, f64) -> DVec3| {
            let mut p = Vec::new();
            for j in 0..=n {
                for i in 0..=n {
                    p.push(map(i as f64 / n as f64, j as f64 / n as f64));
                }
            }
            let at = |i: u32, j: u32| j * (n + 1) + i;
            let mut t = Vec::new();
            for j in 0..n {
                for i in 0..n {
                    t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                    t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
            Mesh::new(path, p, t)
        };
        let floor = grid("/floor", 9, &|u, v| {
            DVec3::new(10.0 * u - 5.0, 0.0, 10.0 * v - 5.0)
        });
        let card = grid("/card", 9, &|u, v| {
            DVec3::new(u - 0.5, 1.0 + 0.3 * v, 0.8 * v - 0.4)
        });
        let strip = grid("/strip", 6, &|u, v| {
            DVec3::new(2.0 + u, 0.5 + 0.4 * (3.0 * u).sin(), v - 0.5)
        });
        let scene = scene_with(vec![floor, card, strip]);
        let g = Geometry::new(&scene);
        let bvh = ShadowBvh::new(&scene, &g);
        let sh = bvh.view(&g);
        let (world, shadow) = (g.world().unwrap(), bvh.shadow.as_ref().unwrap());
        assert_eq!(world.len(), 162 + 162 + 72);
        assert_eq!(shadow.len(), 2 + 2 + 72);
        // Each outline triangle names its card: the rectangle's four corners in order (as the
        // BVH rounds them); the strip's own triangles name none.
        let mut cards = [0usize; 3];
        for id in 0..shadow.len() as u32 {
            let tri = sh.blocker_vertices(id).unwrap();
            match sh.blocker_card(id) {
                Some((mesh, corners)) => {
                    cards[mesh as usize] += 1;
                    assert_eq!(corners.len(), 4);
                    assert!(
                        tri.iter().all(|v| corners.contains(v)),
                        "{tri:?} {corners:?}"
                    );
                    let at = |u: f64, v: f64| {
                        let p = if mesh == 0 {
                            DVec3::new(10.0 * u - 5.0, 0.0, 10.0 * v - 5.0)
                        } else {
                            DVec3::new(u - 0.5, 1.0 + 0.3 * v, 0.8 * v - 0.4)
                        };
                        p.as_vec3().as_dvec3()
                    };
                    let square = [at(0.0, 0.0), at(1.0, 0.0), at(1.0, 1.0), at(0.0, 1.0)];
                    let k = corners.iter().position(|c| *c == square[0]).unwrap();
                    let turn: Vec<DVec3> = (0..4).map(|i| corners[(k + i) % 4]).collect();
                    let back: Vec<DVec3> = (0..4).map(|i| corners[(k + 4 - i) % 4]).collect();
                    assert!(turn == square || back == square, "{corners:?}");
                }
                None => cards[2] += 1,
            }
        }
        assert_eq!(cards, [2, 2, 72]);
        let mut rng = lux_sample::SplitMix64::new(5);
        let mut u = || rng.next_f64();
        let (mut hits, mut misses) = (0, 0);
        for i in 0..20_000 {
            let (o, d) = match i % 4 {
                // From the floor towards the card's region.
                0 => {
                    let o = DVec3::new(6.0 * u() - 3.0, 0.0, 6.0 * u() - 3.0);
                    let o = o + DVec3::Y * offset_scale(o);
                    (
                        o,
                        (DVec3::new(u() - 0.5, 1.2, 0.8 * u() - 0.4) - o).normalize(),
                    )
                }
                // From above, down through everything.
                1 => (
                    DVec3::new(8.0 * u() - 4.0, 4.0, 8.0 * u() - 4.0),
                    DVec3::new(u() - 0.5, -1.0, u() - 0.5).normalize(),
                ),
                // Grazing over the floor.
                2 => (
                    DVec3::new(-6.0, 1e-3 + 0.01 * u(), 6.0 * u() - 3.0),
                    DVec3::new(1.0, 0.02 * (u() - 0.5), 0.3 * (u() - 0.5)).normalize(),
                ),
                // Aimed at the card's edges and grid lines.
                _ => {
                    let k = (9.0 * u()).round() / 9.0;
                    let target = DVec3::new(k - 0.5, 1.0 + 0.3 * u(), 0.8 * u() - 0.4);
                    let o = DVec3::new(2.0 * u() - 1.0, 3.0, 2.0 * u() - 1.0);
                    (o, (target - o).normalize())
                }
            };
            let ray = Geometry::ray(o, d, 0.0, 50.0).unwrap();
            let (mut a, mut b) = (RayHit::none(), RayHit::none());
            let (wa, wb) = (world.nearest(ray, &mut a), shadow.nearest(ray, &mut b));
            assert_eq!(
                world.any(ray),
                shadow.any(ray),
                "ray {i} from {o} along {d}"
            );
            assert_eq!(wa, wb, "ray {i}");
            if wa {
                hits += 1;
                let (ma, mb) = (
                    world.prims[a.primitive_id as usize],
                    shadow.prims[b.primitive_id as usize],
                );
                assert_eq!(ma.mesh, mb.mesh, "ray {i}");
                assert!(
                    (a.t - b.t).abs() <= 1e-5 * a.t.max(1.0),
                    "ray {i}: {} vs {}",
                    a.t,
                    b.t
                );
            } else {
                misses += 1;
            }
        }
        assert!(
            hits > 5_000 && misses > 2_000,
            "{hits} hits, {misses} misses"
        );
        // The queries go to the shadow BVH (off the fans' diagonals, which `f32` ray-triangle
        // tests, like any shared edge, may let an exactly aimed ray through).
        assert!(std::ptr::eq(sh.blockers().unwrap(), shadow));
        let o = DVec3::new(0.1, 3.0, 0.07);
        assert_eq!(
            sh.first_occluder_at(o, DVec3::NEG_Y, 0.0, 10.0)
                .map(|h| h.mesh),
            Some(1)
        );
        assert!(sh.occluded(o, DVec3::NEG_Y, 0.0, 10.0));
        // No shadow BVH without planar tilings, nor where they are a small part (the card and
        // three strips: 2 + 216 of 378 triangles, more than a quarter).
        let one = scene_with(vec![scene.meshes[2].clone()]);
        let g = Geometry::new(&one);
        let bvh = ShadowBvh::new(&one, &g);
        assert!(
            bvh.shadow.is_none()
                && std::ptr::eq(bvh.view(&g).blockers().unwrap(), g.world().unwrap())
        );
        let mostly_strips = scene_with([1, 2, 2, 2].map(|i| scene.meshes[i].clone()).to_vec());
        let g = Geometry::new(&mostly_strips);
        assert!(ShadowBvh::new(&mostly_strips, &g).shadow.is_none());
    }

    /// A subdivided horizontal card (162 triangles at y = 0.5: the BVH nodes holding only its
    /// triangles are flat, their quantization step along y as small as 2⁻⁷⁴) blocks the cone
    /// and the pyramid from the floor under it to a light above, alone in a BVH or over the
    /// floor; beside it, the regions are clear. (The cone's node test once squared the
    /// quantized distance before scaling it back, which overflowed `f32` in such nodes: the
    /// card was culled, and light went through it.)
    #[test]
    fn flat_nodes_of_a_horizontal_card_block_the_regions_they_meet() {
        let mut pos = Vec::new();
        let mut tri = Vec::new();
        for j in 0..=9u32 {
            for i in 0..=9u32 {
                pos.push(DVec3::new(
                    -0.5 + i as f64 / 9.0,
                    0.5,
                    -0.5 + j as f64 / 9.0,
                ));
            }
        }
        for j in 0..9u32 {
            for i in 0..9u32 {
                let a = j * 10 + i;
                tri.push([a, a + 1, a + 11]);
                tri.push([a, a + 11, a + 10]);
            }
        }
        let card = Mesh::new("/card", pos, tri);
        for scene in [
            scene_with(vec![card.clone()]),
            scene_with(vec![crate::visibility::cone::tests::floor(), card]),
        ] {
            let g = Geometry::new(&scene);
            let bvh = ShadowBvh::new(&scene, &g);
            let sh = bvh.view(&g);
            let region = |x: f64| {
                let p = DVec3::new(x, 0.0, 0.1);
                let offset = offset_scale(p);
                let light = DVec3::new(x, 1.5, 0.1);
                let corners =
                    crate::visibility::pyramid::tests::rect(light, -DVec3::Y, DVec3::X, (0.2, 0.2));
                (
                    ShadowCone::new(p, DVec3::Y, offset, light, 0.2, RayEnds::NearSide).unwrap(),
                    ShadowPyramid::new(p, DVec3::Y, offset, &corners).unwrap(),
                )
            };
            let (cone, pyramid) = region(0.0);
            assert!(matches!(
                sh.cone_search(&cone, &|_| true),
                ConeSearch::Blocked(_)
            ));
            assert!(matches!(
                sh.cone_search(&pyramid, &|_| true),
                ConeSearch::Blocked(_)
            ));
            let (cone, pyramid) = region(3.0);
            assert_eq!(sh.cone_search(&cone, &|_| true), ConeSearch::Clear);
            assert_eq!(sh.cone_search(&pyramid, &|_| true), ConeSearch::Clear);
        }
    }

    /// Instanced blockers under similarities (rotated, mirrored, scaled 0.3–3, moved) and under
    /// a stretch: wherever the search of the instances says nothing can block a light (a cone
    /// of a point and of a patch, a rect's pyramid), no shadow ray from the point (traced in
    /// `f64` against the instance's world triangles) is blocked; and searching inside the
    /// similar instances finds clear regions the instances' boxes alone would not.
    #[test]
    fn instance_searches_inside_similar_prototypes_are_sound() {
        use glam::{DMat4, DQuat};
        use lux_usd::{Instance, Prototype};
        let mut rng = lux_sample::SplitMix64::new(17);
        let mut u = move || rng.next_f64();
        let (mut clear, mut inside_only, mut blocked) = (0, 0, 0);
        for case in 0..60 {
            // A thin tilted card as the prototype (its box is much larger than it).
            let proto = Mesh {
                prototype: Some(0),
                ..Mesh::new(
                    "/card",
                    vec![
                        DVec3::new(-0.3, -0.2, -0.2),
                        DVec3::new(0.3, -0.2, -0.2),
                        DVec3::new(0.3, 0.2, 0.2),
                        DVec3::new(-0.3, 0.2, 0.2),
                    ],
                    vec![[0, 1, 2], [0, 2, 3]],
                )
            };
            let q = DQuat::from_axis_angle(
                DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize(),
                6.3 * u(),
            );
            let s = 0.3 + 2.7 * u();
            let mirror = if case % 3 == 0 { -1.0 } else { 1.0 };
            let stretch = if case % 10 == 9 {
                DVec3::new(1.0, 0.4, 1.0)
            } else {
                DVec3::ONE
            };
            let at = DVec3::new(1.2 * (u() - 0.5), 0.6 + 0.8 * u(), 1.2 * (u() - 0.5));
            let m = DMat4::from_scale_rotation_translation(
                DVec3::new(mirror * s, s, s) * stretch / s.max(1.0),
                q,
                at,
            );
            let mut scene =
                scene_with(vec![crate::visibility::cone::tests::floor(), proto.clone()]);
            scene.prototypes.push(Prototype {
                path: "/P".into(),
                meshes: vec![1],
            });
            scene.instances.push(Instance {
                path: "/I".into(),
                prototype: 0,
                to_world: m,
                material: None,
            });
            let g = Geometry::new(&scene);
            let inst = g.instances().unwrap();
            let world_tris: Vec<[DVec3; 3]> = proto
                .triangles
                .iter()
                .map(|t| t.map(|i| m.transform_point3(proto.positions[i as usize])))
                .collect();
            let hits = |o: DVec3, w: DVec3, tmax: f64| {
                world_tris.iter().any(|&[a, b, c]| {
                    let (e1, e2) = (b - a, c - a);
                    let p = w.cross(e2);
                    let det = e1.dot(p);
                    let tv = o - a;
                    let (b1, qv) = (tv.dot(p) / det, tv.cross(e1));
                    let (b2, t) = (w.dot(qv) / det, e2.dot(qv) / det);
                    b1 >= -1e-9 && b2 >= -1e-9 && b1 + b2 <= 1.0 + 1e-9 && t > 0.0 && t < tmax
                })
            };
            for k in 0..12 {
                let p = DVec3::new(2.4 * (u() - 0.5), 0.0, 2.4 * (u() - 0.5));
                let light = DVec3::new(2.0 * (u() - 0.5), 2.2 + u(), 2.0 * (u() - 0.5));
                let radius = 0.1 + 0.3 * u();
                let offset = offset_scale(p);
                let spread = if k % 2 == 0 { 0.0 } else { 0.1 };
                let Some(cone) = (if spread == 0.0 {
                    ShadowCone::new(p, DVec3::Y, offset, light, radius, RayEnds::NearSide)
                } else {
                    ShadowCone::patch(p, DVec3::Y, spread, light, radius, RayEnds::NearSide)
                }) else {
                    continue;
                };
                let corners = crate::visibility::pyramid::tests::rect(
                    light,
                    -DVec3::Y,
                    DVec3::X,
                    (radius, radius),
                );
                let pyramid = ShadowPyramid::new(p, DVec3::Y, offset, &corners).unwrap();
                let boxed = region_search(&inst.tlas, &cone, |_| true).is_some();
                for (free, rays) in [
                    (
                        !inst.may_block(&cone),
                        crate::visibility::cone::tests::segments(p, light, radius, 400, false),
                    ),
                    (
                        !inst.may_block(&pyramid),
                        crate::visibility::pyramid::tests::segments(p, &corners, 400),
                    ),
                ] {
                    if free {
                        clear += 1;
                        for (o, w, t) in rays {
                            assert!(
                                !hits(o, w, t),
                                "case {case}: clear region, blocked ray from {o}"
                            );
                        }
                    } else {
                        blocked += 1;
                    }
                }
                inside_only += (boxed && !inst.may_block(&cone)) as u32;
            }
        }
        assert!(
            clear > 200 && blocked > 50 && inside_only > 20,
            "{clear} clear, {blocked} blocked, {inside_only} clear only inside"
        );
    }
}
