//! Proving that nothing can shadow a light: the cone of a sphere holding the light (a sphere
//! light itself, or a ball around a rect or disk) seen from a shading point, and a
//! conservative test of the BVH's boxes and triangles against it.
//!
//! The shadow rays of a light sampled from `p` all run from the ray origin `o = p + ng·δ`
//! (δ the hit's offset) along a direction `w` inside the cone that the ball subtends from `p`
//! — apex `o`, unit axis `a` towards the centre, half-angle α with sin α = r/d — and end at a
//! point of the light: on a sphere light's near side, so `a·(x − o) ≤ d` along every segment
//! ([`RayEnds::NearSide`]); anywhere in the ball, `a·(x − o) ≤ d + r` ([`RayEnds::Anywhere`]). When the cone lies above the
//! geometric horizon (`ng·a > sin α`), every segment also stays above the tangent plane at `p`.
//! A triangle outside that region cannot stop any of them: if every triangle is, each shadow
//! ray is unblocked and the light's direct contribution is its unshadowed closed form
//! (`integrator/direct.rs`).
//!
//! [`ShadowCone::patch`] is the region of the shadow rays from every point of a patch of a
//! plane (`visibility/patches.rs`): the same tests with margins grown by the patch's radius.
//!
//! The test only ever answers "clear" when it is certain: a box or triangle is dismissed when
//! it lies wholly below the tangent plane at `p` (the surface the rays leave: what the offset
//! δ keeps them clear of), wholly behind the apex or beyond the far plane, or when its
//! bounding sphere misses the cone by a margin that covers the `f32` rounding of the traversal.

use crate::geometry::Region as ShadowRegion;
use glam::{DVec3, Vec3A, Vec4};
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::triangle::Triangle;

/// Where in the ball a light's shadow rays end ([`ShadowCone::new`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayEnds {
    /// On the sphere's near side (a sphere light seen from outside): `a·(x − o) ≤ d`.
    NearSide,
    /// Anywhere in the ball (a rect or disk inside it): `a·(x − o) ≤ d + r`.
    Anywhere,
}

/// The [`ConeSearch::Blocked`] id of instanced geometry: some instance's world box meets the
/// region (its prototype is not searched).
pub const INSTANCED: u32 = u32::MAX;

/// What a search of the BVH against a [`ShadowCone`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeSearch {
    /// No triangle can stop any of its rays.
    Clear,
    /// This triangle (an index into the triangles of the BVH shadow rays test,
    /// `Geometry::blockers`) might; or, for [`INSTANCED`], an instance's box meets the region.
    Blocked(u32),
    /// Not searched (a point on instanced geometry).
    Unsearched,
}

/// The region every shadow ray towards a light stays in, from one shading point.
#[derive(Clone, Copy, Debug)]
pub struct ShadowCone {
    /// Its unit geometric normal (the rays leave on its side).
    ng: DVec3,
    /// Height along `ng`, relative to the apex, below which geometry is the surface the rays
    /// leave: half the ray origin's offset below it.
    floor: f64,
    /// `ng·apex` and `axis·apex`.
    ng_apex: f64,
    axis_apex: f64,
    /// The square of sin_e = cos(β + α) > 0, the least `ng·w` over the cone's directions:
    /// every ray point x satisfies `ng·(x − apex) ≥ sin_e·|x − apex|`.
    sin_e2: f64,
    /// The rays' origin, `p + ng·offset`: the cone's apex.
    apex: DVec3,
    /// Unit axis, towards the sphere's centre.
    axis: DVec3,
    sin_a: f64,
    cos_a: f64,
    /// Largest `axis·(x − apex)` on a ray.
    far: f64,
    /// Distance by which a bounding sphere must miss the cone, and by which a box must lie
    /// below the rays' least rise: at least how far a ray's origin can be from the apex.
    margin: f64,
}

impl ShadowCone {
    /// The cone of the ball (`centre`, `radius`) seen from the surface point `p` with unit
    /// geometric normal `ng`, its rays leaving from `p + ng·offset` and ending as `ends` says.
    /// `None` unless the ball is wholly in front of the tangent plane (`ng·a > sin α`) and
    /// outside `p`.
    pub fn new(
        p: DVec3,
        ng: DVec3,
        offset: f64,
        centre: DVec3,
        radius: f64,
        ends: RayEnds,
    ) -> Option<ShadowCone> {
        Self::build(p, ng, [offset, offset], 0.0, (centre, radius, ends))
    }

