//! # lux-bsdf
//!
//! The physically based shading closures of MaterialX's PBS library (`MaterialX.PBRSpec.md`,
//! "BSDF Nodes" and "Combining Distribution Functions") as a small BSDF library: each closure
//! evaluated, sampled and given its density, and the combinators `layer` (albedo scaling,
//! `f = f_top + (1 − E_top(ωo))·f_base`), `mix`, `add` and `multiply` over them.
//!
//! A [`Bsdf`] is one closure tree at one shading point, built bottom-up with [`Bsdf::push`]
//! (each node may only refer to nodes pushed before it; the last pushed node is the root),
//! for one outgoing direction `wo` (towards the viewer). Directions are world-space unit
//! vectors; every closure carries its own shading [`Frame`] (MaterialX's per-closure `normal`
//! and `tangent` inputs), so a coat may have another normal than its base.
//!
//! Conventions (Mitsuba 3's): [`Bsdf::eval`] returns `f(ωo, ωi)·|cos θi|` with each closure's
//! cosine taken about its own normal; [`Sample::weight`] is `f·|cos θi| / pdf`; delta lobes
//! (a dielectric, conductor or generalized Schlick lobe with roughness below
//! [`DELTA_ALPHA`]) are only reached through [`Bsdf::sample`] and are absent from `eval` and
//! `pdf`.
//!
//! One module per concept: [`microfacet`] (GGX, Smith, visible normals), [`fresnel`],
//! [`thinfilm`] (Airy reflectance), [`albedo`] (directional-albedo tables), one module per
//! closure ([`oren_nayar`], [`burley`], [`translucent`], [`dielectric`], [`conductor`],
//! [`schlick`], [`sheen`], [`subsurface`]), the shared microfacet lobe (`lobe.rs`) and the
//! tree (`tree.rs`). For several queries at one shading point, [`Bsdf::prepare`] resolves the
//! tree once.
//!
//! Approximations, each documented where it is made and measured by the tests:
//! `subsurface_bsdf` is Lambertian reflection of its colour (no volumes); anisotropic lobes
//! read the isotropic albedo tables at the RMS roughness; generalized-Schlick and filmed
//! transmission albedos borrow the dielectric tables; dielectric `R`-only/`T`-only albedos
//! seen from inside are least accurate near the critical angle for 0.1 < α < 0.3.

#![warn(missing_docs)]
// `!(x > 0.0)` is written on purpose throughout: it is true for NaN, which must be rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

pub mod albedo;
pub mod burley;
mod closure;
pub mod conductor;
pub mod dielectric;
pub mod fresnel;
mod lobe;
pub mod microfacet;
pub mod oren_nayar;
pub mod schlick;
pub mod sheen;
pub mod subsurface;
pub mod thinfilm;
pub mod translucent;
mod tree;
pub mod warp;

use glam::{DVec2, DVec3};

/// Roughness (GGX α, per axis) below which a microfacet lobe is a perfect mirror or refractor.
pub const DELTA_ALPHA: f64 = 1.0e-4;

/// Most nodes one [`Bsdf`] holds (standard_surface and open_pbr_surface need ≤ 16).
pub const MAX_NODES: usize = 24;

/// An orthonormal shading frame in world space: `n` the normal, `t` the tangent, `b = n × t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Unit normal.
    pub n: DVec3,
    /// Unit tangent, orthogonal to `n` (the direction of `roughness.x`).
    pub t: DVec3,
    /// Unit bitangent `n × t`.
    pub b: DVec3,
}

impl Frame {
    /// A frame about `n` with the tangent `t` made orthogonal to it (Gram–Schmidt); any
    /// orthogonal tangent when `t` is parallel to `n` or zero.
    pub fn new(n: DVec3, t: DVec3) -> Frame {
        let n = n.normalize();
        let mut t = (t - n * n.dot(t)).normalize_or_zero();
        if t == DVec3::ZERO || !t.is_finite() {
            t = n.any_orthonormal_vector();
        }
        Frame {
            n,
            t,
            b: n.cross(t),
        }
    }
}

