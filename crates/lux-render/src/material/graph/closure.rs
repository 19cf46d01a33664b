//! The pbrlib closures (`MaterialX.PBRSpec.md`, "BSDF Nodes", "EDF Nodes", "Combining
//! Distribution Functions") as `lux-bsdf` nodes.
//!
//! A BSDF value in a register is the id of its node in the [`Bsdf`] being built (`−1`: no
//! closure, black); an EDF value is the radiance it emits towards the viewer (so `mix`, `add`
//! and `multiply` on EDFs are colour arithmetic); a VDF is always none (lux has no volumes:
//! `anisotropic_vdf` and `absorption_vdf` contribute nothing, a `layer` over one keeps its top
//! with `base: None`).

use super::ShadingContext;
use glam::{DVec2, DVec3, DVec4, Vec4Swizzles};
use lux_bsdf::{Bsdf, Closure, Frame, Node, NodeId, ScatterMode, SheenMode, ThinFilm};

/// The register value of "no closure".
pub(crate) const NONE: DVec4 = DVec4::splat(-1.0);

/// A closure or combinator node; its arguments are the inputs [`BsdfOp::inputs`] names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum BsdfOp {
    /// `oren_nayar_diffuse_bsdf`.
    OrenNayar {
        /// `energy_compensation` (uniform).
        energy_compensation: bool,
    },
    /// `burley_diffuse_bsdf`.
    Burley,
    /// `translucent_bsdf`.
    Translucent,
    /// `dielectric_bsdf`.
    Dielectric {
        /// `retroreflective`.
        retroreflective: bool,
        /// `scatter_mode`.
        mode: ScatterMode,
    },
    /// `conductor_bsdf`.
    Conductor {
        /// `retroreflective`.
        retroreflective: bool,
    },
    /// `generalized_schlick_bsdf`.
    GeneralizedSchlick {
        /// `retroreflective`.
        retroreflective: bool,
        /// `scatter_mode`.
        mode: ScatterMode,
    },
    /// `sheen_bsdf`.
    Sheen {
        /// `mode`.
        mode: SheenMode,
    },
    /// `subsurface_bsdf`.
    Subsurface,
    /// `layer`: `top` over `base`; `vdf`: the base is a VDF (so none).
    Layer {
        /// Whether the base is a VDF.
        vdf: bool,
    },
    /// `mix` on BSDFs: `fg`, `bg`, `mix`.
    Mix,
    /// `add` on BSDFs.
    Add,
    /// `multiply` on a BSDF: `in1` by the colour or float `in2`.
    Multiply,
}

impl BsdfOp {
    /// The input names of the op's arguments, in order.
    pub(crate) fn inputs(self) -> &'static [&'static str] {
        match self {
            BsdfOp::OrenNayar { .. } | BsdfOp::Burley | BsdfOp::Sheen { .. } => {
                &["weight", "color", "roughness", "normal"]
            }
            BsdfOp::Translucent => &["weight", "color", "normal"],
            BsdfOp::Dielectric { .. } => &[
                "weight",
                "tint",
                "ior",
                "roughness",
                "thinfilm_thickness",
                "thinfilm_ior",
                "normal",
                "tangent",
            ],
            BsdfOp::Conductor { .. } => &[
                "weight",
                "ior",
                "extinction",
                "roughness",
                "thinfilm_thickness",
                "thinfilm_ior",
                "normal",
                "tangent",
            ],
            BsdfOp::GeneralizedSchlick { .. } => &[
                "weight",
                "color0",
                "color82",
                "color90",
                "exponent",
                "roughness",
                "thinfilm_thickness",
                "thinfilm_ior",
                "normal",
                "tangent",
            ],
            BsdfOp::Subsurface => &["weight", "color", "radius", "anisotropy", "normal"],
            BsdfOp::Layer { .. } => &["top", "base"],
            BsdfOp::Mix => &["fg", "bg", "mix"],
            BsdfOp::Add => &["in1", "in2"],
            BsdfOp::Multiply => &["in1", "in2"],
        }
    }

    /// Whether the op is a closure (with a `weight`, its first argument) rather than a
    /// combinator.
    pub(crate) fn is_closure(self) -> bool {
        !matches!(
            self,
            BsdfOp::Layer { .. } | BsdfOp::Mix | BsdfOp::Add | BsdfOp::Multiply
        )
    }
}

/// The closure node id held by a register value.
#[inline]
pub(crate) fn id(v: DVec4) -> Option<NodeId> {
    (v.x >= 0.0 && v.x < 256.0).then_some(NodeId(v.x as u8))
}

#[inline]
fn reg(id: Option<NodeId>) -> DVec4 {
    match id {
        Some(NodeId(i)) => DVec4::splat(f64::from(i)),
        None => NONE,
    }
}

/// A finite value, else `fallback`.
#[inline]
fn finite(x: f64, fallback: f64) -> f64 {
    if x.is_finite() { x } else { fallback }
}

#[inline]
fn color(v: DVec4) -> DVec3 {
    let c = v.xyz();
    if c.is_finite() { c } else { DVec3::ZERO }
}

/// The unit vector of an argument, else `fallback` (zero or not finite).
#[inline]
fn direction(v: DVec4, fallback: DVec3) -> DVec3 {
    let d = v.xyz();
    if d.is_finite() && d.length_squared() > 1.0e-24 {
        d.normalize()
    } else {
        fallback
    }
}

