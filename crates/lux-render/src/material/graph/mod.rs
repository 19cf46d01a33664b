//! MaterialX shading graphs on the renderer side: a flattened [`ShadingGraph`] (lux-usd's
//! `shading` module: only "native" nodes — the pbrlib closures and helpers and the stdlib
//! nodes) compiled once per material into a flat instruction list ([`GraphShader::compile`]),
//! then evaluated per ray hit into a closure tree of the `lux-bsdf` crate
//! ([`GraphShader::eval`]).
//!
//! Compilation:
//!
//! - every node output becomes an *argument*: a constant, a register written by an
//!   instruction, or a geometric quantity of the hit (`UV0`, `Nworld`, `Tworld`, `Bworld`,
//!   `Pworld`; [`ShadingContext`]);
//! - **constant folding**: a node whose inputs are all constant is evaluated at compile time
//!   (an `image` whose texture coordinate is constant included), and conditionals whose
//!   selector is constant (`ifgreater`, `ifgreatereq`, `ifequal`, `switch`, `mix` with `mix`
//!   0 or 1) become their selected input, so a UsdPreviewSurface or standard_surface with
//!   constant inputs costs only the construction of its closures per hit;
//! - a closure whose `weight` folds to 0 is dropped, and the combinators over dropped closures
//!   simplify (`layer` over nothing is its top, `add` of one closure is that closure, …);
//! - instructions the surface does not depend on are removed.
//!
//! Evaluation runs the instructions on a per-thread register file (no allocation per hit
//! once it has grown to the largest shader), pushing the closures into a
//! [`lux_bsdf::Bsdf`] bottom-up so that its last node is the root.
//!
//! Node semantics follow `MaterialX.StandardNodes.md` and `MaterialX.PBRSpec.md`, with the
//! reference implementations (MaterialX 1.39 `genglsl`) where the text gives no formula
//! (`rotate2d`, `rotate3d`, `normalmap`, `roughness_anisotropy`, `artistic_ior`). The files:
//! `math.rs` (stdlib arithmetic, channel, conditional and adjustment nodes), `texture.rs`
//! (`image`, `tiledimage`, colour spaces, the texture cache), `geometry.rs` (`texcoord`,
//! `position`, `normal`, `tangent`, `bitangent`, `geompropvalue`), `closure.rs` (pbrlib),
//! `compile.rs`, `eval.rs`.

mod closure;
mod compile;
mod eval;
mod geometry;
mod math;
mod texture;

pub use texture::{ColorSpace, TextureCache};

use glam::{DVec2, DVec3, DVec4};
use lux_usd::shading::ShadingGraph;

use eval::{Arg, Instr};

/// What a ray hit provides to a [`GraphShader`]: the geometric quantities MaterialX's
/// geometric nodes and `defaultgeomprop`s read (`MaterialX.StandardNodes.md`, "Geometric
/// Nodes"), all in world space.
#[derive(Clone, Copy, Debug)]
pub struct ShadingContext<'a> {
    /// Position (`Pworld`, `position`).
    pub p: DVec3,
    /// Unit shading normal facing the viewer (`Nworld`, `normal`).
    pub n: DVec3,
    /// Unit geometric normal facing the viewer.
    pub ng: DVec3,
    /// Unit tangent (`Tworld`, `tangent`): ∂p/∂u when the surface has texture coordinates,
    /// else any tangent.
    pub t: DVec3,
    /// Unit bitangent (`Bworld`, `bitangent`).
    pub b: DVec3,
    /// Texture coordinates, set 0 (`UV0`, `texcoord`), MaterialX's convention: (0, 0) at the
    /// lower left of an image.
    pub uv: DVec2,
    /// The values of the primvars of [`GraphShader::primvars`], by slot; a slot the gprim
    /// does not have is a non-finite value (or beyond the slice's end), and the reading
    /// `geompropvalue` node returns its `default` there.
    pub primvars: &'a [DVec4],
    /// Unit direction towards the viewer.
    pub wo: DVec3,
    /// Whether `wo` is on the outside of the surface.
    pub entering: bool,
}

/// A material evaluated at a hit ([`GraphShader::eval`]).
#[derive(Clone, Copy, Debug)]
pub struct Shaded {
    /// The closure tree of the `surface` node's `bsdf` (empty: black).
    pub bsdf: lux_bsdf::Bsdf,
    /// Radiance emitted towards `wo` by the `surface` node's `edf` (`uniform_edf`: its
    /// `color`; `generalized_schlick_edf`: `F(cos θo)·base`; `mix`/`add`/`multiply` on EDFs
    /// combine the radiances); negative or non-finite channels are 0.
    pub emission: DVec3,
    /// The `surface` node's `opacity` (cutout), clamped to \[0, 1\].
    pub opacity: f64,
    /// The `surface` node's `thin_walled`.
    pub thin_walled: bool,
}

/// The `surface` node (`MaterialX.PBRSpec.md`, "surface") the material shades with: its inputs
/// as arguments.
#[derive(Clone, Debug)]
pub(crate) struct SurfaceArgs {
    pub(crate) bsdf: Arg,
    pub(crate) edf: Arg,
    pub(crate) opacity: Arg,
    pub(crate) thin_walled: Arg,
}

