//! The scene's triangles in `obvhs` compressed-wide BVHs (CWBVH): closest-hit queries for
//! camera and BSDF rays, any-hit queries for shadow rays; and the analytic area lights in a
//! BVH of their own (`geometry/lights.rs`), so that a ray finds the light it hits.
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
//! Shadow rays ([`Geometry::occluded`], [`Geometry::first_occluder`]) query a second BVH when
//! some world meshes are flat cards tiling a convex polygon (`geometry/planar.rs`): those
//! meshes as their outline's fan triangles, which block exactly what their triangles block.
//!
//! Where a region holds every ray of a group and meets few triangles, the group tests those
//! alone: a tile's camera rays ([`RayFrustum`], [`Geometry::triangles_in`]) and the shadow rays
//! of a patch of surface ([`Geometry::blockers_in`]); same answers as the BVH.
//!
//! Back faces: a triangle of a mesh that is not `doubleSided` is invisible from behind to
//! closest-hit queries (UsdGeom: single-sided geometry may be back-face culled), but it
//! occludes shadow rays from both sides, so a one-sided wall still casts a shadow.

mod blas;
pub(crate) mod cone;
mod frustum;
mod instances;
mod lights;
mod planar;
pub(crate) mod pyramid;

use crate::light::{Light, LightHit};
use blas::Blas;
pub use cone::{ConeSearch, INSTANCED, RayEnds, ShadowCone};
pub use frustum::RayFrustum;
use glam::{DVec2, DVec3, UVec2, Vec3A, Vec4};
use instances::Instances;
pub(crate) use instances::drawable_transform;
pub use lights::LINEAR_LIGHTS;
use lights::LightShapes;
use lux_usd::Scene;
use obvhs::ray::{Ray, RayHit};
pub use pyramid::ShadowPyramid;

/// Largest triangle count the renderer stores (indices are `u32`): world triangles plus each
/// instanced prototype's triangles once.
pub const MAX_TRIANGLES: usize = 1 << 28;

/// A region holding every shadow ray of a light from a receiver ([`ShadowCone`],
/// [`ShadowPyramid`]), tested conservatively against the BVH: what it drops meets none of the
/// rays.
pub trait ShadowRegion {
    /// A direction into the region (the BVH's traversal order).
    fn axis(&self) -> DVec3;
    /// True when the triangle cannot stop a ray of the region.
    fn culls_triangle(&self, t: &obvhs::triangle::Triangle) -> bool;
    /// The CWBVH hit mask of the node's children the region may reach (what
    /// `CwBvhNode::intersect_ray` returns for a ray), in the traversal order of `oct_inv4`.
    fn node_mask(&self, node: &obvhs::cwbvh::node::CwBvhNode, oct_inv4: u32) -> u32;
    /// The region in the space of an instance's prototype, `x' = Qᵀ·(x − t) / s` (`qt` = Qᵀ,
    /// `Q` orthogonal, `s > 0`: a similarity), its margin grown by `extra` (prototype units):
    /// distances scale by `1/s`, directions turn by `Qᵀ`, angles stay.
    fn to_prototype(&self, qt: &glam::DMat3, t: DVec3, s: f64, extra: f64) -> Self
    where
        Self: Sized;
}

/// The least and most ray-origin offset ([`offset_scale`]) over the points within `spread` of
/// `q` (a patch of [`ShadowCone::patch`] or [`ShadowPyramid::patch`]); `None` for a negative or
/// non-finite spread.
fn patch_offsets(q: DVec3, spread: f64) -> Option<[f64; 2]> {
    if !(spread >= 0.0 && spread.is_finite()) {
        return None;
    }
    let m = q.abs().max_element();
    Some([
        offset_scale(DVec3::splat((m - spread).max(0.0))),
        offset_scale(DVec3::splat(m + spread)),
    ])
}

