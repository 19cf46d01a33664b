//! The closure tree at one shading point (spec: "mix", "layer", "add", "multiply").
//!
//! Every combinator is linear in its inputs with coefficients that depend on `ωo` only —
//! `layer` scales its base by `1 − E_top(ωo)` (per channel, clamped to `[0, 1]`), `mix` by
//! `w`/`1 − w` (clamped to `[0, 1]`), `multiply` by its colour (negative/NaN channels → 0),
//! `add` by 1 — so the tree is a weighted sum `f = Σ cₖ ⊙ fₖ` over its closures. A top-down
//! pass computes the `cₖ` (accumulating, so a closure reachable twice counts twice), a
//! bottom-up pass the albedos `E` (for `layer`: `E_top + (1 − E_top) ⊙ E_base`).
//!
//! Sampling picks closure `k` with probability `pₖ ∝ mean(cₖ ⊙ Eₖ)` (its estimated
//! contribution), then samples it; the density of a direction is the mixture
//! `Σ pₖ pdfₖ` over the non-delta closures, and a non-delta sample's weight is the full
//! tree's `f cosθi` over that mixture density (one-sample MIS with the balance heuristic).
//!
//! `layer` by albedo scaling is not reciprocal (the base's factor depends on `ωo` only).
//! Children must have smaller ids than their parent; others are treated as absent.

use crate::closure::Leaf;
use crate::{Bsdf, Eval, LobeKind, MAX_NODES, Node, NodeId, Sample};
use glam::DVec3;

fn clamp01(v: DVec3) -> DVec3 {
    let f = |x: f64| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    DVec3::new(f(v.x), f(v.y), f(v.z))
}
fn nonneg(v: DVec3) -> DVec3 {
    let f = |x: f64| if x.is_finite() && x > 0.0 { x } else { 0.0 };
    DVec3::new(f(v.x), f(v.y), f(v.z))
}
fn mean(v: DVec3) -> f64 {
    (v.x + v.y + v.z) / 3.0
}

/// Most closures reachable from the root: each of `L` reachable closures needs its own path
/// of two-input combinators to the root, at least `L − 1` of them, so `2L − 1 ≤ MAX_NODES`.
const MAX_LEAVES: usize = MAX_NODES.div_ceil(2);

/// The tree resolved for `ωo`: its reachable closures in node order, each with its `cₖ` and
/// selection probability (nodes the root does not reach are left out; they contribute
/// nothing).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Prepared {
    pub leaves: [Option<Leaf>; MAX_LEAVES],
    /// `cₖ` per leaf (the coefficient of that closure's `f` in the root's).
    pub mult: [DVec3; MAX_LEAVES],
    /// Selection probability per leaf.
    pub prob: [f64; MAX_LEAVES],
    pub albedo: DVec3,
    pub total: f64,
    pub len: usize,
}

/// The children of node `i` (those with smaller ids; others are absent), in order.
fn children(n: &Option<Node>, i: usize) -> [Option<usize>; 2] {
    let child = |c: Option<NodeId>| c.map(|c| c.0 as usize).filter(|&c| c < i);
    match *n {
        None | Some(Node::Closure(_)) => [None, None],
        Some(Node::Layer { top, base }) => [child(Some(top)), child(base)],
        Some(Node::Mix { fg, bg, .. }) => [child(fg), child(bg)],
        Some(Node::Add { a, b }) => [child(a), child(b)],
        Some(Node::Multiply { a, .. }) => [child(Some(a)), None],
    }
}

impl Prepared {
    /// No closure (black); [`Prepared::fill`] resolves a tree into it.
    pub fn empty() -> Prepared {
        Prepared {
            leaves: [None; MAX_LEAVES],
            mult: [DVec3::ZERO; MAX_LEAVES],
            prob: [0.0; MAX_LEAVES],
            albedo: DVec3::ZERO,
            total: 0.0,
            len: 0,
        }
    }

