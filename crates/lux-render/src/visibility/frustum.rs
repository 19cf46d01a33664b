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