/// Which hemispheres a microfacet closure scatters into (`scatter_mode`: `R`, `T`, `RT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScatterMode {
    /// Reflection only.
    R,
    /// Transmission only.
    T,
    /// Both, by the Fresnel curve.
    Rt,
}

/// Thin-film iridescence (`thinfilm_thickness` in nm, `thinfilm_ior`); thickness 0 is none.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ThinFilm {
    /// Thickness in nanometres.
    pub thickness: f64,
    /// Index of refraction of the film.
    pub ior: f64,
}

/// Sheen model (`sheen_bsdf` `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SheenMode {
    /// Conty & Kulla 2017.
    ContyKulla,
    /// Zeltner et al. 2022.
    Zeltner,
}

/// One pbrlib BSDF node with its inputs (MaterialX names; `weight` ∈ [0, 1] scales it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Closure {
    /// `oren_nayar_diffuse_bsdf`: `color` ρ, `roughness` σ (0: Lambertian),
    /// `energy_compensation` (EON).
    OrenNayar {
        /// `weight`.
        weight: f64,
        /// `color`.
        color: DVec3,
        /// `roughness`.
        roughness: f64,
        /// `energy_compensation`.
        energy_compensation: bool,
        /// `normal` (and a tangent).
        frame: Frame,
    },
    /// `burley_diffuse_bsdf`.
    Burley {
        /// `weight`.
        weight: f64,
        /// `color`.
        color: DVec3,
        /// `roughness`.
        roughness: f64,
        /// `normal`.
        frame: Frame,
    },
    /// `translucent_bsdf`: Lambertian transmission.
    Translucent {
        /// `weight`.
        weight: f64,
        /// `color`.
        color: DVec3,
        /// `normal`.
        frame: Frame,
    },
    /// `dielectric_bsdf`.
    Dielectric {
        /// `weight`.
        weight: f64,
        /// `tint`.
        tint: DVec3,
        /// `ior` (0 disables the Fresnel curve).
        ior: f64,
        /// `roughness` (GGX α along `t` and `b`).
        alpha: DVec2,
        /// `retroreflective`.
        retroreflective: bool,
        /// `thinfilm_thickness`, `thinfilm_ior`.
        thinfilm: ThinFilm,
        /// `scatter_mode`.
        mode: ScatterMode,
        /// `normal`, `tangent`.
        frame: Frame,
    },
    /// `conductor_bsdf`: complex IOR `ior + i·extinction` per channel.
    Conductor {
        /// `weight`.
        weight: f64,
        /// `ior` (η per channel).
        ior: DVec3,
        /// `extinction` (κ per channel).
        extinction: DVec3,
        /// `roughness` (GGX α).
        alpha: DVec2,
        /// `retroreflective`.
        retroreflective: bool,
        /// `thinfilm_thickness`, `thinfilm_ior`.
        thinfilm: ThinFilm,
        /// `normal`, `tangent`.
        frame: Frame,
    },
    /// `generalized_schlick_bsdf` (Hoffman 2023's F82 tint).
    GeneralizedSchlick {
        /// `weight`.
        weight: f64,
        /// `color0`.
        color0: DVec3,
        /// `color82`.
        color82: DVec3,
        /// `color90`.
        color90: DVec3,
        /// `exponent`.
        exponent: f64,
        /// `roughness` (GGX α).
        alpha: DVec2,
        /// `retroreflective`.
        retroreflective: bool,
        /// `thinfilm_thickness`, `thinfilm_ior`.
        thinfilm: ThinFilm,
        /// `scatter_mode`.
        mode: ScatterMode,
        /// `normal`, `tangent`.
        frame: Frame,
    },
    /// `sheen_bsdf`.
    Sheen {
        /// `weight`.
        weight: f64,
        /// `color`.
        color: DVec3,
        /// `roughness`.
        roughness: f64,
        /// `mode`.
        mode: SheenMode,
        /// `normal`.
        frame: Frame,
    },
    /// `subsurface_bsdf`, approximated without volumes (see its module for which way).
    Subsurface {
        /// `weight`.
        weight: f64,
        /// `color`.
        color: DVec3,
        /// `radius` (mean free path per channel).
        radius: DVec3,
        /// `anisotropy`.
        anisotropy: f64,
        /// `normal`.
        frame: Frame,
    },
}

