//! A light BVH for many-light selection (Conty Estevez & Kulla 2018, "Importance sampling of
//! many lights with adaptive tree splitting"; pbrt-v4 §12.6.3): a binary tree over light bounds,
//! traversed stochastically with child probabilities proportional to [`LightBounds::importance`].

use crate::bounds::LightBounds;
use crate::error::{MAX_ENTRIES, SampleError};
use crate::not_positive;
use crate::sample::Reference;

#[derive(Clone, Debug)]
struct Node {
    bounds: LightBounds,
    /// Leaf: light index. Interior: index of the second child (the first is `self + 1`).
    payload: u32,
    leaf: bool,
}

/// A light BVH plus the infinite lights (distant, dome), which are chosen uniformly with
/// probability n_inf/(n_inf + 1) (the tree counting as one more candidate), as in pbrt-v4.
#[derive(Clone, Debug)]
pub struct LightBvh {
    nodes: Vec<Node>,
    /// Per light: (bit trail from the root, depth) or `None` if it is infinite or powerless.
    trails: Vec<Option<(u64, u8)>>,
    infinite: Vec<usize>,
}

impl LightBvh {
    /// Builds the tree. `bounds[i]` is `None` for an infinite light. Lights with zero power are
    /// never selected. The split is at the median centroid along the widest centroid axis.
    pub fn new(bounds: &[Option<LightBounds>]) -> Result<Self, SampleError> {
        if bounds.len() > MAX_ENTRIES {
            return Err(SampleError::BadSize {
                field: "bounds",
                expected: format!("at most {MAX_ENTRIES} lights"),
                got: bounds.len(),
            });
        }
        let mut infinite = Vec::new();
        let mut finite = Vec::new();
        for (i, b) in bounds.iter().enumerate() {
            match b {
                None => infinite.push(i),
                Some(b) if b.phi > 0.0 => finite.push(i),
                Some(_) => {}
            }
        }
        let mut bvh = Self {
            nodes: Vec::new(),
            trails: vec![None; bounds.len()],
            infinite,
        };
        if finite.is_empty() && bvh.infinite.is_empty() {
            return Err(SampleError::AllZero("light powers"));
        }
        if !finite.is_empty() {
            bvh.build(bounds, &mut finite, 0, 0);
        }
        Ok(bvh)
    }

