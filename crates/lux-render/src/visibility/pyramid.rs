//! Proving that nothing can shadow a rect light: the pyramid of its shadow rays from a
//! shading point, and a conservative test of the BVH's boxes and triangles against it.
//!
//! Every shadow ray towards a point of a rect (a parallelogram, `inputs:width` ×
//! `inputs:height` under the light's transform) runs from the ray origin `o = p + ng·δ` to a
//! point of the rect: it stays in the convex pyramid with apex `o` over the rect, the
//! intersection of five half-spaces — one through `o` and each edge, and the rect's own plane
//! (the rays end on it). A box or triangle wholly outside one of them (by a margin covering the
//! `f32` traversal; for the rect's plane, wholly beyond it or on it within 10⁻⁶ of the scene's
//! scale), or wholly below the surface the rays leave (half the offset below `o`), cannot stop
//! any of them. Unlike the cone of a ball around the rect
//! ([`ShadowCone`](super::ShadowCone)), the pyramid is there whenever the rect itself lies above
//! the receiver's tangent plane, however large and near the rect is.

use crate::geometry::Region as ShadowRegion;
use glam::DVec3;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::triangle::Triangle;

/// The region every shadow ray towards a rect light stays in, from one shading point.
#[derive(Clone, Copy, Debug)]
pub struct ShadowPyramid {
    /// The rays' origin, `p + ng·offset`: the apex.
    apex: DVec3,
    /// Unit geometric normal of the surface the rays leave.
    ng: DVec3,
    /// Height along `ng` relative to the apex below which geometry is that surface: −δ/2.
    floor: f64,
    /// Unit inward normals of the four sides (through the apex) and of the rect's plane, with
    /// `n·apex` for the sides and `n·c₀ + margin + 10⁻⁶·scale` for the rect: inside is
    /// `n·x ≥ that` (and a triangle or box is outside when wholly below by the margin).
    planes: [(DVec3, f64); 5],
    /// Unit direction from the apex to the rect's centre (a traversal order).
    axis: DVec3,
    /// Distance by which a box or triangle must lie outside a plane.
    margin: f64,
}

impl ShadowPyramid {
    /// The pyramid from the surface point `p` (unit geometric normal `ng`, rays leaving from
    /// `p + ng·offset`) over the rect `corners` (in order around it). `None` unless every
    /// corner lies above the tangent plane by more than twice the offset (so that every ray
    /// rises from its origin) and the apex is off the rect's plane.
    pub fn new(p: DVec3, ng: DVec3, offset: f64, corners: &[DVec3; 4]) -> Option<ShadowPyramid> {
        Self::build(p, ng, [offset, offset], 0.0, corners)
    }

    /// The region of the shadow rays from every point of a patch of a plane: the points
    /// within `spread` of `q` on the plane through `q` with unit normal `ng`, each leaving from
    /// its own offset [`offset_scale`](crate::geometry::offset_scale) along `ng`, towards the
    /// rect. Every such ray point lies within `spread + Δδ` of a ray of the pyramid from the
    /// apex `q + ng·δ_lo` to the same end (δ_lo, δ_hi the least and most offset over the patch,
    /// Δδ their difference), so at most that far outside each of its planes: the margin grows
    /// by `spread` (δ_hi it has). Every origin is on the plane, at least δ_lo above it, and
    /// every corner above it, so the rays rise.
    pub fn patch(q: DVec3, ng: DVec3, spread: f64, corners: &[DVec3; 4]) -> Option<ShadowPyramid> {
        let offsets = super::patch_offsets(q, spread)?;
        Self::build(q, ng, offsets, spread, corners)
    }

