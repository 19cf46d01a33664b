//! [`ShadingGraph`] → program: node dispatch, constant folding, dead-code removal.

use super::closure::{BsdfOp, NONE};
use super::eval::{Arg, Instr, MAX_ARGS, Op, apply_pure};
use super::geometry::Geom;
use super::math::{MathOp, Unary, canon, switch_index};
use super::texture::{Address, ImageOp, TextureCache};
use super::{GraphShader, SurfaceArgs};
use glam::{DVec4, Vec4Swizzles};
use lux_bsdf::{ScatterMode, SheenMode};
use lux_usd::shading::{FileValue, GraphNode, ShadingGraph, Source, Value, ValueType};

struct Compiler<'a> {
    graph: &'a ShadingGraph,
    textures: &'a mut TextureCache,
    /// What could not be honoured (each also a warning).
    notes: Vec<String>,
    program: Vec<Instr>,
    next_reg: u32,
    /// Every compiled node's outputs.
    outputs: Vec<Vec<Arg>>,
    /// The `surface` nodes' inputs, by node.
    surfaces: Vec<Option<SurfaceArgs>>,
    primvars: Vec<String>,
}

/// The "none" value of a closure type, zero of any other.
fn zero_of(ty: ValueType) -> Arg {
    match ty {
        ValueType::Bsdf | ValueType::Vdf => Arg::Const(NONE),
        _ => Arg::Const(DVec4::ZERO),
    }
}

/// A constant input value as a register value of type `ty`.
fn constant(value: &Value, ty: ValueType) -> Option<DVec4> {
    match (value, ty) {
        (_, ValueType::Bsdf | ValueType::Vdf) => Some(NONE),
        (_, ValueType::Edf) => Some(DVec4::ZERO),
        (Value::Numbers(v), _) if ty.components() > 0 && ty.components() <= 4 => {
            let mut out = [0.0; 4];
            for (o, x) in out.iter_mut().zip(v) {
                *o = *x;
            }
            Some(canon(DVec4::from_array(out), ty))
        }
        _ => None,
    }
}

pub(crate) fn compile(
    graph: &ShadingGraph,
    textures: &mut TextureCache,
    warnings: &mut Vec<String>,
) -> GraphShader {
    let mut c = Compiler {
        graph,
        textures,
        notes: Vec::new(),
        program: Vec::new(),
        next_reg: 0,
        outputs: Vec::with_capacity(graph.nodes.len()),
        surfaces: Vec::with_capacity(graph.nodes.len()),
        primvars: Vec::new(),
    };
    for (i, node) in graph.nodes.iter().enumerate() {
        c.surfaces.push(None);
        let outs = c.node(i, node);
        c.outputs.push(outs);
    }
    let surface = match graph.surface {
        Some((n, _)) => c.surface_of(n, 0),
        None => None,
    };
    let (program, registers, surface) = strip(c.program, surface);
    for note in &c.notes {
        warnings.push(format!("material {}: {note}", graph.material));
    }
    let mut unsupported = graph.notes.clone();
    unsupported.extend(c.notes);
    GraphShader {
        material: graph.material.clone(),
        program,
        registers,
        surface,
        primvars: c.primvars,
        unsupported,
    }
}

/// Removes the instructions the surface does not read and numbers the registers densely.
fn strip(
    program: Vec<Instr>,
    mut surface: Option<SurfaceArgs>,
) -> (Vec<Instr>, usize, Option<SurfaceArgs>) {
    let regs = program
        .iter()
        .map(|i| i.out as usize + 1)
        .max()
        .unwrap_or(0);
    let mut live = vec![false; regs];
    let mark = |a: &Arg, live: &mut Vec<bool>| {
        if let Arg::Reg(r) = a {
            live[*r as usize] = true;
        }
    };
    if let Some(s) = &surface {
        for a in [&s.bsdf, &s.edf, &s.opacity, &s.thin_walled] {
            mark(a, &mut live);
        }
    }
    for instr in program.iter().rev() {
        if live[instr.out as usize] {
            for a in &instr.args {
                mark(a, &mut live);
            }
        }
    }
    let mut renumber = vec![u32::MAX; regs];
    let mut kept = Vec::new();
    for mut instr in program {
        if !live[instr.out as usize] {
            continue;
        }
        let r = kept.len() as u32;
        renumber[instr.out as usize] = r;
        instr.out = r;
        for a in &mut instr.args {
            if let Arg::Reg(x) = a {
                *x = renumber[*x as usize];
            }
        }
        kept.push(instr);
    }
    if let Some(s) = &mut surface {
        for a in [&mut s.bsdf, &mut s.edf, &mut s.opacity, &mut s.thin_walled] {
            if let Arg::Reg(x) = a {
                *x = renumber[*x as usize];
            }
        }
    }
    let n = kept.len();
    (kept, n, surface)
}