/// A node of a [`Bsdf`] tree; children are ids of nodes pushed earlier.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    /// A closure.
    Closure(Closure),
    /// `layer`: `f_top + (1 − E_top(ωo))·f_base` (a `None` base is a VDF or nothing: zero).
    Layer {
        /// `top`.
        top: NodeId,
        /// `base`.
        base: Option<NodeId>,
    },
    /// `mix`: `(1 − mix)·bg + mix·fg`.
    Mix {
        /// `fg`.
        fg: Option<NodeId>,
        /// `bg`.
        bg: Option<NodeId>,
        /// `mix` ∈ [0, 1].
        mix: f64,
    },
    /// `add`: `in1 + in2`.
    Add {
        /// `in1`.
        a: Option<NodeId>,
        /// `in2`.
        b: Option<NodeId>,
    },
    /// `multiply`: `in1 · in2` (a float weight as a grey colour).
    Multiply {
        /// `in1`.
        a: NodeId,
        /// `in2`.
        weight: DVec3,
    },
}

/// Index of a node within its [`Bsdf`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeId(pub u8);

/// What kind of scattering a sampled direction came from (for lights' `diffuse` / `specular`
/// multipliers and path statistics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LobeKind {
    /// Diffuse reflection or transmission (Oren–Nayar, Burley, translucent, subsurface, sheen).
    Diffuse,
    /// Glossy (rough microfacet) reflection or transmission.
    Glossy,
    /// A delta lobe: mirror reflection or smooth refraction.
    Specular,
}

/// A sampled incident direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Unit world direction towards the light.
    pub wi: DVec3,
    /// `f·|cos θi| / pdf` (for a delta lobe: its reflectance or transmittance times the
    /// node weights, divided by the probability of choosing it).
    pub weight: DVec3,
    /// Density of `wi` per unit solid angle ([`Bsdf::pdf`]; for a delta lobe, the
    /// probability of choosing it, and `kind` is [`LobeKind::Specular`]).
    pub pdf: f64,
    /// The lobe that produced it.
    pub kind: LobeKind,
    /// Whether `wi` lies on the other side of the geometric surface than `wo`.
    pub transmitted: bool,
}

/// `eval`'s value split by lobe kind.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Eval {
    /// Diffuse lobes' `f·|cos θi|`.
    pub diffuse: DVec3,
    /// Glossy lobes' `f·|cos θi|`.
    pub specular: DVec3,
}

/// A closure tree at one shading point for one outgoing direction.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    nodes: [Option<Node>; MAX_NODES],
    len: u8,
    wo: DVec3,
    ng: DVec3,
    entering: bool,
    thin_walled: bool,
}

impl Bsdf {
    /// An empty tree (black) for the unit direction `wo` towards the viewer, at a surface
    /// whose geometric normal `ng` faces `wo`; `entering` says whether `wo` is on the outside
    /// of the surface (a solid dielectric's ior applies as `ior` entering, `1/ior` leaving);
    /// `thin_walled` makes transmission pass straight through without refraction (the
    /// `surface` node's `thin_walled`).
    pub fn new(wo: DVec3, ng: DVec3, entering: bool, thin_walled: bool) -> Bsdf {
        Bsdf {
            nodes: [None; MAX_NODES],
            len: 0,
            wo,
            ng,
            entering,
            thin_walled,
        }
    }

    /// Adds a node (its children pushed before it); `None` when the tree is full.
    pub fn push(&mut self, node: Node) -> Option<NodeId> {
        let i = self.len as usize;
        if i >= MAX_NODES {
            return None;
        }
        self.nodes[i] = Some(node);
        self.len += 1;
        Some(NodeId(i as u8))
    }

