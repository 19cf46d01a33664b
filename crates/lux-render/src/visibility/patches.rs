//! Patches of surface that see a light unblocked, searched once per patch and worker (while
//! remembered).
//!
//! The closed form of a light's unshadowed integral stands in for its samples where no
//! triangle can block any shadow ray ([`ShadowCone`], `visibility/cone.rs`). Neighbouring shading
//! points of one triangle share almost all of that search: the cone of a whole patch — the
//! points of the triangle's plane within ρ of a point `q` ([`ShadowCone::patch`]) — answers
//! it for all of them at once. The patches are the cells of a grid of side `s` in world space
//! (ρ = s·√3/2, `q` the cell centre projected onto the plane: every point of the plane in the
//! cell is within ρ of it), `s` a fixed fraction of the light's ball ([`CELL_PER_RADIUS`]).
//! A patch that is not clear names the first triangle found that might block one of its
//! rays: a point whose own cone does not rule that triangle out is sampled at once (what its
//! own search would find first, most often, in a penumbra), any other is searched alone.
//!
//! Each answer is a function of its key alone — light, mesh, triangle, side, cell — so the
//! image does not depend on which tile or thread asks first, or whether the answer was
//! remembered.

use super::{ConeSearch, FewTriangles, RayEnds, ShadowCone, ShadowPyramid, Shadows};
use crate::material::SurfacePoint;
use glam::DVec3;
use lux_usd::Scene;

/// A cell's side over the radius of the light's ball: patches of radius ρ ≈ 0.22 of it.
pub const CELL_PER_RADIUS: f64 = 0.25;

/// Remembered answers: direct-mapped by key hash (a worker's, kept from tile to tile and pass to
/// pass: adaptive.rs).
const SLOTS: usize = 1024;

/// One patch: whose light, which triangle and side, which cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Key {
    light: u32,
    mesh: u32,
    tri: u32,
    /// The sign bits of the normal the light is seen along (a triangle's two sides differ).
    side: u8,
    cell: [i32; 3],
}

