//! The camera rays of one tile of pixels: the convex region they stay in, and the few world
//! triangles it can reach, so that those rays test a short list instead of the BVH.
//!
//! A pinhole camera maps the film linearly to ray directions from its eye, so the rays through a
//! rectangle of the film fill the convex pyramid with apex at the eye spanned by the four corner
//! rays: the intersection of four half-spaces, each bounded by the plane through two neighbouring
//! corner rays. An orthographic camera's rays are parallel, from the film rectangle's points:
//! a prism, bounded the same way. A triangle wholly outside one of the planes (by a margin that
//! covers the `f32` rounding of the traversal's rays) cannot be hit by any ray of the tile; the
//! BVH's boxes are tested the same way ([`ShadowRegion::node_mask`]).

use crate::camera::Camera;
use crate::geometry::Region as ShadowRegion;
use glam::DVec3;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::triangle::Triangle;

/// The region every camera ray through a rectangle of the film stays in.
#[derive(Clone, Copy, Debug)]
pub struct RayFrustum {
    /// Unit inward normals of the four sides with `n·x₀` (`x₀` a point of the side): inside is
    /// `n·x ≥ that`.
    planes: [(DVec3, f64); 4],
    /// The centre ray's direction (the BVH's traversal order).
    axis: DVec3,
    /// Distance by which a box or triangle must lie outside a plane.
    margin: f64,
}

impl RayFrustum {
    /// The region every ray through pixels `rect` of `camera` stays in
    /// ([`Camera::rect_rays`]), for geometry whose coordinates are at most `extent` in
    /// magnitude. `None` for an empty rectangle or a degenerate side.
    pub fn of_tile(camera: &Camera, rect: [u32; 4], extent: f64) -> Option<RayFrustum> {
        let rays = camera.rect_rays(rect)?;
        // Bounds every coordinate and distance between the rays' origins (the corners' span
        // them all) and the geometry.
        let scale = 2.0
            * (extent
                + rays
                    .corners
                    .iter()
                    .map(|r| r.0.abs().max_element())
                    .fold(0.0, f64::max));
        RayFrustum::new(
            rays.corners.map(|r| r.0),
            rays.corners.map(|r| r.1),
            rays.centre,
            scale,
        )
    }

    /// The region of the rays leaving `origins[i] + s·(origins[i+1] − origins[i])` along the
    /// matching blend of `dirs` (the four corner rays of a film rectangle in order around it:
    /// a pinhole's four directions from one eye, or an orthographic camera's four origins with
    /// one direction), `centre` a point inside it, `scale` bounding the coordinates and the
    /// distances of the geometry the rays can reach (the margin is 1e-5 of it). `None` when a
    /// side is degenerate or the centre is not strictly inside.
    pub fn new(
        origins: [DVec3; 4],
        dirs: [DVec3; 4],
        centre: (DVec3, DVec3),
        scale: f64,
    ) -> Option<RayFrustum> {
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let inside = centre.0 + centre.1;
        let mut planes = [(DVec3::ZERO, 0.0); 4];
        for i in 0..4 {
            let j = (i + 1) % 4;
            // The plane through ray i and ray j: spanned by dᵢ and (oⱼ + dⱼ − oᵢ) (for a
            // pinhole dᵢ × dⱼ, for parallel rays d × (oⱼ − oᵢ)).
            let n = dirs[i]
                .cross(origins[j] + dirs[j] - origins[i])
                .try_normalize()?;
            let n = if n.dot(inside - origins[i]) >= 0.0 {
                n
            } else {
                -n
            };
            // (NaN fails too)
            if n.dot(inside - origins[i]).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            planes[i] = (n, n.dot(origins[i]));
        }
        Some(RayFrustum {
            planes,
            axis: centre.1.try_normalize()?,
            margin: 1e-5 * scale,
        })
    }

    /// True when the box `[lo, hi]` lies wholly outside one of the four sides (by the margin,
    /// grown by 10⁻⁹ of the box's coordinates for a box beyond the geometry the region was
    /// made for): no ray of the region meets it. For a side `n·x ≥ d`, the box's farthest point
    /// inward is its centre `c` plus `|n|·e` (`e` its half size): outside when
    /// `n·c + |n|·e − d` is below `−margin`.
    pub fn misses_box(&self, lo: DVec3, hi: DVec3) -> bool {
        let (c, e) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
        let margin = self.margin + 1e-9 * (c.abs() + e).max_element();
        self.planes
            .iter()
            .any(|&(n, d)| n.dot(c) + n.abs().dot(e) - d < -margin)
    }
}

