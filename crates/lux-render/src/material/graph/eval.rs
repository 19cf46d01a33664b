//! The compiled program and its evaluation at a hit.

use super::closure::{self, BsdfOp};
use super::geometry::{self, Geom};
use super::math::{self, MathOp};
use super::texture::ImageOp;
use super::{GraphShader, Shaded, ShadingContext};
use glam::{DVec2, DVec3, DVec4, Vec4Swizzles};
use lux_bsdf::{Bsdf, Node};
use lux_usd::shading::ValueType;
use std::cell::RefCell;

/// Where an instruction's argument comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Arg {
    /// A constant (canonical for its type).
    Const(DVec4),
    /// A register written by an earlier instruction.
    Reg(u32),
    /// A geometric quantity of the hit.
    Geom(Geom),
}

/// What an instruction computes.
#[derive(Clone, Debug)]
pub(crate) enum Op {
    /// A value node (pure: folded when its arguments are constant).
    Math(MathOp),
    /// An `image` lookup (pure): arguments `texcoord`, `default`.
    Image(Box<ImageOp>),
    /// `geompropvalue`: the primvar in `slot`; argument `default`.
    Primvar(usize),
    /// A closure or combinator pushed into the hit's [`Bsdf`].
    Bsdf(BsdfOp),
    /// `generalized_schlick_edf` (depends on the viewing direction).
    SchlickEdf,
}

impl Op {
    /// Whether the op builds a closure.
    pub(crate) fn is_closure(&self) -> bool {
        matches!(self, Op::Bsdf(_))
    }
}

/// One instruction: `out = op(args)`, canonicalised for `ty`.
#[derive(Clone, Debug)]
pub(crate) struct Instr {
    pub(crate) op: Op,
    pub(crate) args: Vec<Arg>,
    pub(crate) out: u32,
    pub(crate) ty: ValueType,
}

/// Most arguments one instruction reads (`switch`: 10 inputs and `which`).
pub(crate) const MAX_ARGS: usize = 12;

/// Evaluates a pure op on argument values (the compiler's constant folding uses the same
/// function as the hits).
pub(crate) fn apply_pure(op: &Op, a: &[DVec4], ty: ValueType) -> DVec4 {
    let v = match op {
        Op::Math(m) => math::apply(*m, a),
        Op::Image(img) => {
            let uv = a.first().copied().unwrap_or(DVec4::ZERO);
            let default = a.get(1).copied().unwrap_or(DVec4::ZERO);
            img.sample(DVec2::new(uv.x, uv.y), default)
        }
        _ => DVec4::ZERO,
    };
    math::canon(v, ty)
}

thread_local! {
    /// The register file of the hits shaded on this thread (grown to the largest shader).
    static REGISTERS: RefCell<Vec<DVec4>> = const { RefCell::new(Vec::new()) };
}

#[inline]
fn value(arg: &Arg, regs: &[DVec4], ctx: &ShadingContext) -> DVec4 {
    match arg {
        Arg::Const(v) => *v,
        Arg::Reg(r) => regs.get(*r as usize).copied().unwrap_or(DVec4::ZERO),
        Arg::Geom(g) => g.at(ctx),
    }
}

/// Runs the program of `shader` at a hit.
///
/// The result is built in place (`run` fills it through a reference): the closure tree is a
/// few kilobytes, and returning it through the register file's closure copied it per hit.
pub(crate) fn eval(shader: &GraphShader, ctx: &ShadingContext) -> Shaded {
    let mut out = Shaded {
        bsdf: Bsdf::new(ctx.wo, ctx.ng, ctx.entering, false),
        emission: DVec3::ZERO,
        opacity: 1.0,
        thin_walled: false,
    };
    REGISTERS.with(|cell| match cell.try_borrow_mut() {
        Ok(mut regs) => run(shader, ctx, &mut regs, &mut out),
        // Re-entered on this thread (not done by lux): a register file of its own.
        Err(_) => run(shader, ctx, &mut Vec::new(), &mut out),
    });
    out
}