impl Key {
    fn slot(&self) -> usize {
        let mut h = (self.light as u64) << 32 | self.mesh as u64;
        for x in [
            self.tri as u64,
            self.side as u64,
            self.cell[0] as u32 as u64,
            self.cell[1] as u32 as u64,
            self.cell[2] as u32 as u64,
        ] {
            h = (h.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
        }
        // (bits 40–63 of the product, the best mixed: more than 256 slots are used)
        (h >> 40) as usize % SLOTS
    }
}

/// A patch's answer: whether something may block it and, when so, every triangle that might
/// when there are few ([`Shadows::blockers_in`]).
type Answer = (ConeSearch, Option<FewTriangles>);

/// A worker's remembered patch answers.
#[derive(Clone, Debug, Default)]
pub struct ClearPatches {
    slots: Vec<Option<(Key, Answer)>>,
}

impl ClearPatches {
    /// Whether a triangle of a mesh that `casts` might block a shadow ray of light `light`
    /// from some point of the patch around the shading point `sp` ([`ConeSearch`]): rays
    /// towards the ball (`centre`, `radius`, `ends`), or with `corners` (a rect's, a disk's
    /// square: `regions::shadow_corners`) into their pyramid ([`ShadowPyramid::patch`]; the
    /// ball then holds the light and sizes the cells).
    /// [`ConeSearch::Unsearched`] for points on instances and out-of-range coordinates, which
    /// are not searched here.
    /// With it, for a patch that may be blocked, the few triangles of the shadow rays' BVH
    /// that can block any of its rays ([`Shadows::blockers_in`]; `None` when more): a shadow
    /// ray from the point tests those alone ([`Shadows::occluded_among`]).
    #[allow(clippy::too_many_arguments)]
    pub fn search(
        &mut self,
        scene: &Scene,
        shadows: &Shadows,
        sp: &SurfacePoint,
        light: usize,
        (centre, radius, ends): (DVec3, f64, RayEnds),
        corners: Option<&[DVec3; 4]>,
        casts: &impl Fn(usize) -> bool,
    ) -> Answer {
        // (No patch region where the point's own is missing: the ball, or the rect's or disk's
        // corners, reach its horizon. The region's kind is the light's, never the point's: the
        // remembered answer must be a function of the key.)
        let above = match corners {
            Some(c) => c.iter().all(|&x| sp.ng.dot(x - sp.p) > 0.0),
            None => sp.ng.dot(centre - sp.p) > radius,
        };
        if sp.instance.is_some() || !above {
            return (ConeSearch::Unsearched, None);
        }
        let s = radius * CELL_PER_RADIUS;
        let g = sp.p * (1.0 / s);
        // (NaN fails too)
        if !(s > 0.0 && g.abs().max_element() < (1 << 30) as f64) {
            return (ConeSearch::Unsearched, None);
        }
        // ⌊g⌋ by truncation (`f64::floor` is a libm call on the baseline x86-64 target).
        let cell = g.to_array().map(|x| {
            let i = x as i32;
            i - (x < i as f64) as i32
        });
        let sign = |x: f64| (x.to_bits() >> 63) as u8;
        let key = Key {
            light: light as u32,
            mesh: sp.mesh as u32,
            tri: sp.tri as u32,
            side: sign(sp.ng.x) | sign(sp.ng.y) << 1 | sign(sp.ng.z) << 2,
            cell,
        };
        if self.slots.is_empty() {
            self.slots = vec![None; SLOTS];
        }
        let slot = key.slot();
        if let Some((k, b)) = self.slots[slot]
            && k == key
        {
            return b;
        }
        // The plane through the triangle's first corner (not the hit point, whose rounding
        // differs from hit to hit), with the hit's normal (the same for every hit on this
        // side of the triangle).
        let mesh = &scene.meshes[sp.mesh];
        let a = mesh.positions[mesh.triangles[sp.tri][0] as usize];
        let c = (glam::IVec3::from_array(cell).as_dvec3() + 0.5) * s;
        let q = c - sp.ng * sp.ng.dot(c - a);
        let spread = s * 0.5 * 3f64.sqrt();
        let search = |b: ConeSearch, few: &dyn Fn() -> Option<FewTriangles>| match b {
            ConeSearch::Blocked(_) => (b, few()),
            _ => (b, None),
        };
        let b = match corners {
            Some(c) => ShadowPyramid::patch(q, sp.ng, spread, c).map(|pyramid| {
                search(shadows.cone_search(&pyramid, casts), &|| {
                    shadows.blockers_in(&pyramid, casts)
                })
            }),
            None => ShadowCone::patch(q, sp.ng, spread, centre, radius, ends).map(|cone| {
                search(shadows.cone_search(&cone, casts), &|| {
                    shadows.blockers_in(&cone, casts)
                })
            }),
        }
        .unwrap_or((ConeSearch::Unsearched, None));
        self.slots[slot] = Some((key, b));
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tests::scene_with;
    use crate::material::{Bsdf, DiffuseBsdf};
    use crate::visibility::TestShadows;
    use crate::visibility::cone::tests::{floor, segments, square};

    /// A point of the floor of `cone::tests::floor` (unit quads over [−5, 5]², two triangles
    /// each), seen from above.
    fn floor_point(x: f64, z: f64) -> SurfacePoint {
        let (i, j) = ((x + 5.0).floor() as usize, (z + 5.0).floor() as usize);
        let p = DVec3::new(x, 0.0, z);
        SurfacePoint {
            p,
            ng: DVec3::Y,
            ns: DVec3::Y,
            offset: crate::geometry::offset_scale(p),
            bsdf: Bsdf::Diffuse(DiffuseBsdf {
                albedo: DVec3::ONE,
                ns: DVec3::Y,
            }),
            mesh: 0,
            tri: 2 * (j * 10 + i),
            instance: None,
        }
    }

    #[test]
    fn patch_answers_are_sound_and_the_same_remembered_or_not() {
        // A light of radius 0.4 above a floor with a small square between them.
        let ball = (DVec3::new(0.3, 1.5, -0.2), 0.4, RayEnds::NearSide);
        let scene = scene_with(vec![floor(), square(DVec3::new(0.0, 0.5, 0.0), 0.15)]);
        let g = TestShadows::new(&scene);
        let mut kept = ClearPatches::default();
        let (mut clear, mut blocked) = (0, 0);
        for i in 0..48 {
            for j in 0..48 {
                let sp = floor_point(-1.6 + i as f64 * 0.071, -1.7 + j as f64 * 0.069);
                let remembered = kept
                    .search(&scene, &g.shadows(), &sp, 0, ball, None, &|_| true)
                    .0;
                let fresh = ClearPatches::default()
                    .search(&scene, &g.shadows(), &sp, 0, ball, None, &|_| true)
                    .0;
                assert_eq!(remembered, fresh, "at {}", sp.p);
                match fresh {
                    ConeSearch::Clear => {
                        clear += 1;
                        // Nothing blocks this point's shadow rays.
                        let blocked = segments(sp.p, ball.0, ball.1, 300, false)
                            .into_iter()
                            .any(|(o, w, t)| g.occluded(o, w, 0.0, t));
                        assert!(!blocked, "clear patch at {} is blocked", sp.p);
                    }
                    ConeSearch::Blocked(_) => blocked += 1,
                    ConeSearch::Unsearched => panic!("a world mesh is searched"),
                }
            }
        }
        // Both answers occur: the square's shadow and its surround.
        assert!(
            clear > 1000 && blocked > 100,
            "clear {clear}, blocked {blocked}"
        );
        // Shadow linking that leaves the square out: every patch is clear.
        let sp = floor_point(0.2, -0.1);
        let linked = ClearPatches::default()
            .search(&scene, &g.shadows(), &sp, 0, ball, None, &|m| m != 1)
            .0;
        assert_eq!(linked, ConeSearch::Clear);
        // The light's index is part of the key: another light's answer is not reused.
        let mut m = ClearPatches::default();
        assert_ne!(
            m.search(&scene, &g.shadows(), &sp, 0, ball, None, &|_| true)
                .0,
            ConeSearch::Clear
        );
        assert_eq!(
            m.search(&scene, &g.shadows(), &sp, 1, ball, None, &|m| m != 1)
                .0,
            ConeSearch::Clear
        );
    }

    /// Where a patch may be blocked, the few triangles it names answer every shadow ray of its
    /// points as the whole BVH does: towards a ball (its cone) and a rect (its pyramid), over
    /// a floor with a flat square (both as their outlines in the shadow rays' BVH) and small
    /// scattered triangles, some patches with few enough of them, some not.
    #[test]
    fn a_blocked_patchs_few_triangles_answer_its_shadow_rays() {
        use crate::visibility::cone::tests::mesh;
        use crate::visibility::pyramid::tests::{rect, segments as rect_segments};
        use lux_sample::SplitMix64;
        let mut rng = SplitMix64::new(3);
        let mut u = move || rng.next_f64();
        let (mut v, mut t) = (Vec::new(), Vec::new());
        // (60: the shadow rays' BVH, 4 + 60 triangles, stays within a quarter of the world's)
        for i in 0..60u32 {
            let c = DVec3::new(1.6 * u() - 0.8, 0.3 + 0.5 * u(), 1.6 * u() - 0.8);
            for _ in 0..3 {
                v.push(c + DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 0.12);
            }
            t.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        let scene = scene_with(vec![
            floor(),
            square(DVec3::new(0.0, 0.5, 0.0), 0.15),
            mesh("/bits", v, t),
        ]);
        let g = TestShadows::new(&scene);
        let centre = DVec3::new(0.3, 1.5, -0.2);
        let corners = rect(centre, DVec3::Y, DVec3::X, (0.5, 0.4));
        for with_rect in [false, true] {
            let ball = if with_rect {
                (centre, 0.5f64.hypot(0.4), RayEnds::Anywhere)
            } else {
                (centre, 0.4, RayEnds::NearSide)
            };
            let r = with_rect.then_some(&corners);
            let mut kept = ClearPatches::default();
            let (mut few, mut many, mut rays, mut hit) = (0, 0, 0, 0);
            for i in 0..40 {
                for j in 0..40 {
                    let sp = floor_point(-2.0 + i as f64 * 0.1, -2.1 + j as f64 * 0.103);
                    let (b, ids) = kept.search(&scene, &g.shadows(), &sp, 0, ball, r, &|_| true);
                    assert_eq!(
                        (b, ids),
                        ClearPatches::default().search(
                            &scene,
                            &g.shadows(),
                            &sp,
                            0,
                            ball,
                            r,
                            &|_| true
                        )
                    );
                    let Some(ids) = ids else {
                        many += matches!(b, ConeSearch::Blocked(_)) as u32;
                        continue;
                    };
                    assert!(matches!(b, ConeSearch::Blocked(_)));
                    few += 1;
                    let segs = if with_rect {
                        rect_segments(sp.p, &corners, 100)
                    } else {
                        segments(sp.p, ball.0, ball.1, 100, false)
                    };
                    for (o, w, t) in segs {
                        let all = g.occluded(o, w, 0.0, t);
                        assert_eq!(g.occluded_among(&ids, o, w, 0.0, t), all, "at {}", sp.p);
                        rays += 1;
                        hit += all as u32;
                    }
                }
            }
            assert!(
                few > 50 && many > 10 && hit > 500 && hit < rays,
                "rect {with_rect}: {few} few, {many} many, {hit} of {rays} blocked"
            );
        }
    }

    #[test]
    fn rect_patches_search_the_pyramid_and_are_sound() {
        use crate::visibility::pyramid::tests::{rect, segments as rect_segments};
        // A wide rect 1.2 above the floor (its ball reaches the floor: only the pyramid
        // holds), a small square under it.
        let corners = rect(DVec3::new(0.1, 1.2, 0.0), DVec3::Y, DVec3::X, (1.2, 0.9));
        let ball = (
            DVec3::new(0.1, 1.2, 0.0),
            1.2f64.hypot(0.9),
            RayEnds::Anywhere,
        );
        let scene = scene_with(vec![floor(), square(DVec3::new(0.0, 0.6, 0.0), 0.05)]);
        let g = TestShadows::new(&scene);
        let mut kept = ClearPatches::default();
        let (mut clear, mut blocked) = (0, 0);
        for i in 0..40 {
            for j in 0..40 {
                let sp = floor_point(-4.0 + i as f64 * 0.2, -3.9 + j as f64 * 0.197);
                let r = Some(&corners);
                let remembered = kept
                    .search(&scene, &g.shadows(), &sp, 0, ball, r, &|_| true)
                    .0;
                let fresh = ClearPatches::default()
                    .search(&scene, &g.shadows(), &sp, 0, ball, r, &|_| true)
                    .0;
                assert_eq!(remembered, fresh, "at {}", sp.p);
                match fresh {
                    ConeSearch::Clear => {
                        clear += 1;
                        let hit = rect_segments(sp.p, &corners, 300)
                            .into_iter()
                            .any(|(o, w, t)| g.occluded(o, w, 0.0, t));
                        assert!(!hit, "clear patch at {} is blocked", sp.p);
                    }
                    ConeSearch::Blocked(_) => blocked += 1,
                    ConeSearch::Unsearched => panic!("the rect is above every floor point"),
                }
            }
        }
        assert!(
            clear > 100 && blocked > 100,
            "clear {clear}, blocked {blocked}"
        );
    }
}