    fn build(
        &mut self,
        all: &[Option<LightBounds>],
        ids: &mut [usize],
        trail: u64,
        depth: u8,
    ) -> LightBounds {
        let get = |i: usize| all[i].expect("finite light");
        if ids.len() == 1 {
            let b = get(ids[0]);
            self.nodes.push(Node {
                bounds: b,
                payload: ids[0] as u32,
                leaf: true,
            });
            self.trails[ids[0]] = Some((trail, depth));
            return b;
        }
        let (mut lo, mut hi) = (get(ids[0]).centroid(), get(ids[0]).centroid());
        for &i in ids.iter() {
            let c = get(i).centroid();
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = ids.len() / 2;
        ids.select_nth_unstable_by(mid, |&a, &b| {
            get(a).centroid()[axis].total_cmp(&get(b).centroid()[axis])
        });
        let me = self.nodes.len();
        self.nodes.push(Node {
            bounds: get(ids[0]),
            payload: 0,
            leaf: false,
        });
        let (left, right) = ids.split_at_mut(mid);
        // Depth ≤ 29 for ≤ 2²⁸ lights with median splits, so 64 trail bits suffice.
        let bl = self.build(all, left, trail, depth + 1);
        let second = self.nodes.len();
        let br = self.build(all, right, trail | (1u64 << depth), depth + 1);
        self.nodes[me].payload = second as u32;
        let b = bl.union(&br);
        self.nodes[me].bounds = b;
        b
    }

    #[inline]
    fn p_infinite(&self) -> f64 {
        let ni = self.infinite.len() as f64;
        let tree = if self.nodes.is_empty() { 0.0 } else { 1.0 };
        ni / (ni + tree)
    }

    /// Chooses a light for `r` with `u ∈ [0,1)`; returns `(light index, probability)`, or
    /// `None` when no light can contribute.
    #[inline]
    pub fn sample(&self, r: &Reference, u: f64) -> Option<(usize, f64)> {
        let pinf = self.p_infinite();
        let mut u = u;
        if u < pinf {
            let n = self.infinite.len();
            let k = ((u / pinf * n as f64) as usize).min(n - 1);
            return Some((self.infinite[k], pinf / n as f64));
        }
        if self.nodes.is_empty() {
            return None;
        }
        u = ((u - pinf) / (1.0 - pinf)).min(1.0 - f64::EPSILON);
        let mut pmf = 1.0 - pinf;
        let mut node = 0usize;
        loop {
            let nd = &self.nodes[node];
            if nd.leaf {
                if node == 0 && not_positive(nd.bounds.importance(r.p, r.n)) {
                    return None;
                }
                return Some((nd.payload as usize, pmf));
            }
            let (c0, c1) = (node + 1, nd.payload as usize);
            let i0 = self.nodes[c0].bounds.importance(r.p, r.n);
            let i1 = self.nodes[c1].bounds.importance(r.p, r.n);
            if not_positive(i0 + i1) {
                return None;
            }
            let p0 = i0 / (i0 + i1);
            if u < p0 {
                u = (u / p0).min(1.0 - f64::EPSILON);
                pmf *= p0;
                node = c0;
            } else {
                u = ((u - p0) / (1.0 - p0)).min(1.0 - f64::EPSILON);
                pmf *= 1.0 - p0;
                node = c1;
            }
        }
    }

    /// [`Self::sample`] for each of the numbers `us` at one reference point, in one descent:
    /// `out[j]` is what `sample(r, us[j])` returns, bit for bit, but a node's children are
    /// weighed once for all the numbers that reach it (k choices at a shading point share the
    /// top of the tree). `out` must be as long as `us`.
    pub fn sample_each(&self, r: &Reference, us: &[f64], out: &mut [Option<(usize, f64)>]) {
        assert_eq!(us.len(), out.len(), "one answer per number");
        let pinf = self.p_infinite();
        // The numbers that go down the tree, sorted (each a descent of its own: the order only
        // keeps the ones reaching a node contiguous), with their slot in `out`; 16 at a time,
        // on the stack.
        let mut buf = [(0.0f64, 0usize); 16];
        for (c, chunk) in us.chunks(buf.len()).enumerate() {
            let mut n_down = 0;
            for (i, &u) in chunk.iter().enumerate() {
                let j = c * buf.len() + i;
                if u < pinf {
                    let n = self.infinite.len();
                    let k = ((u / pinf * n as f64) as usize).min(n - 1);
                    out[j] = Some((self.infinite[k], pinf / n as f64));
                } else if self.nodes.is_empty() {
                    out[j] = None;
                } else {
                    buf[n_down] = (((u - pinf) / (1.0 - pinf)).min(1.0 - f64::EPSILON), j);
                    n_down += 1;
                }
            }
            let down = &mut buf[..n_down];
            if !down.is_empty() {
                down.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                self.descend(r, 0, 1.0 - pinf, down, out);
            }
        }
    }

    /// The descent of [`Self::sample_each`] below `node`, reached with probability `pmf` by the
    /// sorted numbers `down`, rescaled to \[0, 1) at this node.
    fn descend(
        &self,
        r: &Reference,
        node: usize,
        pmf: f64,
        down: &mut [(f64, usize)],
        out: &mut [Option<(usize, f64)>],
    ) {
        let nd = &self.nodes[node];
        if nd.leaf {
            let hit = !(node == 0 && not_positive(nd.bounds.importance(r.p, r.n)));
            for &(_, j) in down.iter() {
                out[j] = hit.then_some((nd.payload as usize, pmf));
            }
            return;
        }
        let (c0, c1) = (node + 1, nd.payload as usize);
        let i0 = self.nodes[c0].bounds.importance(r.p, r.n);
        let i1 = self.nodes[c1].bounds.importance(r.p, r.n);
        if not_positive(i0 + i1) {
            for &(_, j) in down.iter() {
                out[j] = None;
            }
            return;
        }
        let p0 = i0 / (i0 + i1);
        // (sorted: those below p0 come first, and each side stays sorted once rescaled)
        let split = down.partition_point(|&(u, _)| u < p0);
        let (left, right) = down.split_at_mut(split);
        for (u, _) in left.iter_mut() {
            *u = (*u / p0).min(1.0 - f64::EPSILON);
        }
        for (u, _) in right.iter_mut() {
            *u = ((*u - p0) / (1.0 - p0)).min(1.0 - f64::EPSILON);
        }
        if !left.is_empty() {
            self.descend(r, c0, pmf * p0, left, out);
        }
        if !right.is_empty() {
            self.descend(r, c1, pmf * (1.0 - p0), right, out);
        }
    }

    /// Probability that [`Self::sample`] picks `light` for `r`.
    #[inline]
    pub fn pmf(&self, r: &Reference, light: usize) -> f64 {
        let pinf = self.p_infinite();
        if self.infinite.contains(&light) {
            return pinf / self.infinite.len() as f64;
        }
        let Some(Some((trail, depth))) = self.trails.get(light).copied() else {
            return 0.0;
        };
        let mut pmf = 1.0 - pinf;
        let mut node = 0usize;
        for level in 0..depth {
            let nd = &self.nodes[node];
            let (c0, c1) = (node + 1, nd.payload as usize);
            let i0 = self.nodes[c0].bounds.importance(r.p, r.n);
            let i1 = self.nodes[c1].bounds.importance(r.p, r.n);
            if not_positive(i0 + i1) {
                return 0.0;
            }
            if trail >> level & 1 == 0 {
                pmf *= i0 / (i0 + i1);
                node = c0;
            } else {
                pmf *= i1 / (i0 + i1);
                node = c1;
            }
        }
        if depth == 0 && not_positive(self.nodes[0].bounds.importance(r.p, r.n)) {
            return 0.0;
        }
        pmf
    }
}