impl ShadowRegion for RayFrustum {
    /// The centre ray's direction.
    fn axis(&self) -> DVec3 {
        self.axis
    }

    /// True when the triangle lies wholly outside one of the four sides.
    #[inline]
    fn culls_triangle(&self, t: &Triangle) -> bool {
        crate::geometry::outside_a_plane(&self.planes, self.margin, t)
    }

    /// The CWBVH hit mask of the node's children the frustum may reach (as the pyramid's,
    /// [`super::ShadowPyramid`], without its floor).
    #[inline(always)]
    fn node_mask(&self, node: &CwBvhNode, oct_inv4: u32) -> u32 {
        let tests = self.planes.map(|(n, d)| {
            (
                crate::geometry::in_node_frame(node, n, d),
                -self.margin as f32,
            )
        });
        crate::geometry::child_mask(
            node,
            oct_inv4,
            crate::geometry::above_all(node, &tests),
            |_| false,
        )
    }

    fn to_prototype(&self, qt: &glam::DMat3, t: DVec3, s: f64, extra: f64) -> RayFrustum {
        // n·x ≥ d with x = s·Q·x' + t: (Qᵀn)·x' ≥ (d − n·t) / s.
        RayFrustum {
            planes: self.planes.map(|(n, d)| (*qt * n, (d - n.dot(t)) / s)),
            axis: *qt * self.axis,
            margin: self.margin / s + extra,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::TestShadows;
    use glam::{DMat4, DVec4};
    use lux_usd::Projection;

    /// Every ray through a tile of pixels hits, among the triangles the tile's frustum keeps,
    /// what it hits in the whole BVH: a floor grid, a tilted single-sided card seen from both
    /// sides and scattered small triangles (some behind the camera), through perspective and
    /// orthographic cameras turned off their axes, in 16-pixel tiles and in odd ones. The lists
    /// stay short (the culling works), and rays from outside a tile miss what it keeps.
    #[test]
    fn a_tiles_triangles_are_every_triangle_its_rays_hit() {
        use crate::geometry::tests::scene_with;
        use crate::visibility::cone::tests::{floor, mesh};
        use lux_sample::SplitMix64;
        let mut rng = SplitMix64::new(7);
        let mut u = move || rng.next_f64();
        let mut card = mesh(
            "/card",
            vec![
                DVec3::new(-1.0, 0.5, -1.0),
                DVec3::new(1.0, 1.5, -1.0),
                DVec3::new(1.0, 1.5, 1.0),
                DVec3::new(-1.0, 0.5, 1.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        card.double_sided = false;
        let (mut v, mut t) = (Vec::new(), Vec::new());
        for i in 0..300u32 {
            let c = DVec3::new(16.0 * u() - 8.0, 40.0 * u() - 5.0, 16.0 * u() - 8.0);
            for _ in 0..3 {
                v.push(c + DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 0.6);
            }
            t.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        let scene = scene_with(vec![floor(), card, mesh("/bits", v, t)]);
        let g = TestShadows::new(&scene);
        let total = g.triangle_count();
        let (lo, hi) = g.world_bounds().unwrap();
        let extent = lo.abs().max(hi.abs()).max_element();
        let turn = DMat4::from_rotation_z(0.3) * DMat4::from_rotation_x(-0.4);
        for ortho in [false, true] {
            let mut c = crate::camera::tests::luxtest_camera();
            c.camera_to_world = turn * c.camera_to_world;
            if ortho {
                c.projection = Projection::Orthographic;
                c.horizontal_aperture = 120.0;
                c.vertical_aperture = 120.0;
            }
            let cam = Camera::new(&c, [64, 48], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).unwrap();
            let (mut kept, mut tiles, mut outside) = (0, 0, 0);
            for (tw, th) in [(16, 16), (5, 7)] {
                for y0 in (0..48).step_by(th) {
                    for x0 in (0..64).step_by(tw) {
                        let rect = [x0, y0, (x0 + tw as u32).min(64), (y0 + th as u32).min(48)];
                        let f = RayFrustum::of_tile(&cam, rect, extent).unwrap();
                        let ids = g.triangles_in(&f, usize::MAX).unwrap();
                        kept += ids.len();
                        tiles += 1;
                        let [x0, y0, x1, y1] = rect.map(f64::from);
                        let mut missed = 0u32;
                        for k in 0..64 {
                            // (the corners too)
                            let (px, py) = match k {
                                0 => (x0, y0),
                                1 => (x1, y1),
                                _ => (x0 + (x1 - x0) * u(), y0 + (y1 - y0) * u()),
                            };
                            let (o, d, tmin, tmax) = cam.ray(px, py);
                            let all = g.intersect(&scene, o, d, tmin, tmax);
                            let among = g.intersect_among(&scene, &ids, o, d, tmin, tmax);
                            assert_eq!(among, all, "ortho {ortho} tile {rect:?} at ({px}, {py})");
                            // A ray from beside the tile: what it hits is not always kept.
                            let (o, d, tmin, tmax) = cam.ray(px + 2.0 * (x1 - x0) + 1.0, py);
                            let all = g.intersect(&scene, o, d, tmin, tmax);
                            missed += (all.is_some()
                                && g.intersect_among(&scene, &ids, o, d, tmin, tmax) != all)
                                as u32;
                        }
                        outside += missed;
                    }
                }
            }
            assert!(
                kept < tiles * total / 10,
                "ortho {ortho}: {kept} kept in {tiles} tiles of {total}"
            );
            assert!(
                outside > 50,
                "ortho {ortho}: {outside} rays beside the tiles missed"
            );
        }
    }

    /// A box a tile's frustum misses ([`RayFrustum::misses_box`]) meets none of the tile's rays
    /// (a slab test along 64 rays through the tile, its corners among them), for boxes of
    /// every size around a camera turned off its axes; both answers occur, and boxes straddling
    /// the tile's sides are kept.
    #[test]
    fn boxes_a_frustum_misses_meet_none_of_its_rays() {
        use lux_sample::SplitMix64;
        let mut rng = SplitMix64::new(9);
        let mut u = move || rng.next_f64();
        let mut c = crate::camera::tests::luxtest_camera();
        c.camera_to_world =
            DMat4::from_rotation_z(0.3) * DMat4::from_rotation_x(-0.4) * c.camera_to_world;
        let cam = Camera::new(&c, [64, 48], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).unwrap();
        let (mut missed, mut kept, mut met) = (0, 0, 0);
        for k in 0..3000 {
            let (x0, y0) = ((u() * 56.0) as u32, (u() * 40.0) as u32);
            let rect = [
                x0,
                y0,
                x0 + 1 + (u() * 7.0) as u32,
                y0 + 1 + (u() * 7.0) as u32,
            ];
            let f = RayFrustum::of_tile(&cam, rect, 40.0).unwrap();
            // Boxes around points on rays through and near the tile, 2 to 40 from the camera.
            let [x0, y0, x1, y1] = rect.map(f64::from);
            let (o, d, _, _) = cam.ray(
                x0 - 4.0 + (x1 - x0 + 8.0) * u(),
                y0 - 4.0 + (y1 - y0 + 8.0) * u(),
            );
            let centre = o + d * (2.0 + 38.0 * u());
            let half = DVec3::new(u(), u(), u()) * if k % 3 == 0 { 1.0 } else { 0.1 };
            let (lo, hi) = (centre - half, centre + half);
            let hits = (0..64).any(|k| {
                let (px, py) = match k {
                    0 => (x0, y0),
                    1 => (x1, y0),
                    2 => (x1, y1),
                    3 => (x0, y1),
                    _ => (x0 + (x1 - x0) * u(), y0 + (y1 - y0) * u()),
                };
                let (o, d, _, _) = cam.ray(px, py);
                let (t0, t1) = ((lo - o) / d, (hi - o) / d);
                let near = t0.min(t1).max_element().max(0.0);
                near <= t0.max(t1).min_element()
            });
            if f.misses_box(lo, hi) {
                assert!(!hits, "tile {rect:?} box {lo} {hi}");
                missed += 1;
            } else {
                kept += 1;
                met += hits as u32;
            }
        }
        assert!(
            missed > 300 && kept > 300 && met > 100,
            "{missed} missed, {kept} kept, {met} met"
        );
    }
}