    /// The region of the shadow rays from every point of a patch of a plane: the points
    /// within `spread` of `q` on the plane through `q` with unit normal `ng`, each leaving
    /// from its own offset [`offset_scale`](crate::geometry::offset_scale) along `ng`, towards
    /// the ball (`centre`, `radius`) as `ends` says. "Clear" for it means clear for each of
    /// those points' cones.
    ///
    /// Every such ray point lies within `spread + Δδ` of the region of the rays from the apex
    /// `q + ng·δ_lo` (δ_lo, δ_hi the least and most offset over the patch, Δδ = δ_hi − δ_lo):
    /// a point `y` of a ray from `o'` and the point of the apex's ray to the same end are
    /// `(1 − s)·|o' − apex|` apart. The margin of the distance tests grows by `spread` (δ_hi
    /// it already has). The rays' directions `x − o'` are those from `q` to points of the
    /// ball grown by `spread + δ_hi`, whose least elevation `e` bounds every ray's rise,
    /// `≥ sin e·|y − o'| ≥ sin e·|y − apex| − margin`, which the elevation test's margin
    /// covers. Every origin is at least δ_lo above the plane.
    pub fn patch(
        q: DVec3,
        ng: DVec3,
        spread: f64,
        centre: DVec3,
        radius: f64,
        ends: RayEnds,
    ) -> Option<ShadowCone> {
        let offsets = super::patch_offsets(q, spread)?;
        Self::build(q, ng, offsets, spread, (centre, radius, ends))
    }

    /// The cone from the plane point `p` (origins within `spread` of it on its plane, offset
    /// by `[δ_lo, δ_hi]` along `ng`) to the ball.
    fn build(
        p: DVec3,
        ng: DVec3,
        [lo, hi]: [f64; 2],
        spread: f64,
        (centre, radius, ends): (DVec3, f64, RayEnds),
    ) -> Option<ShadowCone> {
        let v = centre - p;
        let d = v.length();
        if !(d > radius + spread + hi && d.is_finite() && radius > 0.0) {
            return None;
        }
        let axis = v / d;
        let sin_a = radius / d;
        let cos_a = (1.0 - sin_a * sin_a).max(0.0).sqrt();
        // The rays' directions: from `p` towards the ball grown by the origins' largest
        // distance from `p` (`spread` along the plane, δ_hi up), a cone that must lie wholly
        // in front of the plane (NaN fails too).
        let sin_g = (radius + spread + hi) / d;
        if ng.dot(axis).partial_cmp(&sin_g) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let cos_g = (1.0 - sin_g * sin_g).max(0.0).sqrt();
        let cos_b = ng.dot(axis);
        let sin_b = (1.0 - cos_b * cos_b).max(0.0).sqrt();
        let sin_e = cos_b * cos_g - sin_b * sin_g;
        let scale = p.abs().max_element() + spread + d;
        let apex = p + ng * lo;
        Some(ShadowCone {
            ng,
            floor: -0.5 * lo,
            ng_apex: ng.dot(apex),
            axis_apex: axis.dot(apex),
            sin_e2: sin_e * sin_e,
            apex,
            axis,
            sin_a,
            cos_a,
            far: match ends {
                RayEnds::NearSide => d,
                RayEnds::Anywhere => d + radius,
            },
            margin: 1e-5 * scale + hi + spread,
        })
    }

    /// True when the sphere (`c`, `rho`) is certainly outside the cone.
    #[inline]
    fn misses_sphere(&self, c: DVec3, rho: f64) -> bool {
        let v = c - self.apex;
        let t = v.dot(self.axis);
        let h = (v.length_squared() - t * t).max(0.0).sqrt();
        // Distance from c to the cone: to its surface line when the foot falls in front of the
        // apex, else to the apex.
        let dist = if t * self.cos_a + h * self.sin_a >= 0.0 {
            h * self.cos_a - t * self.sin_a
        } else {
            v.length()
        };
        dist > rho + self.margin
    }

