//! Regions of space for BVH queries ([`Region`]): the conservative node and triangle tests a
//! group of rays shares, and the CWBVH traversal that descends only where a region reaches.

use glam::{DVec3, UVec2, Vec3A, Vec4};

/// A region of space holding a group of rays (a light's shadow rays from a patch of surface,
/// a tile's camera rays), which BVH queries descend conservatively: what it drops meets none
/// of the rays. The visibility accelerations (`crate::visibility`) make such regions.
pub trait Region {
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

/// The quantized boxes of children `4·half … 4·half + 3` of a CWBVH node, one lane each:
/// `(min, max)` per axis, in the node's frame (`x = origin + e ⊙ q`, `q ∈ [0, 255]³`).
#[inline]
pub(crate) fn child_boxes(
    node: &obvhs::cwbvh::node::CwBvhNode,
    half: usize,
) -> ([Vec4; 3], [Vec4; 3]) {
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
pub(crate) fn farthest_along((lo, hi): &([Vec4; 3], [Vec4; 3]), n: [f32; 3]) -> Vec4 {
    let side = |k: usize| if n[k] >= 0.0 { hi[k] } else { lo[k] } * n[k];
    side(0) + side(1) + side(2)
}

/// The plane `n·x = d` (world space) in the quantized frame of `node` (`x = origin + e ⊙ q`):
/// the normal scaled by the extent, and its value at the node's origin less `d`.
#[inline(always)]
pub(crate) fn in_node_frame(
    node: &obvhs::cwbvh::node::CwBvhNode,
    n: DVec3,
    d: f64,
) -> ([f32; 3], f32) {
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
pub(crate) fn above_all<const N: usize>(
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
pub(crate) fn outside_a_plane(
    planes: &[(DVec3, f64)],
    margin: f64,
    t: &obvhs::triangle::Triangle,
) -> bool {
    let v = [t.v0, t.v1, t.v2].map(|x: Vec3A| x.as_dvec3());
    planes
        .iter()
        .any(|&(n, d)| v.iter().all(|&x| n.dot(x) - d < -margin))
}

/// The CWBVH hit mask (in the traversal order of `oct_inv4`) of the node's non-empty children
/// whose bit is set in `keep` and that `drop` does not drop.
#[inline]
pub(crate) fn child_mask(
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
/// searches of triangles (`Blas::region_triangles`) and of instance boxes
/// (`Instances::may_block`).
#[inline(always)]
pub(crate) fn region_search(
    bvh: &obvhs::cwbvh::CwBvh,
    region: &impl Region,
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