/// The quantized boxes of children `4·half … 4·half + 3` of a CWBVH node, one lane each:
/// `(min, max)` per axis, in the node's frame (`x = origin + e ⊙ q`, `q ∈ [0, 255]³`).
#[inline]
fn child_boxes(node: &obvhs::cwbvh::node::CwBvhNode, half: usize) -> ([Vec4; 3], [Vec4; 3]) {
    let lane = |b: &[u8; 8]| {
        let o = 4 * half;
        Vec4::new(
            b[o] as f32,
            b[o + 1] as f32,
            b[o + 2] as f32,
            b[o + 3] as f32,
        )
    };
    (
        [
            lane(&node.child_min_x),
            lane(&node.child_min_y),
            lane(&node.child_min_z),
        ],
        [
            lane(&node.child_max_x),
            lane(&node.child_max_y),
            lane(&node.child_max_z),
        ],
    )
}

/// The largest `n·q` over each of four quantized boxes (`n` in the node's frame): per axis
/// the max or min corner by `n`'s sign.
#[inline]
fn farthest_along((lo, hi): &([Vec4; 3], [Vec4; 3]), n: [f32; 3]) -> Vec4 {
    let side = |k: usize| if n[k] >= 0.0 { hi[k] } else { lo[k] } * n[k];
    side(0) + side(1) + side(2)
}

/// The plane `n·x = d` (world space) in the quantized frame of `node` (`x = origin + e ⊙ q`):
/// the normal scaled by the extent, and its value at the node's origin less `d`.
#[inline(always)]
fn in_node_frame(node: &obvhs::cwbvh::node::CwBvhNode, n: DVec3, d: f64) -> ([f32; 3], f32) {
    let n = n.as_vec3a();
    (
        (n * node.compute_extent()).to_array(),
        n.dot(Vec3A::from(node.p)) - d as f32,
    )
}

/// Bits (child order) of the children of `node` that lie wholly below none of the `tests`:
/// each a plane in the node's frame ([`in_node_frame`]) and the value every point of a box
/// must stay under, by the box's corner farthest along the normal, to be below it.
#[inline(always)]
fn above_all<const N: usize>(
    node: &obvhs::cwbvh::node::CwBvhNode,
    tests: &[(([f32; 3], f32), f32); N],
) -> u32 {
    let mut keep = 0u32;
    for half in 0..2 {
        let boxes = child_boxes(node, half);
        let mut out = glam::BVec4A::splat(false);
        for &((n, d0), below) in tests {
            out |= (farthest_along(&boxes, n) + Vec4::splat(d0)).cmplt(Vec4::splat(below));
        }
        keep |= ((!out.bitmask()) & 0xf) << (4 * half);
    }
    keep
}

/// Whether the triangle lies wholly outside one of the half-spaces `n·x ≥ d` of `planes` by
/// more than `margin` (in `f64`, from its stored `f32` corners).
#[inline]
fn outside_a_plane(planes: &[(DVec3, f64)], margin: f64, t: &obvhs::triangle::Triangle) -> bool {
    let v = [t.v0, t.v1, t.v2].map(|x: Vec3A| x.as_dvec3());
    planes
        .iter()
        .any(|&(n, d)| v.iter().all(|&x| n.dot(x) - d < -margin))
}

/// The CWBVH hit mask (in the traversal order of `oct_inv4`) of the node's non-empty children
/// whose bit is set in `keep` and that `drop` does not drop.
#[inline]
fn child_mask(
    node: &obvhs::cwbvh::node::CwBvhNode,
    oct_inv4: u32,
    keep: u32,
    drop: impl Fn(usize) -> bool,
) -> u32 {
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut mask = 0;
    for child in 0..8 {
        if keep & (1 << child) != 0 && !node.is_child_empty(child) && !drop(child) {
            mask |= obvhs::cwbvh::node::extract_byte64(child_bits8, child)
                << obvhs::cwbvh::node::extract_byte64(bit_index8, child);
        }
    }
    mask
}

/// The first primitive of `bvh` in a leaf that `region` may reach (its node test) and that
/// `keep` accepts, `None` when there is none: the traversal shared by the shadow-region
/// searches of triangles ([`Blas::cone_blocker`]) and of instance boxes
/// (`Instances::may_block`).
#[inline(always)]
fn region_search(
    bvh: &obvhs::cwbvh::CwBvh,
    region: &impl ShadowRegion,
    mut keep: impl FnMut(usize) -> bool,
) -> Option<u32> {
    let mut state = bvh.new_traversal(region.axis().as_vec3a());
    let mut node;
    let mut found = None;
    'outer: {
        obvhs::traverse!(bvh, node, state, region.node_mask(node, state.oct_inv4), {
            let id = state.primitive_id as usize;
            if keep(id) {
                found = Some(id as u32);
                break 'outer;
            }
        });
    }
    found
}