    /// True when the triangle `v` certainly misses the cone grown by `margin`: that set lies
    /// in the cone of the same angle whose apex is `margin / sin α` behind (every surface line
    /// moved out by `margin`), which the triangle misses when its projection from that apex
    /// misses the cone's cap of directions ([`lux_irradiance::hidden::cap_misses_polygon`]).
    fn misses_triangle(&self, v: &[DVec3; 3]) -> bool {
        let apex = self.apex - self.axis * (self.margin / self.sin_a);
        lux_irradiance::hidden::cap_misses_polygon(apex, self.axis, self.cos_a, v)
    }
}

impl ShadowRegion for ShadowCone {
    /// The axis, towards the ball's centre.
    fn axis(&self) -> DVec3 {
        self.axis
    }

    /// True when the triangle cannot stop a shadow ray.
    #[inline]
    fn culls_triangle(&self, t: &Triangle) -> bool {
        let v = [t.v0, t.v1, t.v2].map(|x: Vec3A| x.as_dvec3());
        let up = |x: DVec3| x.dot(self.ng) - self.ng_apex;
        let along = |x: DVec3| (x - self.apex).dot(self.axis);
        if v.iter().all(|&x| up(x) < self.floor)
            || v.iter().all(|&x| along(x) < -self.margin)
            || v.iter().all(|&x| along(x) > self.far + self.margin)
        {
            return true;
        }
        // Lower everywhere than the rays can be at its distance from the apex (the node test's
        // elevation bound, on the triangle's own box: its highest corner, its nearest point).
        let lift = v.iter().map(|&x| up(x)).fold(f64::MIN, f64::max) + self.margin;
        let gap = (v[0].min(v[1]).min(v[2]) - self.apex)
            .max(self.apex - v[0].max(v[1]).max(v[2]))
            .max(DVec3::ZERO);
        if lift * lift < gap.length_squared() * self.sin_e2 {
            return true;
        }
        let c = (v[0] + v[1] + v[2]) / 3.0;
        let rho = v.iter().map(|&x| x.distance(c)).fold(0.0, f64::max);
        self.misses_sphere(c, rho) || self.misses_triangle(&v)
    }

    fn to_prototype(&self, qt: &glam::DMat3, t: DVec3, s: f64, extra: f64) -> ShadowCone {
        let (ng, axis, apex) = (*qt * self.ng, *qt * self.axis, *qt * (self.apex - t) / s);
        ShadowCone {
            ng,
            floor: self.floor / s,
            ng_apex: ng.dot(apex),
            axis_apex: axis.dot(apex),
            sin_e2: self.sin_e2,
            apex,
            axis,
            sin_a: self.sin_a,
            cos_a: self.cos_a,
            far: self.far / s,
            margin: self.margin / s + extra,
        }
    }