/// Fills `out` (as [`eval`] made it: an empty tree, no emission, opaque, not thin-walled).
fn run(shader: &GraphShader, ctx: &ShadingContext, regs: &mut Vec<DVec4>, out: &mut Shaded) {
    if regs.len() < shader.registers {
        regs.resize(shader.registers, DVec4::ZERO);
    }
    let thin_const = match &shader.surface {
        Some(s) => match s.thin_walled {
            Arg::Const(v) => Some(v.x != 0.0),
            _ => None,
        },
        None => Some(false),
    };
    if thin_const == Some(true) {
        out.bsdf = Bsdf::new(ctx.wo, ctx.ng, ctx.entering, true);
    }
    let bsdf = &mut out.bsdf;
    let mut args = [DVec4::ZERO; MAX_ARGS];
    for instr in &shader.program {
        let n = instr.args.len().min(MAX_ARGS);
        for (slot, arg) in args.iter_mut().zip(&instr.args) {
            *slot = value(arg, regs, ctx);
        }
        let a = &args[..n];
        let out = match &instr.op {
            Op::Math(_) | Op::Image(_) => apply_pure(&instr.op, a, instr.ty),
            Op::Primvar(slot) => math::canon(geometry::primvar(ctx, *slot, a[0]), instr.ty),
            Op::Bsdf(op) => closure::push(*op, a, ctx, bsdf),
            Op::SchlickEdf => closure::schlick_edf(a, ctx),
        };
        regs[instr.out as usize] = out;
    }
    let Some(surface) = &shader.surface else {
        return;
    };
    // The tree's root is its last node: make sure the surface's closure is (a pass-through
    // combinator may have returned an earlier node), and that nothing is left when it is none.
    let count = bsdf.nodes().count();
    match closure::id(value(&surface.bsdf, regs, ctx)) {
        Some(root) if usize::from(root.0) + 1 != count => {
            bsdf.push(Node::Add {
                a: Some(root),
                b: None,
            });
        }
        None if count > 0 => {
            *bsdf = Bsdf::new(ctx.wo, ctx.ng, ctx.entering, thin_const.unwrap_or(false))
        }
        _ => {}
    }
    let emission = value(&surface.edf, regs, ctx).xyz();
    let emission = if emission.is_finite() {
        emission.max(DVec3::ZERO)
    } else {
        DVec3::ZERO
    };
    let opacity = value(&surface.opacity, regs, ctx).x;
    let opacity = if opacity.is_nan() {
        1.0
    } else {
        opacity.clamp(0.0, 1.0)
    };
    let thin_walled = match thin_const {
        Some(t) => t,
        None => {
            let t = value(&surface.thin_walled, regs, ctx).x != 0.0;
            if t {
                // A varying thin_walled (not uniform as authored): rebuild the tree with it.
                let mut rebuilt = Bsdf::new(ctx.wo, ctx.ng, ctx.entering, true);
                for node in bsdf.nodes() {
                    rebuilt.push(*node);
                }
                *bsdf = rebuilt;
            }
            t
        }
    };
    out.emission = emission;
    out.opacity = opacity;
    out.thin_walled = thin_walled;
}

/// [`GraphShader::constant_lambert`].
pub(crate) fn constant_lambert(shader: &GraphShader) -> Option<DVec3> {
    let surface = shader.surface.as_ref()?;
    match (surface.opacity, surface.edf) {
        (Arg::Const(o), Arg::Const(e)) if o.x == 1.0 && e.xyz() == DVec3::ZERO => {}
        _ => return None,
    }
    lambert(shader, surface.bsdf)
}

/// The albedo of the closure tree rooted at `arg` when it is a constant Lambertian (none is
/// black).
fn lambert(shader: &GraphShader, arg: Arg) -> Option<DVec3> {
    let r = match arg {
        Arg::Const(v) if closure::id(v).is_none() => return Some(DVec3::ZERO),
        Arg::Reg(r) => r,
        _ => return None,
    };
    let instr = shader.program.iter().find(|i| i.out == r)?;
    let c = |i: usize| match instr.args.get(i) {
        Some(Arg::Const(v)) => Some(*v),
        _ => None,
    };
    match &instr.op {
        Op::Bsdf(BsdfOp::OrenNayar { .. }) => {
            let (weight, color, roughness) = (c(0)?, c(1)?, c(2)?);
            (roughness.x == 0.0 && instr.args.get(3) == Some(&Arg::Geom(Geom::N)))
                .then(|| weight.x * color.xyz())
        }
        Op::Bsdf(BsdfOp::Mix) => {
            let m = c(2)?.x;
            Some(lambert(shader, instr.args[0])? * m + lambert(shader, instr.args[1])? * (1.0 - m))
        }
        Op::Bsdf(BsdfOp::Add) => {
            Some(lambert(shader, instr.args[0])? + lambert(shader, instr.args[1])?)
        }
        Op::Bsdf(BsdfOp::Multiply) => Some(lambert(shader, instr.args[0])? * c(1)?.xyz()),
        _ => None,
    }
}