/// A material's flattened MaterialX shading graph, compiled for evaluation at ray hits.
#[derive(Clone, Debug)]
pub struct GraphShader {
    material: String,
    program: Vec<Instr>,
    registers: usize,
    surface: Option<SurfaceArgs>,
    primvars: Vec<String>,
    unsupported: Vec<String>,
}

impl GraphShader {
    /// Compiles `graph` (nodes topologically sorted, every input present): textures are
    /// loaded through `textures` (once per file and colour space), constant nodes folded,
    /// dead instructions removed. Never fails: what cannot be honoured (an unknown node
    /// category — its outputs take zero, closures none —, a texture that does not load — the
    /// `image` returns its `default` —, an unsupported input value) is a warning in
    /// `warnings` naming material and node, and listed by [`GraphShader::unsupported`].
    pub fn compile(
        graph: &ShadingGraph,
        textures: &mut TextureCache,
        warnings: &mut Vec<String>,
    ) -> GraphShader {
        compile::compile(graph, textures, warnings)
    }

    /// The Material prim path.
    pub fn material(&self) -> &str {
        &self.material
    }

    /// The primvar names `geompropvalue` nodes (and so `UsdPrimvarReader`s) read, in the slot
    /// order of [`ShadingContext::primvars`].
    pub fn primvars(&self) -> &[String] {
        &self.primvars
    }

    /// What could not be honoured as authored, each naming its node: the flattening's
    /// [`ShadingGraph::notes`] followed by the compiler's (unknown node categories, textures
    /// that did not load, inputs read otherwise than authored), for `lux info`.
    pub fn unsupported(&self) -> &[String] {
        &self.unsupported
    }

    /// How many instructions run per hit, closure constructions included (0 for a material
    /// whose surface folded to constants and has no closure).
    pub fn instruction_count(&self) -> usize {
        self.program.len()
    }

    /// How many of the per-hit instructions are not closure constructions (0 for a material
    /// whose inputs are all constant).
    pub fn value_instruction_count(&self) -> usize {
        self.program.iter().filter(|i| !i.op.is_closure()).count()
    }

    /// Evaluates the material at a hit.
    pub fn eval(&self, ctx: &ShadingContext) -> Shaded {
        eval::eval(self, ctx)
    }

    /// Whether some closure of the compiled surface may transmit (`translucent_bsdf`, or a
    /// `dielectric_bsdf` / `generalized_schlick_bsdf` whose `scatter_mode` is `T` or `RT`).
    pub fn may_transmit(&self) -> bool {
        use closure::BsdfOp;
        self.program.iter().any(|i| {
            matches!(
                i.op,
                eval::Op::Bsdf(
                    BsdfOp::Translucent
                        | BsdfOp::Dielectric {
                            mode: lux_bsdf::ScatterMode::T | lux_bsdf::ScatterMode::Rt,
                            ..
                        }
                        | BsdfOp::GeneralizedSchlick {
                            mode: lux_bsdf::ScatterMode::T | lux_bsdf::ScatterMode::Rt,
                            ..
                        }
                )
            )
        })
    }

    /// Whether the shader depends on the hit's tangent frame (`Tworld`, `Bworld`): a value
    /// node reads it, or a microfacet closure is anisotropic (its `roughness` not a constant
    /// with equal components). An isotropic surface is the same about any tangent, so the
    /// renderer may then give any tangent orthogonal to the normal.
    pub fn reads_tangent(&self) -> bool {
        use eval::{Arg, Op};
        use geometry::Geom;
        let tangent = |a: &Arg| matches!(a, Arg::Geom(Geom::T | Geom::B));
        self.program.iter().any(|i| match &i.op {
            Op::Bsdf(op) => {
                let names = op.inputs();
                let at = |name: &str| {
                    names
                        .iter()
                        .position(|n| *n == name)
                        .and_then(|k| i.args.get(k))
                };
                match (at("roughness"), at("tangent")) {
                    (Some(Arg::Const(r)), Some(_)) if i.args.len() == names.len() => r.x != r.y,
                    (Some(_), Some(_)) => true,
                    _ => false,
                }
            }
            _ => i.args.iter().any(tangent),
        })
    }

    /// The surface's emission when it is a constant (`None`: it varies over the surface or
    /// with the viewing direction); black without a surface.
    pub fn constant_emission(&self) -> Option<DVec3> {
        match &self.surface {
            None => Some(DVec3::ZERO),
            Some(s) => match s.edf {
                eval::Arg::Const(v) => Some(v.truncate()),
                _ => None,
            },
        }
    }

    /// The surface's `opacity` when it is a constant (`None`: it varies); 1 without a surface.
    pub fn constant_opacity(&self) -> Option<f64> {
        match &self.surface {
            None => Some(1.0),
            Some(s) => match s.opacity {
                eval::Arg::Const(v) => Some(v.x),
                _ => None,
            },
        }
    }

    /// The albedo of the renderer's fast Lambertian path: `Some(weight·color)` when the
    /// whole surface folds to constant `oren_nayar_diffuse_bsdf` closures of roughness 0
    /// about the shading normal (combined by `mix`, `add` and `multiply` with constant
    /// weights), with no other closure of nonzero weight, opacity 1 and no emission.
    pub fn constant_lambert(&self) -> Option<DVec3> {
        eval::constant_lambert(self)
    }
}