impl Compiler<'_> {
    fn note(&mut self, node: &GraphNode, what: String) {
        self.notes.push(format!("node {}: {what}", node.name));
    }

    /// The argument feeding input `name` of `node` (`None`: the node has no such input).
    fn input(&mut self, index: usize, node: &GraphNode, name: &str) -> Option<Arg> {
        let input = node.input(name)?;
        Some(match &input.source {
            Source::Value(v) => match constant(v, input.ty) {
                Some(v) => Arg::Const(v),
                None => {
                    if !matches!(input.ty, ValueType::String | ValueType::Filename) {
                        self.note(
                            node,
                            format!(
                                "input {name} ({}) value {v:?} is not supported; zero used",
                                input.ty.name()
                            ),
                        );
                    }
                    zero_of(input.ty)
                }
            },
            Source::Node { node: n, output } => {
                match (*n < index)
                    .then(|| self.outputs.get(*n))
                    .flatten()
                    .and_then(|o| o.get(*output))
                {
                    Some(a) => match a {
                        // A constant of another type (an authoring slip): re-canonicalised.
                        Arg::Const(v) if input.ty.components() > 0 => {
                            Arg::Const(canon(*v, input.ty))
                        }
                        a => *a,
                    },
                    None => {
                        self.note(
                            node,
                            format!("input {name} connects to no earlier node output; zero used"),
                        );
                        zero_of(input.ty)
                    }
                }
            }
            Source::Geomprop(g) => match Geom::of_geomprop(g) {
                Some((geom, world)) => {
                    if !world {
                        self.note(node, format!("input {name}: {g} is read in world space"));
                    }
                    Arg::Geom(geom)
                }
                None => {
                    let slot = self.primvar_slot(g);
                    self.emit(Op::Primvar(slot), vec![zero_of(input.ty)], input.ty)
                }
            },
        })
    }

    /// [`Compiler::input`], else a default by the input's name (`normal`: the shading
    /// normal, `weight`: 1, …; zero otherwise).
    fn input_or_default(&mut self, index: usize, node: &GraphNode, name: &str) -> Arg {
        if let Some(a) = self.input(index, node, name) {
            return a;
        }
        match name {
            "normal" => Arg::Geom(Geom::N),
            "tangent" => Arg::Geom(Geom::T),
            "bitangent" => Arg::Geom(Geom::B),
            "texcoord" => Arg::Geom(Geom::Uv),
            "weight" | "opacity" | "scale" | "amount" | "inhigh" | "outhigh" | "high" => {
                Arg::Const(DVec4::ONE)
            }
            "top" | "base" | "fg" | "bg" | "bsdf" => Arg::Const(NONE),
            _ => Arg::Const(DVec4::ZERO),
        }
    }

    fn inputs(&mut self, index: usize, node: &GraphNode, names: &[&str]) -> Vec<Arg> {
        names
            .iter()
            .map(|n| self.input_or_default(index, node, n))
            .collect()
    }

    /// The constant value of a uniform input (`string`, `filename`, `integer`, `boolean`),
    /// following `dot`, `constant` and `geompropvalueuniform` (its `default`) nodes.
    fn uniform(&self, node: &GraphNode, name: &str) -> Option<Value> {
        let mut source = &node.input(name)?.source;
        for _ in 0..64 {
            match source {
                Source::Value(v) => return Some(v.clone()),
                Source::Node { node: n, .. } => {
                    let up = self.graph.nodes.get(*n)?;
                    let next = match up.category.as_str() {
                        "geompropvalueuniform" => "default",
                        "dot" => "in",
                        "constant" => "value",
                        _ => return None,
                    };
                    source = &up.input(next)?.source;
                }
                Source::Geomprop(_) => return None,
            }
        }
        None
    }

    fn string(&self, node: &GraphNode, name: &str) -> String {
        match self.uniform(node, name) {
            Some(Value::String(s)) => s,
            _ => String::new(),
        }
    }

    fn file(&self, node: &GraphNode, name: &str) -> Option<FileValue> {
        match self.uniform(node, name) {
            Some(Value::File(f)) => Some(f),
            _ => None,
        }
    }

    fn flag(&self, node: &GraphNode, name: &str) -> bool {
        match self.uniform(node, name) {
            Some(Value::Numbers(v)) => v.first().is_some_and(|x| *x != 0.0),
            _ => false,
        }
    }

    fn primvar_slot(&mut self, name: &str) -> usize {
        match self.primvars.iter().position(|p| p == name) {
            Some(i) => i,
            None => {
                self.primvars.push(name.to_owned());
                self.primvars.len() - 1
            }
        }
    }

    /// Adds `out = op(args)`, or folds it: a pure op of constant arguments is evaluated now,
    /// a conditional of constant selector becomes its selected input, a closure of weight 0
    /// and combinators over nothing simplify.
    fn emit(&mut self, op: Op, args: Vec<Arg>, ty: ValueType) -> Arg {
        let konst = |i: usize| match args.get(i) {
            Some(Arg::Const(v)) => Some(*v),
            _ => None,
        };
        let is_none = |i: usize| konst(i).is_some_and(|v| v.x < 0.0);
        match &op {
            Op::Math(m) => {
                if args.iter().all(|a| matches!(a, Arg::Const(_))) {
                    let vals: Vec<DVec4> = args
                        .iter()
                        .map(|a| match a {
                            Arg::Const(v) => *v,
                            _ => DVec4::ZERO,
                        })
                        .collect();
                    return Arg::Const(apply_pure(&op, &vals, ty));
                }
                let pick = |a: Arg| match a {
                    Arg::Const(v) => Arg::Const(canon(v, ty)),
                    a => a,
                };
                match m {
                    MathOp::IfGreater | MathOp::IfGreaterEq | MathOp::IfEqual => {
                        if let (Some(a), Some(b)) = (konst(0), konst(1)) {
                            let yes = match m {
                                MathOp::IfGreater => a.x > b.x,
                                MathOp::IfGreaterEq => a.x >= b.x,
                                _ => a.x == b.x,
                            };
                            return pick(args[if yes { 2 } else { 3 }]);
                        }
                    }
                    MathOp::Switch(n) => {
                        if let Some(w) = konst(*n as usize) {
                            return pick(args[switch_index(w.x, *n as usize)]);
                        }
                    }
                    MathOp::Mix => {
                        if let Some(w) = konst(2) {
                            if w == DVec4::ZERO {
                                return pick(args[1]);
                            }
                            if canon(w, ty) == canon(DVec4::ONE, ty) {
                                return pick(args[0]);
                            }
                        }
                    }
                    MathOp::Normalize if args[0] == Arg::Geom(Geom::N) => return args[0],
                    // A flat normal (encoded (0.5, 0.5, 1)) is the frame's normal.
                    MathOp::Normalmap if konst(0) == Some(DVec4::new(0.5, 0.5, 1.0, 0.0)) => {
                        if args[2] == Arg::Geom(Geom::N) {
                            return args[2];
                        }
                        return self.emit(Op::Math(MathOp::Normalize), vec![args[2]], ty);
                    }
                    _ => {}
                }
            }
            Op::Image(_) => {
                if let (Some(uv), Some(d)) = (konst(0), konst(1)) {
                    return Arg::Const(apply_pure(&op, &[uv, d], ty));
                }
            }
            Op::Bsdf(b) => {
                if b.is_closure() {
                    if konst(0).is_some_and(|w| w.x == 0.0) {
                        return Arg::Const(NONE);
                    }
                    // A reflecting dielectric of ior 1 without a thin film reflects nothing
                    // (F ≡ 0: an OpenPBR or standard_surface specular of weight 0), and a
                    // layer over it is its base (E_top = 0).
                    if matches!(
                        b,
                        BsdfOp::Dielectric {
                            mode: lux_bsdf::ScatterMode::R,
                            ..
                        }
                    ) && konst(2).is_some_and(|ior| ior.x == 1.0)
                        && konst(4).is_some_and(|thickness| thickness.x == 0.0)
                    {
                        return Arg::Const(NONE);
                    }
                } else {
                    match b {
                        BsdfOp::Layer { vdf } => {
                            if is_none(0) {
                                return if *vdf { Arg::Const(NONE) } else { args[1] };
                            }
                            if !vdf && is_none(1) {
                                return args[0];
                            }
                        }
                        BsdfOp::Mix => {
                            if let Some(m) = konst(2) {
                                if m.x == 0.0 {
                                    return args[1];
                                }
                                if m.x == 1.0 {
                                    return args[0];
                                }
                            }
                            if is_none(0) && is_none(1) {
                                return Arg::Const(NONE);
                            }
                        }
                        BsdfOp::Add => {
                            if is_none(0) {
                                return args[1];
                            }
                            if is_none(1) {
                                return args[0];
                            }
                        }
                        BsdfOp::Multiply => {
                            if is_none(0) {
                                return Arg::Const(NONE);
                            }
                            if let Some(w) = konst(1) {
                                if w.xyz() == glam::DVec3::ZERO {
                                    return Arg::Const(NONE);
                                }
                                if w.xyz() == glam::DVec3::ONE {
                                    return args[0];
                                }
                            }
                        }
                        _ => {}
                    }
                }
            }
            Op::SchlickEdf => {
                if konst(3).is_some_and(|b| b.xyz() == glam::DVec3::ZERO) {
                    return Arg::Const(DVec4::ZERO);
                }
                if let (Some(c0), Some(c90)) = (konst(0), konst(1))
                    && c0 == c90
                {
                    return self.emit(Op::Math(MathOp::Multiply), vec![args[0], args[3]], ty);
                }
            }
            Op::Primvar(_) => {}
        }
        let out = self.next_reg;
        self.next_reg += 1;
        self.program.push(Instr { op, args, out, ty });
        Arg::Reg(out)
    }

    /// The surface a `surfaceshader` output of node `n` shades with.
    fn surface_of(&mut self, n: usize, depth: usize) -> Option<SurfaceArgs> {
        let node = self.graph.nodes.get(n)?;
        match node.category.as_str() {
            "surface" => self.surfaces.get(n).cloned().flatten(),
            "surfacematerial" if depth < 8 => match &node.input("surfaceshader")?.source {
                Source::Node { node: up, .. } if *up < n => self.surface_of(*up, depth + 1),
                _ => None,
            },
            _ => {
                let what = format!(
                    "surface shader node of category {} is not supported; the material is black",
                    node.category
                );
                self.note(node, what);
                None
            }
        }
    }

    /// Compiles node `index`: its outputs' arguments.
    fn node(&mut self, index: usize, node: &GraphNode) -> Vec<Arg> {
        let out_ty = node.outputs.first().map_or(ValueType::Float, |o| o.1);
        let in_ty = |name: &str| node.input(name).map_or(ValueType::Float, |i| i.ty);
        let math = math_op(node.category.as_str(), in_ty, out_ty);
        if let Some(args) = self.closure_node(index, node, math, out_ty) {
            return args;
        }
        if let Some(op) = math
            && out_ty.components() > 0
            && out_ty.components() <= 4
        {
            let args = self.inputs(index, node, op.inputs());
            return vec![self.emit(Op::Math(op), args, out_ty)];
        }
        if let Some(args) = self.structural_node(index, node, out_ty) {
            return args;
        }
        if matches!(out_ty, ValueType::String | ValueType::Filename) {
            // Uniform strings are read where they are consumed ([`Compiler::uniform`]).
            return node.outputs.iter().map(|o| zero_of(o.1)).collect();
        }
        let what = format!(
            "node category {:?} ({}) is not supported; its outputs take their nodedef's \
             defaults (`default`, `defaultinput`; zero, no closure, where it states none)",
            node.category, node.nodedef
        );
        self.note(node, what);
        self.output_fallbacks(index, node)
    }

    /// The outputs of a node lux does not evaluate, as its nodedef states them where the node
    /// is not evaluated (MaterialX Specification, "NodeDef Output Elements"): an output's
    /// `defaultinput` passes that input through, its `default` is a constant (or a geometric
    /// property); zero (no closure) where it states none.
    fn output_fallbacks(&mut self, index: usize, node: &GraphNode) -> Vec<Arg> {
        use lux_usd::mtlx::OutputFallback;
        let def = lux_usd::mtlx::library().nodedef(&node.nodedef);
        node.outputs
            .iter()
            .map(
                |(name, ty)| match def.and_then(|d| d.output_fallback(name)) {
                    Some(OutputFallback::Input(input))
                        if node.input(input).is_some_and(|i| i.ty == *ty) =>
                    {
                        self.input_or_default(index, node, input)
                    }
                    Some(OutputFallback::Value(v)) => {
                        constant(v, *ty).map_or_else(|| zero_of(*ty), Arg::Const)
                    }
                    Some(OutputFallback::Geomprop(g)) => match Geom::of_geomprop(g) {
                        Some((geom, _)) => Arg::Geom(geom),
                        None => zero_of(*ty),
                    },
                    _ => zero_of(*ty),
                },
            )
            .collect()
    }

    /// A node whose output is a closure (`BSDF`, `EDF`, `VDF`): the pbrlib nodes and the
    /// combinators that share their categories with math nodes; `None` for any other node.
    fn closure_node(
        &mut self,
        index: usize,
        node: &GraphNode,
        math: Option<MathOp>,
        out_ty: ValueType,
    ) -> Option<Vec<Arg>> {
        let in_ty = |name: &str| node.input(name).map_or(ValueType::Float, |i| i.ty);
        let category = node.category.as_str();
        let one = |a: Arg| Some(vec![a]);
        match out_ty {
            // Closure combinators share categories with math nodes.
            ValueType::Bsdf => {
                let op = match category {
                    "layer" => Some(BsdfOp::Layer {
                        vdf: in_ty("base") == ValueType::Vdf,
                    }),
                    "mix" => Some(BsdfOp::Mix),
                    "add" => Some(BsdfOp::Add),
                    "multiply" => Some(BsdfOp::Multiply),
                    _ => self.closure_op(node),
                };
                if let Some(op) = op {
                    let args = self.inputs(index, node, op.inputs());
                    return one(self.emit(Op::Bsdf(op), args, out_ty));
                }
            }
            ValueType::Edf => match category {
                "mix" | "add" | "multiply" => {
                    let op = math.unwrap_or(MathOp::Add);
                    let args = self.inputs(index, node, op.inputs());
                    return one(self.emit(Op::Math(op), args, out_ty));
                }
                "uniform_edf" => return one(self.input_or_default(index, node, "color")),
                "generalized_schlick_edf" => {
                    let args = self.inputs(index, node, &["color0", "color90", "exponent", "base"]);
                    return one(self.emit(Op::SchlickEdf, args, out_ty));
                }
                _ => {}
            },
            ValueType::Vdf => {
                // lux has no participating media: every VDF is none.
                if matches!(
                    category,
                    "anisotropic_vdf" | "absorption_vdf" | "mix" | "add" | "multiply"
                ) {
                    return one(Arg::Const(NONE));
                }
            }
            _ => {}
        }
        None
    }

    /// The stdlib nodes that are neither plain math nor closures (constructors, channels,
    /// conditionals of many inputs, geometry, textures); `None` for an unknown category.
    fn structural_node(
        &mut self,
        index: usize,
        node: &GraphNode,
        out_ty: ValueType,
    ) -> Option<Vec<Arg>> {
        let in_ty = |name: &str| node.input(name).map_or(ValueType::Float, |i| i.ty);
        let category = node.category.as_str();
        let one = |a: Arg| Some(vec![a]);
        match category {
            "surface" => {
                let args = SurfaceArgs {
                    bsdf: self.input_or_default(index, node, "bsdf"),
                    edf: self.input_or_default(index, node, "edf"),
                    opacity: self.input_or_default(index, node, "opacity"),
                    thin_walled: self.input_or_default(index, node, "thin_walled"),
                };
                self.surfaces[index] = Some(args);
                return one(Arg::Const(DVec4::splat(index as f64)));
            }
            "surfacematerial" => return one(Arg::Const(DVec4::ZERO)),
            "dot" | "constant" => {
                let name = if category == "dot" { "in" } else { "value" };
                return one(self.input(index, node, name).unwrap_or(zero_of(out_ty)));
            }
            "switch" => {
                let mut names: Vec<&str> = [
                    "in1", "in2", "in3", "in4", "in5", "in6", "in7", "in8", "in9", "in10",
                ]
                .into_iter()
                .filter(|n| node.input(n).is_some())
                .collect();
                names.truncate(MAX_ARGS - 1);
                let n = names.len().max(1);
                if names.is_empty() {
                    names.push("in1");
                }
                names.push("which");
                let args = self.inputs(index, node, &names);
                return one(self.emit(Op::Math(MathOp::Switch(n as u8)), args, out_ty));
            }
            "extract" => {
                let i = match self.uniform(node, "index") {
                    Some(Value::Numbers(v)) => v.first().copied().unwrap_or(0.0),
                    _ => 0.0,
                };
                let n = in_ty("in").components().max(1);
                if !(0.0..n as f64).contains(&i) {
                    self.note(
                        node,
                        format!("extract index {i} is outside 0..{n}; clamped"),
                    );
                }
                let i = i.clamp(0.0, (n - 1) as f64) as u8;
                let arg = self.input_or_default(index, node, "in");
                return one(self.emit(Op::Math(MathOp::Extract(i)), vec![arg], ValueType::Float));
            }
            "separate2" | "separate3" | "separate4" => {
                let arg = self.input_or_default(index, node, "in");
                return Some(
                    (0..node.outputs.len())
                        .map(|i| {
                            self.emit(
                                Op::Math(MathOp::Extract(i.min(3) as u8)),
                                vec![arg],
                                ValueType::Float,
                            )
                        })
                        .collect(),
                );
            }
            "combine2" | "combine3" | "combine4" => {
                let names = ["in1", "in2", "in3", "in4"];
                let mut counts = [0u8; 4];
                for (c, n) in counts.iter_mut().zip(names) {
                    *c = node.input(n).map_or(0, |i| i.ty.components().min(4) as u8);
                }
                let args = self.inputs(index, node, &names);
                return one(self.emit(Op::Math(MathOp::Combine(counts)), args, out_ty));
            }
            "artistic_ior" => {
                let args = self.inputs(index, node, &["reflectivity", "edge_color"]);
                return Some(
                    node.outputs
                        .iter()
                        .map(|(name, ty)| {
                            let op = MathOp::ArtisticIor {
                                extinction: name == "extinction",
                            };
                            self.emit(Op::Math(op), args.clone(), *ty)
                        })
                        .collect(),
                );
            }
            "texcoord" | "position" | "normal" | "tangent" | "bitangent" => {
                let geom = Geom::of_category(category).unwrap_or(Geom::Uv);
                let space = self.string(node, "space");
                if geom != Geom::Uv && space != "world" {
                    let s = if space.is_empty() {
                        "object"
                    } else {
                        space.as_str()
                    };
                    self.note(
                        node,
                        format!("{category} in space {s:?} is read in world space"),
                    );
                }
                if matches!(self.uniform(node, "index"), Some(Value::Numbers(v)) if v.first().is_some_and(|i| *i != 0.0))
                {
                    self.note(
                        node,
                        format!("{category} of a texture coordinate set other than 0 reads set 0"),
                    );
                }
                return one(self.emit_geom(geom, out_ty));
            }
            "geompropvalue" => {
                let name = self.string(node, "geomprop");
                let default = self.input_or_default(index, node, "default");
                if name.is_empty() {
                    return one(default);
                }
                if let Some((geom, _)) = Geom::of_geomprop(&name) {
                    return one(self.emit_geom(geom, out_ty));
                }
                let slot = self.primvar_slot(&name);
                return one(self.emit(Op::Primvar(slot), vec![default], out_ty));
            }
            "geompropvalueuniform" => {
                return one(self
                    .input(index, node, "default")
                    .unwrap_or(zero_of(out_ty)));
            }
            "image" | "tiledimage" => return one(self.image(index, node, out_ty)),
            _ => {}
        }
        None
    }

    /// A geometric quantity as a value of type `ty` (a vector2 of `UV0`, or a vector3 of a
    /// direction): the quantity itself when its canonical form already fits.
    fn emit_geom(&mut self, geom: Geom, ty: ValueType) -> Arg {
        let fits = match geom {
            Geom::Uv => ty == ValueType::Vector2,
            _ => matches!(ty, ValueType::Vector3 | ValueType::Color3),
        };
        if fits {
            Arg::Geom(geom)
        } else {
            let from = if geom == Geom::Uv {
                ValueType::Vector2
            } else {
                ValueType::Vector3
            };
            self.emit(
                Op::Math(MathOp::Convert { from, to: ty }),
                vec![Arg::Geom(geom)],
                ty,
            )
        }
    }

    /// The closure op of a pbrlib BSDF node.
    fn closure_op(&mut self, node: &GraphNode) -> Option<BsdfOp> {
        let retroreflective = self.flag(node, "retroreflective");
        let scatter = |c: &mut Compiler| {
            let s = c.string(node, "scatter_mode");
            match s.as_str() {
                "R" | "" => ScatterMode::R,
                "T" => ScatterMode::T,
                "RT" => ScatterMode::Rt,
                other => {
                    c.note(node, format!("scatter_mode {other:?} is unknown; R used"));
                    ScatterMode::R
                }
            }
        };
        let distribution = self.string(node, "distribution");
        if !distribution.is_empty() && distribution != "ggx" {
            self.note(
                node,
                format!("distribution {distribution:?} is read as ggx"),
            );
        }
        Some(match node.category.as_str() {
            "oren_nayar_diffuse_bsdf" => BsdfOp::OrenNayar {
                energy_compensation: self.flag(node, "energy_compensation"),
            },
            "burley_diffuse_bsdf" => BsdfOp::Burley,
            "translucent_bsdf" => BsdfOp::Translucent,
            "dielectric_bsdf" => BsdfOp::Dielectric {
                retroreflective,
                mode: scatter(self),
            },
            "conductor_bsdf" => BsdfOp::Conductor { retroreflective },
            "generalized_schlick_bsdf" => BsdfOp::GeneralizedSchlick {
                retroreflective,
                mode: scatter(self),
            },
            "sheen_bsdf" => BsdfOp::Sheen {
                mode: match self.string(node, "mode").as_str() {
                    "zeltner" => SheenMode::Zeltner,
                    "conty_kulla" | "" => SheenMode::ContyKulla,
                    other => {
                        self.note(
                            node,
                            format!("sheen mode {other:?} is unknown; conty_kulla used"),
                        );
                        SheenMode::ContyKulla
                    }
                },
            },
            "subsurface_bsdf" => BsdfOp::Subsurface,
            _ => return None,
        })
    }

    /// `image` and `tiledimage`.
    fn image(&mut self, index: usize, node: &GraphNode, ty: ValueType) -> Arg {
        let default = self.input_or_default(index, node, "default");
        let mut uv = self.input_or_default(index, node, "texcoord");
        let tiled = node.category == "tiledimage";
        let address = if tiled {
            // NG_tiledimage: ((texcoord·uvtiling − uvoffset)/realworldimagesize)·realworldtilesize,
            // periodic.
            let v2 = ValueType::Vector2;
            let tiling = self
                .input(index, node, "uvtiling")
                .unwrap_or(Arg::Const(DVec4::new(1.0, 1.0, 0.0, 0.0)));
            let offset = self
                .input(index, node, "uvoffset")
                .unwrap_or(Arg::Const(DVec4::ZERO));
            let image_size = self
                .input(index, node, "realworldimagesize")
                .unwrap_or(Arg::Const(DVec4::new(1.0, 1.0, 0.0, 0.0)));
            let tile_size = self
                .input(index, node, "realworldtilesize")
                .unwrap_or(Arg::Const(DVec4::new(1.0, 1.0, 0.0, 0.0)));
            uv = self.emit(Op::Math(MathOp::Multiply), vec![uv, tiling], v2);
            uv = self.emit(Op::Math(MathOp::Subtract), vec![uv, offset], v2);
            uv = self.emit(Op::Math(MathOp::Divide), vec![uv, image_size], v2);
            uv = self.emit(Op::Math(MathOp::Multiply), vec![uv, tile_size], v2);
            [Address::Periodic; 2]
        } else {
            let mut modes = [Address::Periodic; 2];
            for (m, name) in modes.iter_mut().zip(["uaddressmode", "vaddressmode"]) {
                let s = self.string(node, name);
                *m = Address::of(&s).unwrap_or_else(|| {
                    self.note(node, format!("{name} {s:?} is unknown; periodic used"));
                    Address::Periodic
                });
            }
            modes
        };
        let filter = self.string(node, "filtertype");
        if filter == "cubic" {
            self.note(node, "filtertype cubic is read as linear".to_owned());
        }
        if !self.string(node, "layer").is_empty() {
            self.note(
                node,
                "image layers are not supported; the file's first layer is read".to_owned(),
            );
        }
        if !self.string(node, "framerange").is_empty() {
            self.note(
                node,
                "frame ranges are not supported; the file is read as named".to_owned(),
            );
        }
        let Some(file) = self.file(node, "file") else {
            self.note(
                node,
                "file is not a constant filename; default used".to_owned(),
            );
            return default;
        };
        if file.asset.authored.is_empty() && file.asset.resolved.is_none() {
            return default;
        }
        let mut notes = Vec::new();
        let tex = self.textures.get(&file, &mut notes);
        for n in notes {
            self.note(node, n);
        }
        match tex {
            Ok(tex) => {
                let op = ImageOp {
                    tex,
                    address,
                    closest: filter == "closest",
                };
                self.emit(Op::Image(Box::new(op)), vec![uv, default], ty)
            }
            Err(e) => {
                self.note(node, format!("{e}; the image's default is used"));
                default
            }
        }
    }
}