#[inline]
fn alpha(v: DVec4) -> DVec2 {
    DVec2::new(finite(v.x, 0.0).max(0.0), finite(v.y, 0.0).max(0.0))
}

#[inline]
fn thinfilm(thickness: DVec4, ior: DVec4) -> ThinFilm {
    ThinFilm {
        thickness: finite(thickness.x, 0.0).max(0.0),
        ior: finite(ior.x, 1.5),
    }
}

/// Builds the node of `op` from its arguments `a` at a hit and pushes it: the new register
/// value (none for a closure of weight 0, for a combinator of nothing, or when the tree is
/// full).
pub(crate) fn push(op: BsdfOp, a: &[DVec4], ctx: &ShadingContext, bsdf: &mut Bsdf) -> DVec4 {
    let arg = |i: usize| a.get(i).copied().unwrap_or(DVec4::ZERO);
    let frame = |ni: usize, ti: Option<usize>| {
        let n = direction(arg(ni), ctx.n);
        let t = ti.map_or(ctx.t, |ti| direction(arg(ti), ctx.t));
        Frame::new(n, t)
    };
    let node = if op.is_closure() {
        let weight = finite(arg(0).x, 0.0);
        if weight == 0.0 {
            return NONE;
        }
        Node::Closure(match op {
            BsdfOp::OrenNayar {
                energy_compensation,
            } => Closure::OrenNayar {
                weight,
                color: color(arg(1)),
                roughness: finite(arg(2).x, 0.0),
                energy_compensation,
                frame: frame(3, None),
            },
            BsdfOp::Burley => Closure::Burley {
                weight,
                color: color(arg(1)),
                roughness: finite(arg(2).x, 0.0),
                frame: frame(3, None),
            },
            BsdfOp::Translucent => Closure::Translucent {
                weight,
                color: color(arg(1)),
                frame: frame(2, None),
            },
            BsdfOp::Dielectric {
                retroreflective,
                mode,
            } => Closure::Dielectric {
                weight,
                tint: color(arg(1)),
                ior: finite(arg(2).x, 1.5),
                alpha: alpha(arg(3)),
                retroreflective,
                thinfilm: thinfilm(arg(4), arg(5)),
                mode,
                frame: frame(6, Some(7)),
            },
            BsdfOp::Conductor { retroreflective } => Closure::Conductor {
                weight,
                ior: color(arg(1)),
                extinction: color(arg(2)),
                alpha: alpha(arg(3)),
                retroreflective,
                thinfilm: thinfilm(arg(4), arg(5)),
                frame: frame(6, Some(7)),
            },
            BsdfOp::GeneralizedSchlick {
                retroreflective,
                mode,
            } => Closure::GeneralizedSchlick {
                weight,
                color0: color(arg(1)),
                color82: color(arg(2)),
                color90: color(arg(3)),
                exponent: finite(arg(4).x, 5.0),
                alpha: alpha(arg(5)),
                retroreflective,
                thinfilm: thinfilm(arg(6), arg(7)),
                mode,
                frame: frame(8, Some(9)),
            },
            BsdfOp::Sheen { mode } => Closure::Sheen {
                weight,
                color: color(arg(1)),
                roughness: finite(arg(2).x, 0.3),
                mode,
                frame: frame(3, None),
            },
            BsdfOp::Subsurface => Closure::Subsurface {
                weight,
                color: color(arg(1)),
                radius: color(arg(2)),
                anisotropy: finite(arg(3).x, 0.0),
                frame: frame(4, None),
            },
            BsdfOp::Layer { .. } | BsdfOp::Mix | BsdfOp::Add | BsdfOp::Multiply => {
                unreachable!("combinators are not closures")
            }
        })
    } else {
        match op {
            BsdfOp::Layer { vdf } => {
                let Some(top) = id(arg(0)) else {
                    return if vdf { NONE } else { arg(1) };
                };
                let base = if vdf { None } else { id(arg(1)) };
                Node::Layer { top, base }
            }
            BsdfOp::Mix => {
                let (fg, bg) = (id(arg(0)), id(arg(1)));
                if fg.is_none() && bg.is_none() {
                    return NONE;
                }
                Node::Mix {
                    fg,
                    bg,
                    mix: finite(arg(2).x, 0.0),
                }
            }
            BsdfOp::Add => {
                let (a, b) = (id(arg(0)), id(arg(1)));
                if a.is_none() && b.is_none() {
                    return NONE;
                }
                Node::Add { a, b }
            }
            BsdfOp::Multiply => {
                let Some(a) = id(arg(0)) else {
                    return NONE;
                };
                Node::Multiply {
                    a,
                    weight: color(arg(1)),
                }
            }
            _ => unreachable!("closures handled above"),
        }
    };
    reg(bsdf.push(node))
}

/// `generalized_schlick_edf`: `(r0 + (r90 − r0)·(1 − cos θo)^q)·base` with `cos θo = ωo·n`
/// about the shading normal (`a`: `color0`, `color90`, `exponent`, `base`).
pub(crate) fn schlick_edf(a: &[DVec4], ctx: &ShadingContext) -> DVec4 {
    let arg = |i: usize| a.get(i).copied().unwrap_or(DVec4::ZERO);
    let cos = ctx.wo.dot(ctx.n).clamp(0.0, 1.0);
    let f = (1.0 - cos).powf(arg(2).x);
    (arg(0) + (arg(1) - arg(0)) * f) * arg(3)
}