    /// The CWBVH hit mask of the node's children the cone may reach (what
    /// `CwBvhNode::intersect_ray` returns for a ray), in the traversal order of `oct_inv4`.
    ///
    /// The children's boxes are tested in the node's quantized frame (`x = origin + e ⊙ q`,
    /// `q ∈ [0, 255]³`), in `f32`: the projections onto `ng` and the axis, and the distance to
    /// the apex, are a few multiply-adds per child there. Their rounding (a few ulps of the
    /// coordinates) is far inside the margins (1e-5 of the scene scale, the offset).
    #[inline(always)]
    fn node_mask(&self, node: &CwBvhNode, oct_inv4: u32) -> u32 {
        let e = node.compute_extent();
        let origin = Vec3A::from(node.p);
        let ng = self.ng.as_vec3a();
        let axis = self.axis.as_vec3a();
        let (ng_q, axis_q) = (ng * e, axis * e);
        let rise0 = ng.dot(origin) - self.ng_apex as f32;
        let along0 = axis.dot(origin) - self.axis_apex as f32;
        let a = ((self.apex.as_vec3a() - origin) / e).to_array();
        let es = e.to_array();
        let (floor, margin) = (self.floor as f32, self.margin as f32);
        let (far, sin_e2) = (self.far as f32, self.sin_e2 as f32);
        let [nx, ny, nz] = ng_q.to_array();
        let [ax, ay, az] = axis_q.to_array();
        // Four children at a time, one lane each.
        let mut keep = 0u32;
        for half in 0..2 {
            let boxes = crate::geometry::child_boxes(node, half);
            let (lo, hi) = boxes;
            let far_along = |n: [f32; 3]| crate::geometry::farthest_along(&boxes, n);
            let rise = far_along([nx, ny, nz]) + rise0;
            let reach = far_along([ax, ay, az]) + along0;
            let back = along0 - far_along([-ax, -ay, -az]);
            // (back in world units before squaring: in a flat node, e.g. of a horizontal card,
            // `e` is as small as 2⁻⁷⁴ and the quantized gap overflows `f32` when squared)
            let gap = |k: usize| {
                let g = (lo[k] - a[k]).max(a[k] - hi[k]).max(Vec4::ZERO) * es[k];
                g * g
            };
            let lift = rise + margin;
            let out = rise.cmplt(Vec4::splat(floor))
                | (lift * lift).cmplt((gap(0) + gap(1) + gap(2)) * sin_e2)
                | reach.cmplt(Vec4::splat(-margin))
                | back.cmpgt(Vec4::splat(far + margin));
            keep |= ((!out.bitmask()) & 0xf) << (4 * half);
        }
        crate::geometry::child_mask(node, oct_inv4, keep, |child| {
            let b = node.child_aabb(child);
            let centre = 0.5 * (b.min + b.max);
            self.misses_sphere(centre.as_dvec3(), 0.5 * (b.max - b.min).length() as f64)
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::tests::scene_with;
    use crate::visibility::TestShadows;
    use lux_usd::Mesh;
    use obvhs::cwbvh::node::extract_byte64;
    use proptest::prelude::*;

    /// A light of radius 0.5 at (0, 2, 0) seen from points of the floor y = 0 (normal +y, the
    /// offset a shading point there gets).
    fn cone_from(p: DVec3, centre: DVec3, radius: f64) -> ShadowCone {
        let offset = crate::geometry::offset_scale(p);
        ShadowCone::new(p, DVec3::Y, offset, centre, radius, RayEnds::NearSide).unwrap()
    }

    pub(crate) fn mesh(name: &str, v: Vec<DVec3>, tris: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            double_sided: true,
            ..Mesh::new(name, v, tris)
        }
    }

    /// A floor of 10 × 10 quads over [−5, 5]² at y = 0 (what the shading points lie on).
    pub(crate) fn floor() -> Mesh {
        let n = 10;
        let mut v = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                v.push(DVec3::new(-5.0 + i as f64, 0.0, -5.0 + j as f64));
            }
        }
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = (j * (n + 1) + i) as u32;
                let (b, c, d) = (a + 1, a + n as u32 + 2, a + n as u32 + 1);
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
        mesh("/floor", v, t)
    }