/// The math op of a stdlib or pbrlib value node's category (`in_ty`: the type of an input by
/// name, `out_ty`: the node's output type); `None` for other categories.
fn math_op(category: &str, in_ty: impl Fn(&str) -> ValueType, out_ty: ValueType) -> Option<MathOp> {
    match category {
        "add" | "plus" => Some(MathOp::Add),
        "subtract" | "minus" => Some(MathOp::Subtract),
        "multiply" => Some(MathOp::Multiply),
        "divide" => Some(MathOp::Divide),
        "modulo" => Some(MathOp::Modulo),
        "power" => Some(MathOp::Power),
        "max" => Some(MathOp::Max),
        "min" => Some(MathOp::Min),
        "atan2" => Some(MathOp::Atan2),
        "invert" => Some(MathOp::Invert),
        "clamp" => Some(MathOp::Clamp),
        "mix" => Some(MathOp::Mix),
        "remap" => Some(MathOp::Remap),
        "smoothstep" => Some(MathOp::Smoothstep),
        "normalize" => Some(MathOp::Normalize),
        "magnitude" => Some(MathOp::Magnitude),
        "distance" => Some(MathOp::Distance),
        "dotproduct" => Some(MathOp::DotProduct),
        "crossproduct" => Some(MathOp::CrossProduct),
        "mincomponent" => Some(MathOp::MinComponent(in_ty("in").components() as u8)),
        "maxcomponent" => Some(MathOp::MaxComponent(in_ty("in").components() as u8)),
        "luminance" => Some(MathOp::Luminance),
        "rotate2d" => Some(MathOp::Rotate2d),
        "rotate3d" => Some(MathOp::Rotate3d),
        "ifgreater" => Some(MathOp::IfGreater),
        "ifgreatereq" => Some(MathOp::IfGreaterEq),
        "ifequal" => Some(MathOp::IfEqual),
        "convert" => Some(MathOp::Convert {
            from: in_ty("in"),
            to: out_ty,
        }),
        "normalmap" => Some(MathOp::Normalmap),
        "roughness_anisotropy" => Some(MathOp::RoughnessAnisotropy),
        "open_pbr_anisotropy" => Some(MathOp::OpenPbrAnisotropy),
        "and" => Some(MathOp::And),
        "or" => Some(MathOp::Or),
        "xor" => Some(MathOp::Xor),
        "not" => Some(MathOp::Not),
        c => Unary::of(c).map(MathOp::Unary),
    }
}