    /// The nodes pushed so far, in order (the last is the root).
    pub fn nodes(&self) -> impl Iterator<Item = &Node> {
        self.nodes[..self.len as usize].iter().flatten()
    }

    /// The root node (the last pushed), if any.
    pub fn root(&self) -> Option<NodeId> {
        self.len.checked_sub(1).map(NodeId)
    }

    pub(crate) fn node_slice(&self) -> &[Option<Node>] {
        &self.nodes[..self.len as usize]
    }
    pub(crate) fn wo_dir(&self) -> DVec3 {
        self.wo
    }
    pub(crate) fn is_entering(&self) -> bool {
        self.entering
    }
    pub(crate) fn is_thin_walled(&self) -> bool {
        self.thin_walled
    }

    /// The tree resolved for its `wo` (every closure's frame, inputs, albedo and the
    /// combinators' coefficients), for several queries at one shading point: each method of
    /// [`Bsdf`] resolves the tree anew, [`PreparedBsdf`]'s do not.
    pub fn prepare(&self) -> PreparedBsdf {
        let mut out = PreparedBsdf {
            tree: tree::Prepared::empty(),
            ng: self.ng,
        };
        out.tree.fill(self);
        out
    }

    /// Whether the tree reflects and transmits nothing (every closure's contribution
    /// `cₖ ⊙ Eₖ(ωo)` is zero; see `tree.rs`).
    pub fn is_black(&self) -> bool {
        self.prepare().is_black()
    }

    /// `f(wo, wi)·|cos θi|` of the non-delta lobes, split into diffuse and glossy parts
    /// (never NaN or negative).
    pub fn eval(&self, wi: DVec3) -> Eval {
        self.prepare().eval(wi)
    }

    /// Density of [`Bsdf::sample`] producing `wi` (non-delta lobes only): the mixture
    /// `Σ pₖ pdfₖ(wi)` of `tree.rs`. It integrates to one minus the probability of choosing a
    /// delta lobe (minus that of samples that fail, e.g. a microfacet reflection below the
    /// horizon).
    pub fn pdf(&self, wi: DVec3) -> f64 {
        self.prepare().pdf(wi)
    }

    /// Samples an incident direction: `u_lobe` chooses a lobe (its remainder also chooses
    /// reflection or transmission within a microfacet lobe), `u` the direction within it.
    /// `None` when the tree is black or the sample falls where the lobe is zero (below the
    /// horizon, total internal reflection).
    pub fn sample(&self, u_lobe: f64, u: [f64; 2]) -> Option<Sample> {
        self.prepare().sample(u_lobe, u)
    }

    /// The directional albedo `E(wo) = ∫ f·|cos θi| dωi` of the whole tree (tabulated or
    /// closed form per closure, combined as the combinators combine them), delta lobes
    /// included.
    pub fn albedo(&self) -> DVec3 {
        self.prepare().albedo()
    }
}

/// A [`Bsdf`] resolved for its `wo` ([`Bsdf::prepare`]): the same queries without redoing
/// the per-closure set-up (table lookups, Fresnel averages) each time. `Copy`, no allocation.
#[derive(Clone, Copy, Debug)]
pub struct PreparedBsdf {
    tree: tree::Prepared,
    ng: DVec3,
}

impl PreparedBsdf {
    /// [`Bsdf::is_black`].
    pub fn is_black(&self) -> bool {
        !(self.tree.total > 0.0)
    }
    /// [`Bsdf::eval`].
    pub fn eval(&self, wi: DVec3) -> Eval {
        self.tree.eval(wi)
    }
    /// [`Bsdf::pdf`].
    pub fn pdf(&self, wi: DVec3) -> f64 {
        self.tree.pdf(wi)
    }
    /// [`Bsdf::sample`].
    pub fn sample(&self, u_lobe: f64, u: [f64; 2]) -> Option<Sample> {
        self.tree.sample(self.ng, u_lobe, u)
    }
    /// [`Bsdf::albedo`].
    pub fn albedo(&self) -> DVec3 {
        self.tree.albedo
    }
}