    /// The pyramid from the plane point `p` (origins within `spread` of it on its plane,
    /// offset by `[δ_lo, δ_hi]` along `ng`) over the rect.
    fn build(
        p: DVec3,
        ng: DVec3,
        [lo, hi]: [f64; 2],
        spread: f64,
        corners: &[DVec3; 4],
    ) -> Option<ShadowPyramid> {
        if !corners.iter().all(|&c| ng.dot(c - p) > 2.0 * hi) {
            return None;
        }
        let apex = p + ng * lo;
        let centre = (corners[0] + corners[1] + corners[2] + corners[3]) * 0.25;
        let scale = p.abs().max_element()
            + spread
            + corners.iter().map(|c| c.distance(p)).fold(0.0, f64::max);
        let margin = 1e-5 * scale + hi + spread;
        let inward = |n: DVec3| -> Option<DVec3> {
            let n = n.try_normalize()?;
            Some(if n.dot(centre - apex) >= 0.0 { n } else { -n })
        };
        let mut planes = [(DVec3::ZERO, 0.0); 5];
        for i in 0..4 {
            let (a, b) = (corners[i] - apex, corners[(i + 1) % 4] - apex);
            let n = inward(a.cross(b))?;
            planes[i] = (n, n.dot(apex));
        }
        // The rect's plane, facing the apex: the rays end on it.
        let n = (corners[1] - corners[0])
            .cross(corners[3] - corners[0])
            .try_normalize()?;
        let n = if n.dot(apex - corners[0]) >= 0.0 {
            n
        } else {
            -n
        };
        // (NaN fails too)
        if n.dot(apex - corners[0]).partial_cmp(&margin) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        // (a triangle or box is outside it when wholly within 10⁻⁶ of the scale beyond it or on
        // it: the rays end on the rect, so what lies in its plane — a ceiling around a light
        // in its hole, rounded to f32 — meets none of them before their end)
        planes[4] = (n, n.dot(corners[0]) + margin + 1e-6 * scale);
        Some(ShadowPyramid {
            apex,
            ng,
            floor: -0.5 * lo,
            planes,
            axis: (centre - apex).try_normalize()?,
            margin,
        })
    }
}

impl ShadowRegion for ShadowPyramid {
    /// The direction to the rect's centre (a traversal order for the BVH).
    fn axis(&self) -> DVec3 {
        self.axis
    }

    /// True when the triangle cannot stop a shadow ray: below the surface, or wholly outside
    /// one of the five planes.
    #[inline]
    fn culls_triangle(&self, t: &Triangle) -> bool {
        let up = self.ng.dot(self.apex);
        [t.v0, t.v1, t.v2]
            .iter()
            .all(|x| self.ng.dot(x.as_dvec3()) - up < self.floor)
            || crate::geometry::outside_a_plane(&self.planes, self.margin, t)
    }

    /// The CWBVH hit mask of the node's children the pyramid may reach, in the traversal
    /// order of `oct_inv4` (as the cone's, [`super::ShadowCone`]): the
    /// children's boxes in the node's quantized frame, in `f32`, each plane's largest value
    /// over a box from its corner farthest along the normal.
    fn to_prototype(&self, qt: &glam::DMat3, t: DVec3, s: f64, extra: f64) -> ShadowPyramid {
        // n·x ≥ d with x = s·Q·x' + t: (Qᵀn)·x' ≥ (d − n·t) / s.
        ShadowPyramid {
            apex: *qt * (self.apex - t) / s,
            ng: *qt * self.ng,
            floor: self.floor / s,
            planes: self.planes.map(|(n, d)| (*qt * n, (d - n.dot(t)) / s)),
            axis: *qt * self.axis,
            margin: self.margin / s + extra,
        }
    }