/// A few triangles of the BVH shadow rays query ([`Geometry::blockers_in`]): all that can stop
/// a shadow ray inside some region.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FewTriangles {
    len: u8,
    ids: [u32; FewTriangles::CAP],
}

impl FewTriangles {
    /// Most triangles held: a shadow ray testing more costs about what the BVH's traversal does.
    pub const CAP: usize = 6;

    /// The triangles (indices into the shadow rays' BVH).
    pub fn ids(&self) -> &[u32] {
        &self.ids[..self.len as usize]
    }
}

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
    /// What shadow rays test instead of `world` when planar tilings of a convex polygon
    /// (`geometry/planar.rs`) make most of it: those meshes as their outlines' fan triangles,
    /// the others as in `world` ([`Geometry::shadow_blas`]). `None` otherwise.
    shadow: Option<Blas>,
    /// Per mesh, with `shadow`: the convex outline whose fan stands for it there (corners
    /// rounded as the BVH's triangles are), when it has at most
    /// [`lux_irradiance::hidden::MAX_CORNERS`] corners ([`Geometry::blocker_card`]).
    cards: Vec<Option<Card>>,
    /// Instanced prototypes and their placements.
    instances: Option<Instances>,
    /// The analytic area lights.
    lights: LightShapes,
}

/// A planar mesh's convex outline in the shadow BVH (`geometry/planar.rs`): its corners in
/// order, as its fan triangles hold them.
#[derive(Clone, Copy, Debug)]
struct Card {
    len: u8,
    corners: [DVec3; lux_irradiance::hidden::MAX_CORNERS],
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
        Geometry::with_lights(scene, &[])
    }

    /// [`Geometry::new`] with the analytic area lights of `lights` (rect, disk, sphere,
    /// cylinder) indexed for [`Geometry::closest_light`] and [`Geometry::lights_crossed`],
    /// which must then be given the same slice.
    pub fn with_lights(scene: &Scene, lights: &[Light]) -> Geometry {
        let mut stored = 0;
        let world_meshes =
            || (0..scene.meshes.len()).filter(|&i| scene.meshes[i].prototype.is_none());
        let world = Blas::build(scene, world_meshes(), &mut stored);
        // (not when the world stopped at MAX_TRIANGLES: shadow rays would see what it left out)
        let mut cards = vec![None; scene.meshes.len()];
        let shadow = world
            .as_ref()
            .filter(|_| stored < MAX_TRIANGLES)
            .and_then(|w| Self::shadow_blas(scene, world_meshes(), w.len(), &mut cards));
        if shadow.is_none() {
            cards.clear();
        }
        let instances = Instances::build(scene, &mut stored);
        Geometry {
            shadow,
            cards,
            world,
            instances,
            lights: LightShapes::new(lights),
        }
    }

    /// The shadow BVH of [`Geometry::shadow`]: the meshes `meshes` (the world BVH's, of
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
                        let prim = blas::PrimRef {
                            mesh: mi as u32,
                            tri: k as u32,
                            double_sided: m.double_sided,
                        };
                        (prim, t)
                    }));
                }
                None => items.extend(blas::mesh_triangles(scene, mi)),
            }
        }
        // (its own count: these triangles stand for the world's, already counted)
        (replaced && 4 * items.len() <= world_len)
            .then(|| Blas::from_triangles(items.into_iter(), &mut 0))
            .flatten()
    }

    /// The convex outline (its mesh, its corners in order) whose fan holds the triangle `id` of
    /// the BVH shadow rays test ([`Geometry::blocker_vertices`]), when that triangle stands
    /// for a planar mesh there (`geometry/planar.rs`).
    pub fn blocker_card(&self, id: u32) -> Option<(u32, &[DVec3])> {
        let mesh = self.shadow.as_ref()?.prims.get(id as usize)?.mesh;
        let card = self.cards.get(mesh as usize)?.as_ref()?;
        Some((mesh, &card.corners[..card.len as usize]))
    }

    /// What shadow rays test: the shadow BVH, else the world's.
    #[inline]
    fn blockers(&self) -> Option<&Blas> {
        self.shadow.as_ref().or(self.world.as_ref())
    }

    /// Number of analytic area lights indexed.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }

    /// The closest analytic light on `origin + t·dir`, `t ∈ (tmin, tmax)`, among those
    /// `visible` keeps (a camera ray: the camera-visible ones), the lower index on a tie.
    /// `lights` is the slice the geometry was built with.
    #[inline]
    pub fn closest_light(
        &self,
        lights: &[Light],
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
        visible: impl Fn(&Light) -> bool,
    ) -> Option<(usize, LightHit)> {
        self.lights
            .closest(lights, origin, dir, tmin, tmax, visible)
    }

    /// True when no ray inside `frustum` can meet an analytic light that `visible` keeps (what
    /// [`Geometry::closest_light`] finds): each one's box lies wholly outside it
    /// ([`RayFrustum::misses_box`]); false (unsure) with more than [`LINEAR_LIGHTS`] of them.
    /// `lights` is the slice the geometry was built with.
    pub fn no_light_in(
        &self,
        lights: &[Light],
        frustum: &RayFrustum,
        visible: impl Fn(&Light) -> bool,
    ) -> bool {
        self.lights.none_in(lights, frustum, visible)
    }

    /// Calls `f` with every analytic light crossing `origin + t·dir`, `t ∈ (tmin, tmax)`, and
    /// its hit, by light index (lights do not occlude one another). `lights` is the slice the
    /// geometry was built with.
    #[inline]
    pub fn lights_crossed(
        &self,
        lights: &[Light],
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
        f: impl FnMut(usize, LightHit),
    ) {
        self.lights.crossed(lights, origin, dir, tmin, tmax, f)
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
            + self.shadow.as_ref().map_or(0, Blas::heap_bytes)
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

    /// The world triangles a ray inside `frustum` may hit (their BVH indices, in the order
    /// the BVH's traversal along its axis meets them), for [`Geometry::intersect_among`]; `None`
    /// when there are more than `cap`, or the scene has instances (their rays take the BVH).
    pub fn triangles_in(&self, frustum: &RayFrustum, cap: usize) -> Option<Box<[u32]>> {
        if self.instances.is_some() {
            return None;
        }
        let world = self.world.as_ref()?;
        let mut ids = Vec::new();
        let over = world.region_triangles(frustum, &|_| true, |id| {
            ids.push(id);
            ids.len() > cap
        });
        over.is_none().then(|| ids.into_boxed_slice())
    }

    /// [`Geometry::intersect`] of a ray among the world triangles `ids` alone: the same hit
    /// when they hold every triangle the ray can reach ([`Geometry::triangles_in`] of a frustum
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
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        let world = self.world.as_ref()?;
        let mut hit = RayHit::none();
        world
            .closest_among(ids, ray, &mut hit)
            .then(|| Self::world_hit(world, scene, hit, origin, dir))
    }

    /// The exact hit of the world BVH's traversal hit `hit`.
    #[inline]
    fn world_hit(world: &Blas, scene: &Scene, hit: RayHit, origin: DVec3, dir: DVec3) -> Hit {
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
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        if let Some(inst) = &self.instances {
            return self.first_occluder_instanced(inst, ray, origin, dir);
        }
        let mut hit = RayHit::none();
        (self.blockers()?.nearest(ray, &mut hit)).then_some(hit.t as f64)
    }

    /// [`Geometry::first_occluder`] with instances.
    #[inline(never)]
    fn first_occluder_instanced(
        &self,
        inst: &Instances,
        ray: Ray,
        origin: DVec3,
        dir: DVec3,
    ) -> Option<f64> {
        let mut hit = RayHit::none();
        let found = self.blockers().is_some_and(|w| w.nearest(ray, &mut hit));
        let mut r = ray;
        if found {
            r.tmax = hit.t;
        }
        match inst.closest(origin, dir, r, false) {
            Some(h) => Some(h.t as f64),
            None => found.then_some(hit.t as f64),
        }
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
        let ray = Self::ray(origin, dir, tmin, tmax)?;
        let mut hit = RayHit::none();
        let world = self.blockers().filter(|w| w.nearest(ray, &mut hit));
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

    /// True when no triangle of a mesh that `casts` (a `Scene::meshes` index: what a light's
    /// shadow linking keeps) can stop a shadow ray inside `cone` ([`ShadowCone`]) — searched in
    /// the BVH shadow rays test (a planar tiling as its outline: fewer, larger triangles, which
    /// a cone drops by its exact triangle test where their bounding spheres reach it) — and no
    /// instance's world box meets it (instances are not searched inside, and are taken to cast
    /// every light's shadow); false when unsure.
    pub fn cone_clear(&self, cone: &impl ShadowRegion, casts: &impl Fn(usize) -> bool) -> bool {
        self.blockers().is_none_or(|w| w.cone_clear(cone, casts))
            && self.instances.as_ref().is_none_or(|i| !i.may_block(cone))
    }

    /// What can stop the shadow rays inside `cone` ([`ShadowCone`]) among the triangles of
    /// meshes that `casts`: nothing, or the first triangle of the shadow rays' BVH found that
    /// `cone` does not rule out, else [`INSTANCED`] when an instance's world box meets it
    /// ([`ConeSearch`]).
    pub fn cone_search(
        &self,
        cone: &impl ShadowRegion,
        casts: &impl Fn(usize) -> bool,
    ) -> ConeSearch {
        match self.blockers().and_then(|w| w.cone_blocker(cone, casts)) {
            Some(id) => ConeSearch::Blocked(id),
            None if self.instances.as_ref().is_some_and(|i| i.may_block(cone)) => {
                ConeSearch::Blocked(INSTANCED)
            }
            None => ConeSearch::Clear,
        }
    }

    /// Whether `cone` rules out the blocker `id` of a [`ConeSearch::Blocked`]: a triangle of
    /// the shadow rays' BVH, or for [`INSTANCED`] every instance's box.
    #[inline]
    pub fn culls(&self, cone: &impl ShadowRegion, id: u32) -> bool {
        if id == INSTANCED {
            return self.instances.as_ref().is_none_or(|i| !i.may_block(cone));
        }
        self.blockers().is_none_or(|w| w.culls(cone, id))
    }

    /// The vertices of the triangle `id` of a [`FewTriangles`] ([`Geometry::blockers_in`]), as
    /// shadow rays meet it.
    #[inline]
    pub fn blocker_vertices(&self, id: u32) -> Option<[DVec3; 3]> {
        self.blockers()?.vertices(id)
    }

    /// Every triangle of a mesh that `casts` which can stop a shadow ray inside `region`, among
    /// those shadow rays query (the outlines of flat cards where built: `geometry/planar.rs`), for
    /// [`Geometry::occluded_among`]; `None` when more than [`FewTriangles::CAP`], or with
    /// instances.
    pub fn blockers_in(
        &self,
        region: &impl ShadowRegion,
        casts: &impl Fn(usize) -> bool,
    ) -> Option<FewTriangles> {
        if self.instances.is_some() {
            return None;
        }
        let b = self.blockers()?;
        let mut few = FewTriangles {
            len: 0,
            ids: [0; FewTriangles::CAP],
        };
        let over = b.region_triangles(region, casts, |id| {
            if few.len as usize == FewTriangles::CAP {
                return true;
            }
            few.ids[few.len as usize] = id;
            few.len += 1;
            false
        });
        over.is_none().then_some(few)
    }

    /// [`Geometry::occluded`] among the triangles `few` alone: the same answer for a ray inside
    /// the region they were found for ([`Geometry::blockers_in`]), when it was searched for
    /// every mesh that can block it.
    #[inline]
    pub fn occluded_among(
        &self,
        few: &FewTriangles,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> bool {
        let Some(ray) = Self::ray(origin, dir, tmin, tmax) else {
            return false;
        };
        self.blockers().is_some_and(|b| b.any_among(few.ids(), ray))
    }

    /// True when any triangle (either side) lies on `origin + t·dir`, `t ∈ (tmin, tmax)`.
    pub fn occluded(&self, origin: DVec3, dir: DVec3, tmin: f64, tmax: f64) -> bool {
        let Some(ray) = Self::ray(origin, dir, tmin, tmax) else {
            return false;
        };
        if let Some(inst) = &self.instances {
            return self.occluded_instanced(inst, ray, origin, dir);
        }
        self.blockers().is_some_and(|w| w.any(ray))
    }

    /// [`Geometry::occluded`] with instances: the world BVH, then the instances.
    #[inline(never)]
    fn occluded_instanced(&self, inst: &Instances, ray: Ray, origin: DVec3, dir: DVec3) -> bool {
        self.blockers().is_some_and(|w| w.any(ray)) || inst.any(origin, dir, ray)
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
        let (world, shadow) = (g.world.as_ref().unwrap(), g.shadow.as_ref().unwrap());
        assert_eq!(world.len(), 162 + 162 + 72);
        assert_eq!(shadow.len(), 2 + 2 + 72);
        // Each outline triangle names its card: the rectangle's four corners in order (as the
        // BVH rounds them); the strip's own triangles name none.
        let mut cards = [0usize; 3];
        for id in 0..shadow.len() as u32 {
            let tri = g.blocker_vertices(id).unwrap();
            match g.blocker_card(id) {
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
        assert!(std::ptr::eq(g.blockers().unwrap(), shadow));
        let o = DVec3::new(0.1, 3.0, 0.07);
        assert_eq!(
            g.first_occluder_at(o, DVec3::NEG_Y, 0.0, 10.0)
                .map(|h| h.mesh),
            Some(1)
        );
        assert!(g.occluded(o, DVec3::NEG_Y, 0.0, 10.0));
        // No shadow BVH without planar tilings, nor where they are a small part (the card and
        // three strips: 2 + 216 of 378 triangles, more than a quarter).
        let g = Geometry::new(&scene_with(vec![scene.meshes[2].clone()]));
        assert!(
            g.shadow.is_none() && std::ptr::eq(g.blockers().unwrap(), g.world.as_ref().unwrap())
        );
        let mostly_strips = [1, 2, 2, 2].map(|i| scene.meshes[i].clone()).to_vec();
        assert!(Geometry::new(&scene_with(mostly_strips)).shadow.is_none());
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
            scene_with(vec![cone::tests::floor(), card]),
        ] {
            let g = Geometry::new(&scene);
            let region = |x: f64| {
                let p = DVec3::new(x, 0.0, 0.1);
                let offset = offset_scale(p);
                let light = DVec3::new(x, 1.5, 0.1);
                let corners = pyramid::tests::rect(light, -DVec3::Y, DVec3::X, (0.2, 0.2));
                (
                    ShadowCone::new(p, DVec3::Y, offset, light, 0.2, RayEnds::NearSide).unwrap(),
                    ShadowPyramid::new(p, DVec3::Y, offset, &corners).unwrap(),
                )
            };
            let (cone, pyramid) = region(0.0);
            assert!(matches!(
                g.cone_search(&cone, &|_| true),
                ConeSearch::Blocked(_)
            ));
            assert!(matches!(
                g.cone_search(&pyramid, &|_| true),
                ConeSearch::Blocked(_)
            ));
            let (cone, pyramid) = region(3.0);
            assert_eq!(g.cone_search(&cone, &|_| true), ConeSearch::Clear);
            assert_eq!(g.cone_search(&pyramid, &|_| true), ConeSearch::Clear);
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
            let mut scene = scene_with(vec![cone::tests::floor(), proto.clone()]);
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
            let inst = g.instances.as_ref().unwrap();
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
                let corners = pyramid::tests::rect(light, -DVec3::Y, DVec3::X, (radius, radius));
                let pyramid = ShadowPyramid::new(p, DVec3::Y, offset, &corners).unwrap();
                let boxed = region_search(&inst.tlas, &cone, |_| true).is_some();
                for (free, rays) in [
                    (
                        !inst.may_block(&cone),
                        cone::tests::segments(p, light, radius, 400, false),
                    ),
                    (
                        !inst.may_block(&pyramid),
                        pyramid::tests::segments(p, &corners, 400),
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