    /// Resolves `b` into `self` (which must be [`Prepared::empty`]), in place: the leaves are
    /// written where they stay rather than moved there.
    pub fn fill(&mut self, b: &Bsdf) {
        let nodes = b.node_slice();
        let len = nodes.len();
        // Which nodes the root reaches (only their closures are prepared).
        let mut reach = [false; MAX_NODES];
        if len > 0 {
            reach[len - 1] = true;
        }
        for i in (0..len).rev() {
            if reach[i] {
                for c in children(&nodes[i], i).into_iter().flatten() {
                    reach[c] = true;
                }
            }
        }
        let leaves = &mut self.leaves;
        let mut leaf_albedo = [DVec3::ZERO; MAX_LEAVES];
        let mut leaf_node = [0usize; MAX_LEAVES];
        let mut n_leaves = 0;
        let mut alb = [DVec3::ZERO; MAX_NODES];
        let child = |c: Option<NodeId>, i: usize| c.map(|c| c.0 as usize).filter(|&c| c < i);
        let wo = b.wo_dir();
        for (i, n) in nodes.iter().enumerate() {
            let get = |c: Option<NodeId>| child(c, i).map(|c| alb[c]).unwrap_or(DVec3::ZERO);
            let Some(n) = n else { continue };
            if !reach[i] {
                continue;
            }
            alb[i] = match *n {
                Node::Closure(cl) => {
                    let leaf = if wo.is_finite() {
                        Leaf::new(&cl, wo, b.is_entering(), b.is_thin_walled())
                    } else {
                        None
                    };
                    match leaf {
                        Some((l, a)) if n_leaves < MAX_LEAVES => {
                            leaves[n_leaves] = Some(l);
                            leaf_albedo[n_leaves] = a;
                            leaf_node[n_leaves] = i;
                            n_leaves += 1;
                            a
                        }
                        _ => DVec3::ZERO,
                    }
                }
                Node::Layer { top, base } => {
                    let t = get(Some(top));
                    t + (DVec3::ONE - clamp01(t)) * get(base)
                }
                Node::Mix { fg, bg, mix } => {
                    let m = if mix.is_nan() {
                        0.0
                    } else {
                        mix.clamp(0.0, 1.0)
                    };
                    get(fg) * m + get(bg) * (1.0 - m)
                }
                Node::Add { a, b } => get(a) + get(b),
                Node::Multiply { a, weight } => get(Some(a)) * nonneg(weight),
            };
        }
        let mut node_mult = [DVec3::ZERO; MAX_NODES];
        if len > 0 {
            node_mult[len - 1] = DVec3::ONE;
        }
        for i in (0..len).rev() {
            let m = node_mult[i];
            if m == DVec3::ZERO {
                continue;
            }
            let mut add = |c: Option<NodeId>, f: DVec3| {
                if let Some(c) = child(c, i) {
                    node_mult[c] += m * f;
                }
            };
            let top_albedo = |t: NodeId| child(Some(t), i).map(|t| alb[t]).unwrap_or(DVec3::ZERO);
            match nodes[i] {
                None | Some(Node::Closure(_)) => {}
                Some(Node::Layer { top, base }) => {
                    add(Some(top), DVec3::ONE);
                    add(base, DVec3::ONE - clamp01(top_albedo(top)));
                }
                Some(Node::Mix { fg, bg, mix }) => {
                    let w = if mix.is_nan() {
                        0.0
                    } else {
                        mix.clamp(0.0, 1.0)
                    };
                    add(fg, DVec3::splat(w));
                    add(bg, DVec3::splat(1.0 - w));
                }
                Some(Node::Add { a, b }) => {
                    add(a, DVec3::ONE);
                    add(b, DVec3::ONE);
                }
                Some(Node::Multiply { a, weight }) => add(Some(a), nonneg(weight)),
            }
        }
        let mult = &mut self.mult;
        let prob = &mut self.prob;
        let mut total = 0.0;
        for k in 0..n_leaves {
            mult[k] = node_mult[leaf_node[k]];
            let c = mean(mult[k] * leaf_albedo[k]);
            if c.is_finite() && c > 0.0 {
                prob[k] = c;
                total += c;
            }
        }
        if total > 0.0 {
            for p in &mut prob[..n_leaves] {
                *p /= total;
            }
        }
        let albedo = if len > 0 {
            nonneg(alb[len - 1])
        } else {
            DVec3::ZERO
        };
        self.albedo = albedo;
        self.total = total;
        self.len = n_leaves;
    }

    pub fn eval(&self, wi: DVec3) -> Eval {
        let mut e = Eval::default();
        if !wi.is_finite() {
            return e;
        }
        for i in 0..self.len {
            let Some(l) = &self.leaves[i] else { continue };
            if self.prob[i] <= 0.0 || l.is_delta() {
                continue;
            }
            let v = self.mult[i] * l.eval(l.local(wi));
            match l.lobe_kind() {
                LobeKind::Diffuse => e.diffuse += v,
                _ => e.specular += v,
            }
        }
        e.diffuse = nonneg(e.diffuse);
        e.specular = nonneg(e.specular);
        e
    }

    pub fn pdf(&self, wi: DVec3) -> f64 {
        if !wi.is_finite() {
            return 0.0;
        }
        let mut p = 0.0;
        for i in 0..self.len {
            let Some(l) = &self.leaves[i] else { continue };
            if self.prob[i] <= 0.0 || l.is_delta() {
                continue;
            }
            p += self.prob[i] * l.pdf(l.local(wi));
        }
        if p.is_finite() { p.max(0.0) } else { 0.0 }
    }

    pub fn sample(&self, ng: DVec3, u_lobe: f64, u: [f64; 2]) -> Option<Sample> {
        if !(self.total > 0.0) {
            return None;
        }
        let u_lobe = if u_lobe.is_nan() {
            0.0
        } else {
            u_lobe.clamp(0.0, 1.0 - f64::EPSILON)
        };
        let mut acc = 0.0;
        let mut pick = None;
        for i in 0..self.len {
            let p = self.prob[i];
            if p <= 0.0 {
                continue;
            }
            if u_lobe < acc + p || pick.is_none() {
                pick = Some((i, ((u_lobe - acc) / p).clamp(0.0, 1.0 - f64::EPSILON)));
                if u_lobe < acc + p {
                    break;
                }
            }
            acc += p;
        }
        let (i, u_sel) = pick?;
        let l = self.leaves[i].as_ref()?;
        let (wl, delta) = l.sample(u_sel, u)?;
        let wi = l.world(wl).normalize();
        if !wi.is_finite() {
            return None;
        }
        let transmitted = wi.dot(ng) < 0.0;
        if let Some((w, q)) = delta {
            let pdf = self.prob[i] * q;
            let weight = nonneg(self.mult[i] * w / self.prob[i]);
            if !(pdf > 0.0) {
                return None;
            }
            return Some(Sample {
                wi,
                weight,
                pdf,
                kind: LobeKind::Specular,
                transmitted,
            });
        }
        let pdf = self.pdf(wi);
        if !(pdf > 0.0) {
            return None;
        }
        let e = self.eval(wi);
        let weight = nonneg((e.diffuse + e.specular) / pdf);
        Some(Sample {
            wi,
            weight,
            pdf,
            kind: l.lobe_kind(),
            transmitted,
        })
    }
}