    /// A square of half-size `h` centred at `c`, horizontal.
    pub(crate) fn square(c: DVec3, h: f64) -> Mesh {
        let v = vec![
            c + DVec3::new(-h, 0.0, -h),
            c + DVec3::new(h, 0.0, -h),
            c + DVec3::new(h, 0.0, h),
            c + DVec3::new(-h, 0.0, h),
        ];
        mesh("/sq", v, vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn a_bare_floor_is_clear_and_a_blocker_in_the_cone_is_not() {
        let (centre, radius) = (DVec3::new(0.0, 2.0, 0.0), 0.5);
        let p = DVec3::new(0.3, 0.0, -0.2);
        let bare = TestShadows::new(&scene_with(vec![floor()]));
        assert!(bare.cone_clear(&cone_from(p, centre, radius), &|_| true));
        let blocked_in = |g: &TestShadows| {
            segments(p, centre, radius, 2000, false)
                .into_iter()
                .any(|(o, w, tmax)| g.occluded(o, w, 0.0, tmax))
        };
        assert!(!blocked_in(&bare));
        // A small square halfway up, above p: in the cone.
        let blocked = TestShadows::new(&scene_with(vec![
            floor(),
            square(DVec3::new(0.2, 1.0, -0.1), 0.1),
        ]));
        assert!(!blocked.cone_clear(&cone_from(p, centre, radius), &|_| true));
        assert!(blocked_in(&blocked));
        // Clear again for a light whose shadow linking leaves the square (mesh 1) out.
        assert!(blocked.cone_clear(&cone_from(p, centre, radius), &|m| m != 1));
        // The same square 2 units to the side: outside the cone, clear again.
        let beside = TestShadows::new(&scene_with(vec![
            floor(),
            square(DVec3::new(2.2, 1.0, -0.1), 0.1),
        ]));
        assert!(beside.cone_clear(&cone_from(p, centre, radius), &|_| true));
        // Above the light: beyond the far plane.
        let above = TestShadows::new(&scene_with(vec![
            floor(),
            square(DVec3::new(0.0, 3.0, 0.0), 2.0),
        ]));
        assert!(above.cone_clear(&cone_from(p, centre, radius), &|_| true));
    }

    #[test]
    fn a_patch_is_blocked_by_what_blocks_any_of_its_points() {
        let (centre, radius) = (DVec3::new(0.0, 2.0, 0.0), 0.3);
        let (p, edge) = (DVec3::ZERO, DVec3::new(0.5, 0.0, 0.0));
        // A small square on the way from the patch's edge point to the light, outside the
        // cone from its centre (at height 0.2 that cone is 0.03 wide around x = 0).
        let g = TestShadows::new(&scene_with(vec![
            floor(),
            square(DVec3::new(0.45, 0.2, 0.0), 0.02),
        ]));
        let blocked_from = |q: DVec3| {
            segments(q, centre, radius, 2000, false)
                .into_iter()
                .any(|(o, w, tmax)| g.occluded(o, w, 0.0, tmax))
        };
        assert!(!blocked_from(p) && blocked_from(edge));
        assert!(g.cone_clear(&cone_from(p, centre, radius), &|_| true));
        let patch = |spread| {
            ShadowCone::patch(p, DVec3::Y, spread, centre, radius, RayEnds::NearSide).unwrap()
        };
        assert!(!g.cone_clear(&patch(0.5), &|_| true));
        // A patch that stops short of the square's shadow is clear, and so is the bare floor.
        assert!(g.cone_clear(&patch(0.1), &|_| true));
        let bare = TestShadows::new(&scene_with(vec![floor()]));
        assert!(bare.cone_clear(&patch(0.5), &|_| true));
        // No patch cone once the grown ball reaches the horizon.
        assert!(ShadowCone::patch(p, DVec3::Y, 1.8, centre, radius, RayEnds::NearSide).is_none());
    }

    #[test]
    fn a_light_below_the_horizon_has_no_cone() {
        let p = DVec3::ZERO;
        // The sphere crosses the tangent plane: ng·a = 0.2 < sin α = 0.5.
        let c = DVec3::new(0.98, 0.2, 0.0);
        assert!(ShadowCone::new(p, DVec3::Y, 1e-5, c, 0.5, RayEnds::NearSide).is_none());
        // p inside the sphere.
        assert!(
            ShadowCone::new(p, DVec3::Y, 1e-5, DVec3::Y * 0.4, 0.5, RayEnds::NearSide).is_none()
        );
    }

    /// Shadow-ray segments of the cone, as the renderer traces them: from the offset origin
    /// along directions uniform in the cone (and its rim), to where each meets the sphere — on
    /// its near side, or with `whole_ball` on its far side (the farthest a light inside the
    /// ball can be).
    pub(crate) fn segments(
        p: DVec3,
        centre: DVec3,
        radius: f64,
        n: usize,
        whole_ball: bool,
    ) -> Vec<(DVec3, DVec3, f64)> {
        let origin = p + DVec3::Y * crate::geometry::offset_scale(p);
        let v = centre - p;
        let d = v.length();
        let cos_max = (1.0 - (radius / d).powi(2)).sqrt();
        let frame = lux_math::Frame::from_normal(v / d);
        (0..n)
            .map(|i| {
                let (cos_t, phi) = if i < 64 {
                    (cos_max, i as f64 / 64.0 * std::f64::consts::TAU)
                } else {
                    let u = (i as f64 + 0.5) / n as f64;
                    (1.0 - u * (1.0 - cos_max), i as f64 * 2.399_963_229_728_653)
                };
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let w = frame.to_world(DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t));
                let b = (p - centre).dot(w);
                let disc = (b * b - ((p - centre).length_squared() - radius * radius)).max(0.0);
                let t = if whole_ball {
                    -b + disc.sqrt()
                } else {
                    -b - disc.sqrt()
                };
                (origin, w, crate::geometry::shadow_tmax(t, p + w * t))
            })
            .collect()
    }

    /// Whether the segment `o + t·w`, `t ∈ [0, tmax]`, meets the box (slab test in `f64`).
    pub(crate) fn segment_meets_box(o: DVec3, w: DVec3, tmax: f64, b: &obvhs::aabb::Aabb) -> bool {
        let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
        let (mut t0, mut t1) = (0.0f64, tmax);
        for k in 0..3 {
            if w[k] == 0.0 {
                if o[k] < lo[k] || o[k] > hi[k] {
                    return false;
                }
                continue;
            }
            let (a, c) = ((lo[k] - o[k]) / w[k], (hi[k] - o[k]) / w[k]);
            t0 = t0.max(a.min(c));
            t1 = t1.min(a.max(c));
        }
        t0 <= t1
    }

    /// A blocker near the rim of the cone from a point of the floor: `(ψ, k, φ, t, s, u)` —
    /// from the point at azimuth `ψ` (turns) on the rim of the patch (the receiver itself
    /// without one), at `k` × its cone's half-angle from the axis, azimuth `φ` (turns), a
    /// fraction `t` of the centre's distance, half-size `s`, oriented by `u`.
    type Blocker = (f64, f64, f64, f64, f64, (f64, f64, f64));

    /// The floor and small triangles near the rim of the cones to the sphere from `p` or
    /// from points of the rim of the patch within `spread` of it.
    fn rim_scene(
        p: DVec3,
        spread: f64,
        centre: DVec3,
        radius: f64,
        blockers: &[Blocker],
    ) -> TestShadows {
        let mut meshes = vec![floor()];
        for (i, &(psi, k, phi, t, s, (ox, oy, oz))) in blockers.iter().enumerate() {
            let psi = psi * std::f64::consts::TAU;
            let p = p + spread * DVec3::new(psi.cos(), 0.0, psi.sin());
            let v = centre - p;
            let d = v.length();
            let frame = lux_math::Frame::from_normal(v / d);
            let alpha = (radius / d).asin();
            let (th, phi) = (k * alpha, phi * std::f64::consts::TAU);
            let w = frame.to_world(DVec3::new(
                th.sin() * phi.cos(),
                th.sin() * phi.sin(),
                th.cos(),
            ));
            let c = p + w * (t * d);
            let u = DVec3::new(ox, oy, oz).normalize_or(DVec3::X);
            let b = u.any_orthonormal_vector();
            let tri = vec![c + u * s, c - u * s + b * s, c - u * s - b * s];
            meshes.push(mesh(&format!("/t{i}"), tri, vec![[0, 1, 2]]));
        }
        TestShadows::new(&scene_with(meshes))
    }

    /// A receiver on the floor (or the patch of floor within `spread` of it), a light above
    /// it, blockers near its cone's rim, and whether the rays end anywhere in the ball.
    #[derive(Clone, Debug)]
    struct RimCase {
        p: DVec3,
        spread: f64,
        centre: DVec3,
        radius: f64,
        blockers: Vec<Blocker>,
        whole_ball: bool,
    }

    impl RimCase {
        /// The cone (`None` when the light is not above the horizon) and the scene.
        fn build(&self) -> Option<(ShadowCone, TestShadows)> {
            let offset = crate::geometry::offset_scale(self.p);
            let ends = if self.whole_ball {
                RayEnds::Anywhere
            } else {
                RayEnds::NearSide
            };
            let cone = if self.spread > 0.0 {
                ShadowCone::patch(
                    self.p,
                    DVec3::Y,
                    self.spread,
                    self.centre,
                    self.radius,
                    ends,
                )?
            } else {
                ShadowCone::new(self.p, DVec3::Y, offset, self.centre, self.radius, ends)?
            };
            Some((
                cone,
                rim_scene(
                    self.p,
                    self.spread,
                    self.centre,
                    self.radius,
                    &self.blockers,
                ),
            ))
        }

        /// About `n` shadow-ray segments of the case: from `p`, or from points of the patch
        /// (its rim at 12 azimuths, 4 points inside, the centre), each with its own offset and
        /// its own near side of the sphere.
        fn segments(&self, n: usize) -> Vec<(DVec3, DVec3, f64)> {
            if self.spread == 0.0 {
                return segments(self.p, self.centre, self.radius, n, self.whole_ball);
            }
            let mut points = vec![self.p];
            for i in 0..16 {
                let (r, phi) = if i < 12 {
                    (self.spread, i as f64 / 12.0)
                } else {
                    (self.spread * 0.5, (i - 12) as f64 / 4.0 + 0.125)
                };
                let phi = phi * std::f64::consts::TAU;
                points.push(self.p + DVec3::new(r * phi.cos(), 0.0, r * phi.sin()));
            }
            let each = n.div_ceil(points.len()).max(65);
            points
                .into_iter()
                .flat_map(|q| segments(q, self.centre, self.radius, each, self.whole_ball))
                .collect()
        }
    }

    prop_compose! {
        fn rim_case()(
            px in -3.0f64..3.0, pz in -3.0f64..3.0,
            spread in prop_oneof![Just(0.0), 0.0f64..0.3],
            lx in -2.0f64..2.0, ly in 0.8f64..4.0, lz in -2.0f64..2.0, radius in 0.05f64..0.7,
            blockers in proptest::collection::vec(
                (0.0f64..1.0, 0.8f64..1.25, 0.0f64..1.0, 0.0f64..2.0, 0.005f64..0.3,
                 (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)), 1..5),
            whole_ball in proptest::bool::ANY,
        ) -> RimCase {
            RimCase {
                p: DVec3::new(px, 0.0, pz),
                spread,
                centre: DVec3::new(lx, ly, lz),
                radius,
                blockers,
                whole_ball,
            }
        }
    }

    prop_compose! {
        /// [`rim_case`] with large triangles (half-size 0.3–3): the exact triangle test
        /// ([`ShadowCone::misses_triangle`]) decides where their bounding spheres meet the cone.
        fn rim_case_large()(
            case in rim_case(),
            sizes in proptest::collection::vec(0.3f64..3.0, 4),
        ) -> RimCase {
            let mut case = case;
            for (b, s) in case.blockers.iter_mut().zip(sizes) {
                b.4 = s;
            }
            case
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Conservative for large triangles too: a triangle the cone drops is hit by none of
        /// its shadow rays, and a clear search means no shadow ray is blocked.
        #[test]
        fn large_triangles_are_dropped_only_where_no_ray_meets_them(
            case in rim_case_large(),
        ) {
            let Some((cone, g)) = case.build() else {
                return Ok(());
            };
            let segs = case.segments(600);
            drops_only_what_no_ray_meets(&g, &cone, &segs)?;
            if g.cone_clear(&cone, &|_| true) {
                prop_assert!(!segs.iter().any(|&(o, w, tmax)| g.occluded(o, w, 0.0, tmax)));
            }
        }

        /// Conservative, whole search: whenever it says clear, no shadow ray of the cone
        /// (traced through the same `f32` BVH as the renderer's) is blocked. Small triangles sit
        /// near the cone's rim (0.8–1.25 × its half-angle from the axis), anywhere from the
        /// apex to twice the centre's distance, so that the answer is close either way; rays
        /// end on the sphere (a sphere light) or at the ball's far side (a light inside it).
        /// Half the cases are a patch's cone ([`ShadowCone::patch`], spread up to 0.3), its
        /// rays from points of the patch, rim included.
        #[test]
        fn clear_means_no_shadow_ray_is_blocked(
            case in rim_case(),
        ) {
            let Some((cone, g)) = case.build() else {
                return Ok(());
            };
            if g.cone_clear(&cone, &|_| true) {
                let blocked = case.segments(1500)
                    .into_iter()
                    .any(|(o, w, tmax)| g.occluded(o, w, 0.0, tmax));
                prop_assert!(!blocked);
            }
        }

        /// Conservative, box by box: a child box of any BVH node that the cone's node test
        /// drops is met by none of the cone's shadow-ray segments, and a triangle it drops is
        /// hit by none.
        #[test]
        fn dropped_boxes_and_triangles_meet_no_shadow_ray(
            case in rim_case(),
        ) {
            let Some((cone, g)) = case.build() else {
                return Ok(());
            };
            drops_only_what_no_ray_meets(&g, &cone, &case.segments(600))?;
        }
    }

    /// Every child box of any BVH node that `region`'s node test drops, and every triangle
    /// it drops, meets none of the segments `segs` (slab test in `f64`; the renderer's `f32`
    /// triangle test).
    pub(crate) fn drops_only_what_no_ray_meets(
        g: &TestShadows,
        region: &impl ShadowRegion,
        segs: &[(DVec3, DVec3, f64)],
    ) -> Result<(), TestCaseError> {
        let world = g.world().unwrap();
        for node in world.nodes() {
            // Identity octant: bit i of the mask's high byte stands for inner child i.
            let mask = region.node_mask(node, 0);
            let (bits, index) = node.get_child_and_index_bits(0);
            for child in 0..8 {
                if node.is_child_empty(child) {
                    continue;
                }
                let kept = (extract_byte64(bits, child) << extract_byte64(index, child)) & mask;
                if kept == 0 {
                    let b = node.child_aabb(child);
                    prop_assert!(
                        !segs.iter().any(|&(o, w, t)| segment_meets_box(o, w, t, &b)),
                        "dropped box {b:?}"
                    );
                }
            }
        }
        for t in world.triangles() {
            if region.culls_triangle(t) {
                let hits = |&(o, w, tmax): &(DVec3, DVec3, f64)| {
                    let r = obvhs::ray::Ray::new(o.as_vec3a(), w.as_vec3a(), 0.0, tmax as f32);
                    t.intersect(&r) < tmax as f32
                };
                prop_assert!(!segs.iter().any(hits), "dropped triangle {t:?}");
            }
        }
        Ok(())
    }

    /// A large card beside the cone (its bounding sphere reaches into the cone, the card does
    /// not) is dropped by the exact triangle test; moved across the axis, it is kept.
    #[test]
    fn a_large_card_beside_the_cone_is_dropped() {
        let (p, centre) = (DVec3::ZERO, DVec3::new(0.0, 2.0, 0.0));
        let cone = cone_from(p, centre, 0.3);
        // A vertical card in the plane x = 0.8, from y = 0.2 to 1.8, 3 wide: the cone's radius
        // at y = 1 is 0.15, the card's bounding sphere (radius ≈ 2) contains the axis.
        let card = |x: f64| {
            [
                DVec3::new(x, 0.2, -1.5),
                DVec3::new(x, 0.2, 1.5),
                DVec3::new(x, 1.8, 1.5),
            ]
        };
        let tri = |v: [DVec3; 3]| Triangle {
            v0: v[0].as_vec3a(),
            v1: v[1].as_vec3a(),
            v2: v[2].as_vec3a(),
        };
        let beside = card(0.8);
        let c = (beside[0] + beside[1] + beside[2]) / 3.0;
        let rho = beside.iter().map(|&x| x.distance(c)).fold(0.0, f64::max);
        assert!(!cone.misses_sphere(c, rho));
        assert!(cone.misses_triangle(&beside));
        assert!(cone.culls_triangle(&tri(beside)));
        // Across the axis: the card cuts the cone.
        assert!(!cone.misses_triangle(&card(0.0)));
        assert!(!cone.culls_triangle(&tri(card(0.0))));
        // Beside the axis by 0.2, which the cone's radius exceeds from y ≈ 1.3 up, where this
        // one reaches: kept; the card of the same plane ends at y = 1 there: dropped.
        let reaching = [
            DVec3::new(0.2, 0.2, 0.0),
            DVec3::new(0.2, 1.9, -1.5),
            DVec3::new(0.2, 1.9, 1.5),
        ];
        assert!(!cone.misses_triangle(&reaching));
        assert!(!cone.culls_triangle(&tri(reaching)));
        assert!(cone.misses_triangle(&card(0.2)));
    }

    #[test]
    fn clear_is_found_where_the_floor_alone_is_below() {
        // Over a grid of receivers and lights, a floor without blockers is always clear.
        let g = TestShadows::new(&scene_with(vec![floor()]));
        let mut n = 0;
        for i in 0..7 {
            for j in 0..7 {
                let p = DVec3::new(-3.0 + i as f64, 0.0, -3.0 + j as f64 * 0.9);
                let centre = DVec3::new(0.5, 1.0 + 0.3 * j as f64, -0.4);
                if let Some(c) = ShadowCone::new(
                    p,
                    DVec3::Y,
                    crate::geometry::offset_scale(p),
                    centre,
                    0.3,
                    RayEnds::NearSide,
                ) {
                    n += 1;
                    assert!(g.cone_clear(&c, &|_| true), "p {p} light {centre}");
                }
            }
        }
        assert!(n > 30);
    }
}