    #[inline(always)]
    fn node_mask(&self, node: &CwBvhNode, oct_inv4: u32) -> u32 {
        let frame = |n: DVec3, d: f64| crate::geometry::in_node_frame(node, n, d);
        let side = |i: usize| {
            (
                frame(self.planes[i].0, self.planes[i].1),
                -self.margin as f32,
            )
        };
        let floor = (frame(self.ng, self.ng.dot(self.apex)), self.floor as f32);
        let tests = [floor, side(0), side(1), side(2), side(3), side(4)];
        crate::geometry::child_mask(
            node,
            oct_inv4,
            crate::geometry::above_all(node, &tests),
            |_| false,
        )
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::tests::scene_with;
    use crate::visibility::TestShadows;
    use crate::visibility::cone::tests::{drops_only_what_no_ray_meets, floor, mesh, square};
    use proptest::prelude::*;

    /// A rect of half-sizes `(a, b)` centred at `c`, its sides along `u` and `u × n`
    /// (`n` its normal).
    pub(crate) fn rect(c: DVec3, n: DVec3, u: DVec3, (a, b): (f64, f64)) -> [DVec3; 4] {
        let n = n.normalize();
        let u = (u - n * n.dot(u)).normalize();
        let v = n.cross(u);
        [(-a, -b), (a, -b), (a, b), (-a, b)].map(|(x, y)| c + u * x + v * y)
    }

    fn pyramid_from(p: DVec3, corners: &[DVec3; 4]) -> Option<ShadowPyramid> {
        ShadowPyramid::new(p, DVec3::Y, crate::geometry::offset_scale(p), corners)
    }

    /// Shadow-ray segments from `p`'s offset origin to points of the rect: its boundary at
    /// 16 points an edge and a grid inside, as the renderer traces them (`shadow_tmax`).
    pub(crate) fn segments(p: DVec3, corners: &[DVec3; 4], n: usize) -> Vec<(DVec3, DVec3, f64)> {
        let o = p + DVec3::Y * crate::geometry::offset_scale(p);
        let at = |s: f64, t: f64| {
            let a = corners[0].lerp(corners[1], s);
            let b = corners[3].lerp(corners[2], s);
            a.lerp(b, t)
        };
        let mut ends = Vec::new();
        for i in 0..16 {
            let s = i as f64 / 16.0;
            ends.extend([at(s, 0.0), at(1.0, s), at(1.0 - s, 1.0), at(0.0, 1.0 - s)]);
        }
        let k = ((n.saturating_sub(ends.len())) as f64).sqrt().ceil() as usize;
        for i in 0..k {
            for j in 0..k {
                ends.push(at((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64));
            }
        }
        ends.into_iter()
            .map(|x| {
                let d = x - o;
                let t = d.length();
                (o, d / t, crate::geometry::shadow_tmax(t, x))
            })
            .collect()
    }

    #[test]
    fn a_wide_low_rect_is_clear_over_a_bare_floor_where_its_ball_has_no_cone() {
        // 3 × 2, 0.4 above the floor, facing down: its ball (radius 1.8) reaches the horizon.
        let corners = rect(DVec3::new(0.2, 0.4, -0.1), DVec3::Y, DVec3::X, (1.5, 1.0));
        let p = DVec3::new(0.3, 0.0, 0.2);
        let (c, r) = (DVec3::new(0.2, 0.4, -0.1), 1.5f64.hypot(1.0));
        let offset = crate::geometry::offset_scale(p);
        assert!(
            crate::visibility::ShadowCone::new(
                p,
                DVec3::Y,
                offset,
                c,
                r,
                super::super::RayEnds::Anywhere
            )
            .is_none()
        );
        let pyramid = pyramid_from(p, &corners).unwrap();
        let bare = TestShadows::new(&scene_with(vec![floor()]));
        assert!(bare.cone_clear(&pyramid, &|_| true));
        // A small square under the rect, between it and p: blocked; beside the pyramid or
        // above the rect: clear.
        for (at, clear) in [
            (DVec3::new(0.25, 0.2, 0.0), false),
            (DVec3::new(2.5, 0.2, 0.0), true),
            (DVec3::new(0.25, 0.6, 0.0), true),
        ] {
            let g = TestShadows::new(&scene_with(vec![floor(), square(at, 0.05)]));
            assert_eq!(g.cone_clear(&pyramid, &|_| true), clear, "square at {at}");
            let blocked = segments(p, &corners, 400)
                .into_iter()
                .any(|(o, w, t)| g.occluded(o, w, 0.0, t));
            assert_eq!(blocked, !clear, "square at {at}");
        }
        // A ceiling around the rect in its plane, the rect filling its hole (a Cornell box's
        // light): it meets no shadow ray before the rect, and the pyramid drops it.
        let outer = rect(DVec3::new(0.2, 0.4, -0.1), DVec3::Y, DVec3::X, (3.0, 2.5));
        let ring: Vec<[u32; 3]> = (0..4u32)
            .flat_map(|i| {
                let j = (i + 1) % 4;
                [[i, j, 4 + j], [i, 4 + j, 4 + i]]
            })
            .collect();
        let points: Vec<DVec3> = corners.iter().chain(outer.iter()).copied().collect();
        let ceiling = TestShadows::new(&scene_with(vec![floor(), mesh("/ceiling", points, ring)]));
        assert!(ceiling.cone_clear(&pyramid, &|_| true));
        assert!(
            !segments(p, &corners, 400)
                .into_iter()
                .any(|(o, w, t)| ceiling.occluded(o, w, 0.0, t))
        );
        // A rect reaching below the tangent plane has no pyramid.
        let tilted = rect(
            DVec3::new(0.2, 0.4, -0.1),
            DVec3::new(0.0, 1.0, 0.6),
            DVec3::X,
            (1.5, 1.0),
        );
        assert!(pyramid_from(p, &tilted).is_none());
    }

    /// A small triangle near a face of the pyramid, `(ψ, s, k, f, h, u)`: from the point at
    /// azimuth `ψ` (turns) on the rim of the patch (the receiver itself without one), towards
    /// the rect's boundary point `s` (0–1 around its 4 edges), `k` × the way from its centre to
    /// that point, a fraction `f` of the way, half-size `h`, oriented by `u`.
    type Blocker = (f64, f64, f64, f64, f64, (f64, f64, f64));

    /// A receiver on the floor (or the patch within `spread` of it), a rect above it, small
    /// triangles near the pyramid's faces.
    #[derive(Clone, Debug)]
    struct Case {
        p: DVec3,
        spread: f64,
        corners: [DVec3; 4],
        blockers: Vec<Blocker>,
    }

    /// The points of the floor within `spread` of `p` the rays of a case leave from: `p`, and
    /// for a patch its rim at 12 azimuths and 4 points halfway.
    fn patch_points(p: DVec3, spread: f64) -> Vec<DVec3> {
        let mut points = vec![p];
        if spread > 0.0 {
            for i in 0..16 {
                let (r, phi) = if i < 12 {
                    (spread, i as f64 / 12.0)
                } else {
                    (spread * 0.5, (i - 12) as f64 / 4.0 + 0.125)
                };
                let phi = phi * std::f64::consts::TAU;
                points.push(p + DVec3::new(r * phi.cos(), 0.0, r * phi.sin()));
            }
        }
        points
    }

    impl Case {
        fn region(&self) -> Option<ShadowPyramid> {
            if self.spread > 0.0 {
                ShadowPyramid::patch(self.p, DVec3::Y, self.spread, &self.corners)
            } else {
                pyramid_from(self.p, &self.corners)
            }
        }

        fn segments(&self, n: usize) -> Vec<(DVec3, DVec3, f64)> {
            let points = patch_points(self.p, self.spread);
            let each = n.div_ceil(points.len()).max(80);
            points
                .into_iter()
                .flat_map(|q| segments(q, &self.corners, each))
                .collect()
        }

        fn scene(&self) -> TestShadows {
            let centre = self.corners.iter().sum::<DVec3>() * 0.25;
            let mut meshes = vec![floor()];
            for (i, &(psi, s, k, f, h, (ux, uy, uz))) in self.blockers.iter().enumerate() {
                let psi = psi * std::f64::consts::TAU;
                let o = self.p + self.spread * DVec3::new(psi.cos(), 0.0, psi.sin());
                let e = (s * 4.0).floor().min(3.0) as usize;
                let edge = self.corners[e].lerp(self.corners[(e + 1) % 4], s * 4.0 - e as f64);
                let x = centre.lerp(edge, k);
                let c = o.lerp(x, f);
                let u = DVec3::new(ux, uy, uz).normalize_or(DVec3::X);
                let b = u.any_orthonormal_vector();
                meshes.push(mesh(
                    &format!("/t{i}"),
                    vec![c + u * h, c - u * h + b * h, c - u * h - b * h],
                    vec![[0, 1, 2]],
                ));
            }
            TestShadows::new(&scene_with(meshes))
        }
    }

    prop_compose! {
        fn case()(
            px in -3.0f64..3.0, pz in -3.0f64..3.0,
            spread in prop_oneof![Just(0.0), 0.0f64..0.3],
            cx in -2.0f64..2.0, cy in 0.2f64..2.5, cz in -2.0f64..2.0,
            nx in -0.6f64..0.6, nz in -0.6f64..0.6, ux in -1.0f64..1.0,
            a in 0.05f64..2.0, b in 0.05f64..2.0,
            blockers in proptest::collection::vec(
                (0.0f64..1.0, 0.0f64..1.0, 0.8f64..1.25, 0.0f64..1.0, 0.005f64..0.2,
                 (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)), 1..5),
        ) -> Case {
            let n = DVec3::new(nx, -1.0, nz);
            Case {
                p: DVec3::new(px, 0.0, pz),
                spread,
                corners: rect(DVec3::new(cx, cy, cz), n, DVec3::new(ux, 0.3, 1.0), (a, b)),
                blockers,
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Conservative, whole search and box by box: "clear" means no shadow ray (traced
        /// through the renderer's `f32` BVH) is blocked, and every box a node test drops and
        /// every triangle dropped meets none of them. Blockers sit near the pyramid's faces
        /// (0.8–1.25 × the way from the rect's centre to its boundary). Half the cases are a
        /// patch's pyramid (spread up to 0.3), its rays from 17 points of the patch.
        #[test]
        fn the_pyramid_drops_only_what_no_shadow_ray_meets(c in case()) {
            let Some(pyramid) = c.region() else {
                return Ok(());
            };
            let g = c.scene();
            let segs = c.segments(1200);
            if g.cone_clear(&pyramid, &|_| true) {
                prop_assert!(!segs.iter().any(|&(o, w, t)| g.occluded(o, w, 0.0, t)));
            }
            drops_only_what_no_ray_meets(&g, &pyramid, &segs)?;
        }
    }
}
