//! MaterialX shading graphs compiled and evaluated by `lux_render::material::graph`: hand-built
//! flattened graphs against the closed forms of `MaterialX.StandardNodes.md` and
//! `MaterialX.PBRSpec.md`, textures read from tiny PNG/EXR files written here.

use glam::{DVec2, DVec3, DVec4};
use lux_bsdf::{Closure, Node, NodeId};
use lux_render::image_io::srgb_to_linear;
use lux_render::material::graph::{GraphShader, Shaded, ShadingContext, TextureCache};
use lux_usd::AssetRef;
use lux_usd::shading::{FileValue, GraphInput, GraphNode, ShadingGraph, Source, Value, ValueType};
use std::path::PathBuf;

use ValueType::{Bsdf, Color3, Color4, Edf, Float, Integer, SurfaceShader, Vector2, Vector3};

// ---------------------------------------------------------------------------------------------
// Graph building helpers.

fn num(v: &[f64]) -> Source {
    Source::Value(Value::Numbers(v.to_vec()))
}

fn s(v: &str) -> Source {
    Source::Value(Value::String(v.to_owned()))
}

fn from(node: usize) -> Source {
    Source::Node { node, output: 0 }
}

fn geom(name: &str) -> Source {
    Source::Geomprop(name.to_owned())
}

fn node(category: &str, out: ValueType, inputs: &[(&str, ValueType, Source)]) -> GraphNode {
    GraphNode {
        name: format!("/Test/{category}"),
        category: category.to_owned(),
        nodedef: format!("ND_{category}_{}", out.name()),
        outputs: vec![("out".to_owned(), out)],
        inputs: inputs
            .iter()
            .map(|(n, ty, src)| GraphInput {
                name: (*n).to_owned(),
                ty: *ty,
                source: src.clone(),
            })
            .collect(),
    }
}

fn surface(bsdf: Source, edf: Source, opacity: f64) -> GraphNode {
    node(
        "surface",
        SurfaceShader,
        &[
            ("bsdf", Bsdf, bsdf),
            ("edf", Edf, edf),
            ("opacity", Float, num(&[opacity])),
            ("thin_walled", ValueType::Boolean, num(&[0.0])),
        ],
    )
}

fn graph(mut nodes: Vec<GraphNode>) -> ShadingGraph {
    // A graph whose last node is not a surface gets one reading nothing.
    if nodes.last().map(|n| n.category.as_str()) != Some("surface") {
        nodes.push(surface(s(""), s(""), 1.0));
    }
    ShadingGraph {
        material: "/World/Looks/Test".to_owned(),
        model: "ND_test".to_owned(),
        surface: Some((nodes.len() - 1, 0)),
        nodes,
        notes: Vec::new(),
    }
}

/// `nodes` followed by a conversion of node `value`'s output (of type `ty`) to colour and
/// an `oren_nayar_diffuse_bsdf` of that colour, the surface's only closure: the value is
/// the closure's colour ([`seen`]).
fn emitting(mut nodes: Vec<GraphNode>, value: usize, ty: ValueType) -> ShadingGraph {
    let mut colour = from(value);
    if ty != Color3 {
        nodes.push(node("convert", Color3, &[("in", ty, colour)]));
        colour = from(nodes.len() - 1);
    }
    nodes.push(node(
        "oren_nayar_diffuse_bsdf",
        Bsdf,
        &[
            ("weight", Float, num(&[1.0])),
            ("color", Color3, colour),
            ("roughness", Float, num(&[0.0])),
            ("normal", Vector3, geom("Nworld")),
        ],
    ));
    let bsdf = from(nodes.len() - 1);
    nodes.push(surface(bsdf, s(""), 1.0));
    graph(nodes)
}

/// The colour of the closure of a graph built by [`emitting`].
fn seen(shaded: Shaded) -> DVec3 {
    match shaded.bsdf.nodes().next() {
        Some(Node::Closure(Closure::OrenNayar { color, .. })) => *color,
        other => panic!("no observer closure: {other:?}"),
    }
}

fn ctx(uv: DVec2, primvars: &[DVec4]) -> ShadingContext<'_> {
    ShadingContext {
        p: DVec3::new(1.0, 2.0, 3.0),
        n: DVec3::Z,
        ng: DVec3::Z,
        t: DVec3::X,
        b: DVec3::Y,
        uv,
        primvars,
        wo: DVec3::new(0.0, 0.6, 0.8),
        entering: true,
    }
}

fn compile(g: &ShadingGraph) -> (GraphShader, Vec<String>) {
    let mut warnings = Vec::new();
    let shader = GraphShader::compile(g, &mut TextureCache::new(), &mut warnings);
    (shader, warnings)
}

/// The emission of a graph built by [`emitting`] at texture coordinates `uv`.
fn value_at(g: &ShadingGraph, uv: DVec2) -> DVec3 {
    let (shader, warnings) = compile(g);
    assert!(warnings.is_empty(), "{warnings:?}");
    seen(shader.eval(&ctx(uv, &[])))
}

fn assert_close(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).abs().max_element() < 1e-9, "{what}: {a} != {b}");
}

/// A unary/binary float node evaluated on constants and, through a texcoord-driven input, at
/// run time: both must give `expected`.
fn float_node(category: &str, inputs: &[(&str, f64)], expected: f64) {
    let ins: Vec<(&str, ValueType, Source)> = inputs
        .iter()
        .map(|(n, v)| (*n, Float, num(&[*v])))
        .collect();
    let folded = emitting(vec![node(category, Float, &ins)], 0, Float);
    let got = value_at(&folded, DVec2::ZERO);
    assert_close(got, DVec3::splat(expected), category);
    // The first input from the hit's u coordinate: the same value at run time.
    let mut nodes = vec![
        node("texcoord", Vector2, &[("index", Integer, num(&[0.0]))]),
        node(
            "extract",
            Float,
            &[("in", Vector2, from(0)), ("index", Integer, num(&[0.0]))],
        ),
    ];
    let mut ins2 = ins.clone();
    ins2[0].2 = from(1);
    nodes.push(node(category, Float, &ins2));
    let g = emitting(nodes, 2, Float);
    let (shader, _) = compile(&g);
    assert!(
        shader.value_instruction_count() > 0,
        "{category} should run per hit"
    );
    let got = seen(shader.eval(&ctx(DVec2::new(inputs[0].1, 0.0), &[])));
    assert_close(got, DVec3::splat(expected), category);
}

// ---------------------------------------------------------------------------------------------
// Math nodes.

#[test]
fn float_math_nodes_match_their_formulas() {
    float_node("add", &[("in1", 0.25), ("in2", 0.5)], 0.75);
    float_node("subtract", &[("in1", 0.25), ("in2", 0.5)], -0.25);
    float_node("multiply", &[("in1", 0.25), ("in2", 0.5)], 0.125);
    float_node("divide", &[("in1", 0.25), ("in2", 0.5)], 0.5);
    // modulo: in1 − in2·⌊in1/in2⌋.
    float_node("modulo", &[("in1", -0.25), ("in2", 1.0)], 0.75);
    float_node("modulo", &[("in1", 2.5), ("in2", 0.75)], 0.25);
    float_node("power", &[("in1", 0.5), ("in2", 3.0)], 0.125);
    float_node("sqrt", &[("in", 0.25)], 0.5);
    float_node("ln", &[("in", std::f64::consts::E)], 1.0);
    float_node("sign", &[("in", -0.3)], -1.0);
    float_node("sign", &[("in", 0.0)], 0.0);
    float_node("absval", &[("in", -0.3)], 0.3);
    float_node("floor", &[("in", -0.5)], -1.0);
    float_node("ceil", &[("in", 0.2)], 1.0);
    float_node("sin", &[("in", 0.5)], 0.5f64.sin());
    float_node("cos", &[("in", 0.5)], 0.5f64.cos());
    float_node("max", &[("in1", 0.25), ("in2", 0.5)], 0.5);
    float_node("min", &[("in1", 0.25), ("in2", 0.5)], 0.25);
    // invert: amount − in.
    float_node("invert", &[("in", 0.25), ("amount", 1.0)], 0.75);
    float_node("clamp", &[("in", 1.5), ("low", 0.0), ("high", 1.0)], 1.0);
    float_node("clamp", &[("in", -0.5), ("low", 0.0), ("high", 1.0)], 0.0);
    // mix: fg·mix + bg·(1 − mix).
    float_node("mix", &[("fg", 1.0), ("bg", 0.0), ("mix", 0.25)], 0.25);
    // remap: outlow + (in − inlow)(outhigh − outlow)/(inhigh − inlow).
    float_node(
        "remap",
        &[
            ("in", 0.5),
            ("inlow", 0.0),
            ("inhigh", 2.0),
            ("outlow", 1.0),
            ("outhigh", 3.0),
        ],
        1.5,
    );
    // smoothstep: t²(3 − 2t) with t = (in − low)/(high − low).
    float_node(
        "smoothstep",
        &[("in", 0.25), ("low", 0.0), ("high", 1.0)],
        0.15625,
    );
    float_node(
        "smoothstep",
        &[("in", 1.5), ("low", 0.0), ("high", 1.0)],
        1.0,
    );
}

#[test]
fn vector_math_nodes_match_their_formulas() {
    let c3 = |v: [f64; 3]| num(&v);
    // A colour times a float (multiply_color3FA) and a colour luminance.
    let g = emitting(
        vec![node(
            "multiply",
            Color3,
            &[
                ("in1", Color3, c3([0.2, 0.4, 0.6])),
                ("in2", Float, num(&[0.5])),
            ],
        )],
        0,
        Color3,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.1, 0.2, 0.3),
        "multiply FA",
    );
    let g = emitting(
        vec![node(
            "luminance",
            Color3,
            &[
                ("in", Color3, c3([1.0, 0.5, 0.25])),
                ("lumacoeffs", Color3, c3([0.2126, 0.7152, 0.0722])),
            ],
        )],
        0,
        Color3,
    );
    let l = 0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25;
    assert_close(value_at(&g, DVec2::ZERO), DVec3::splat(l), "luminance");
    // normalize, magnitude, dot, mincomponent.
    let v = [3.0, 0.0, 4.0];
    let g = emitting(
        vec![node("normalize", Vector3, &[("in", Vector3, c3(v))])],
        0,
        Vector3,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.6, 0.0, 0.8),
        "normalize",
    );
    let g = emitting(
        vec![node("magnitude", Float, &[("in", Vector3, c3(v))])],
        0,
        Float,
    );
    assert_close(value_at(&g, DVec2::ZERO), DVec3::splat(5.0), "magnitude");
    let g = emitting(
        vec![node(
            "dotproduct",
            Float,
            &[
                ("in1", Vector3, c3(v)),
                ("in2", Vector3, c3([1.0, 2.0, 3.0])),
            ],
        )],
        0,
        Float,
    );
    assert_close(value_at(&g, DVec2::ZERO), DVec3::splat(15.0), "dotproduct");
    let g = emitting(
        vec![node(
            "mincomponent",
            Float,
            &[("in", Color3, c3([0.7, 0.3, 0.5]))],
        )],
        0,
        Float,
    );
    assert_close(value_at(&g, DVec2::ZERO), DVec3::splat(0.3), "mincomponent");
    // rotate2d (mx_rotate_vector2): 90° takes (1, 0) to (0, −1).
    let g = emitting(
        vec![node(
            "rotate2d",
            Vector2,
            &[
                ("in", Vector2, num(&[1.0, 0.0])),
                ("amount", Float, num(&[90.0])),
            ],
        )],
        0,
        Vector2,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.0, -1.0, 0.0),
        "rotate2d",
    );
    // rotate3d (mx_rotate_vector3): in·c + (in × axis)·s + axis(axis·in)(1 − c); 90° about z
    // takes x to −y.
    let g = emitting(
        vec![node(
            "rotate3d",
            Vector3,
            &[
                ("in", Vector3, c3([1.0, 0.0, 0.0])),
                ("amount", Float, num(&[90.0])),
                ("axis", Vector3, c3([0.0, 0.0, 1.0])),
            ],
        )],
        0,
        Vector3,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.0, -1.0, 0.0),
        "rotate3d",
    );
}

#[test]
fn channel_nodes_convert_extract_combine_separate() {
    // convert float → color3 copies to every channel; vector2 → color3 pads with 0.
    let g = emitting(
        vec![node("convert", Color3, &[("in", Float, num(&[0.5]))])],
        0,
        Color3,
    );
    assert_close(value_at(&g, DVec2::ZERO), DVec3::splat(0.5), "float→color3");
    let g = emitting(
        vec![node(
            "convert",
            Color3,
            &[("in", Vector2, num(&[0.1, 0.2]))],
        )],
        0,
        Color3,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.1, 0.2, 0.0),
        "vector2→color3",
    );
    // convert vector2 → color4 gets alpha 1, extracted.
    let g = emitting(
        vec![
            node("convert", Color4, &[("in", Vector2, num(&[0.1, 0.2]))]),
            node(
                "extract",
                Float,
                &[("in", Color4, from(0)), ("index", Integer, num(&[3.0]))],
            ),
        ],
        1,
        Float,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::splat(1.0),
        "vector2→color4 alpha",
    );
    // convert integer → float, boolean → float.
    let g = emitting(
        vec![node("convert", Float, &[("in", Integer, num(&[3.0]))])],
        0,
        Float,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::splat(3.0),
        "integer→float",
    );
    // combine3 of separated channels in another order.
    let mut sep = node("separate3", Float, &[("in", Color3, num(&[0.1, 0.2, 0.3]))]);
    sep.outputs = vec![
        ("outr".into(), Float),
        ("outg".into(), Float),
        ("outb".into(), Float),
    ];
    let g = emitting(
        vec![
            sep,
            node(
                "combine3",
                Color3,
                &[
                    ("in1", Float, Source::Node { node: 0, output: 2 }),
                    ("in2", Float, Source::Node { node: 0, output: 0 }),
                    ("in3", Float, Source::Node { node: 0, output: 1 }),
                ],
            ),
        ],
        1,
        Color3,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(0.3, 0.1, 0.2),
        "separate/combine",
    );
    // combine2 of a colour and a float → color4.
    let g = emitting(
        vec![
            node(
                "combine2",
                Color4,
                &[
                    ("in1", Color3, num(&[0.1, 0.2, 0.3])),
                    ("in2", Float, num(&[0.9])),
                ],
            ),
            node(
                "extract",
                Float,
                &[("in", Color4, from(0)), ("index", Integer, num(&[3.0]))],
            ),
        ],
        1,
        Float,
    );
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::splat(0.9),
        "combine2 color4",
    );
}

#[test]
fn conditionals_select_by_their_comparisons() {
    let cond = |category: &str, v1: f64, v2: f64| {
        let g = emitting(
            vec![node(
                category,
                Float,
                &[
                    ("value1", Float, num(&[v1])),
                    ("value2", Float, num(&[v2])),
                    ("in1", Float, num(&[0.25])),
                    ("in2", Float, num(&[0.75])),
                ],
            )],
            0,
            Float,
        );
        value_at(&g, DVec2::ZERO).x
    };
    assert_eq!(cond("ifgreater", 1.0, 0.5), 0.25);
    assert_eq!(cond("ifgreater", 0.5, 0.5), 0.75);
    assert_eq!(cond("ifgreatereq", 0.5, 0.5), 0.25);
    assert_eq!(cond("ifgreatereq", 0.4, 0.5), 0.75);
    // switch: input ⌊which⌋ + 1, clamped to the inputs.
    let switch = |which: f64| {
        let mut ins: Vec<(String, ValueType, Source)> = (1..=5)
            .map(|i| (format!("in{i}"), Float, num(&[i as f64 / 10.0])))
            .collect();
        ins.push(("which".into(), Float, num(&[which])));
        let ins: Vec<(&str, ValueType, Source)> = ins
            .iter()
            .map(|(n, t, s)| (n.as_str(), *t, s.clone()))
            .collect();
        value_at(
            &emitting(vec![node("switch", Float, &ins)], 0, Float),
            DVec2::ZERO,
        )
        .x
    };
    assert_eq!(switch(0.0), 0.1);
    assert_eq!(switch(2.7), 0.3);
    assert_eq!(switch(9.0), 0.5);
    assert_eq!(switch(-1.0), 0.1);
    // A runtime comparison (u against 0.5) selects per hit.
    let g = emitting(
        vec![
            node("texcoord", Vector2, &[]),
            node(
                "extract",
                Float,
                &[("in", Vector2, from(0)), ("index", Integer, num(&[0.0]))],
            ),
            node(
                "ifgreater",
                Color3,
                &[
                    ("value1", Float, from(1)),
                    ("value2", Float, num(&[0.5])),
                    ("in1", Color3, num(&[1.0, 0.0, 0.0])),
                    ("in2", Color3, num(&[0.0, 0.0, 1.0])),
                ],
            ),
        ],
        2,
        Color3,
    );
    assert_eq!(value_at(&g, DVec2::new(0.7, 0.0)), DVec3::X);
    assert_eq!(value_at(&g, DVec2::new(0.3, 0.0)), DVec3::Z);
}

// ---------------------------------------------------------------------------------------------
// Geometry and primvars.

#[test]
fn geometric_nodes_and_primvars() {
    let g = emitting(
        vec![node(
            "position",
            Vector3,
            &[("space", ValueType::String, s("world"))],
        )],
        0,
        Vector3,
    );
    assert_eq!(value_at(&g, DVec2::ZERO), DVec3::new(1.0, 2.0, 3.0));
    // geompropvalue reads its slot, else its default.
    let g = emitting(
        vec![
            node(
                "geompropvalue",
                Color3,
                &[
                    ("geomprop", ValueType::String, s("tint")),
                    ("default", Color3, num(&[0.1, 0.2, 0.3])),
                ],
            ),
            node(
                "geompropvalue",
                Float,
                &[
                    ("geomprop", ValueType::String, s("rough")),
                    ("default", Float, num(&[0.5])),
                ],
            ),
            node(
                "multiply",
                Color3,
                &[("in1", Color3, from(0)), ("in2", Float, from(1))],
            ),
        ],
        2,
        Color3,
    );
    let (shader, _) = compile(&g);
    assert_eq!(shader.primvars(), ["tint", "rough"]);
    let with = [DVec4::new(1.0, 0.5, 0.25, 0.0), DVec4::splat(2.0)];
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &with))),
        DVec3::new(2.0, 1.0, 0.5),
        "primvars",
    );
    let missing = [DVec4::new(1.0, 0.5, 0.25, 0.0), DVec4::splat(f64::NAN)];
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &missing))),
        DVec3::new(0.5, 0.25, 0.125),
        "default",
    );
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &[]))),
        DVec3::new(0.05, 0.1, 0.15),
        "both defaults",
    );
}

#[test]
fn normalmap_follows_mx_normalmap() {
    // in (1, 0.5, 1) decodes to (1, 0, 1): normalize(T + N) with scale 1.
    let g = emitting(
        vec![node(
            "normalmap",
            Vector3,
            &[
                ("in", Vector3, num(&[1.0, 0.5, 1.0])),
                ("scale", Float, num(&[1.0])),
                ("normal", Vector3, geom("Nworld")),
                ("tangent", Vector3, geom("Tworld")),
                ("bitangent", Vector3, geom("Bworld")),
            ],
        )],
        0,
        Vector3,
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_close(
        value_at(&g, DVec2::ZERO),
        DVec3::new(h, 0.0, h),
        "normalmap",
    );
    // A flat normal folds to the shading normal: no instruction.
    let g = emitting(
        vec![node(
            "normalmap",
            Vector3,
            &[
                ("in", Vector3, num(&[0.5, 0.5, 1.0])),
                ("scale", Float, num(&[1.0])),
                ("normal", Vector3, geom("Nworld")),
                ("tangent", Vector3, geom("Tworld")),
                ("bitangent", Vector3, geom("Bworld")),
            ],
        )],
        0,
        Vector3,
    );
    let (shader, _) = compile(&g);
    assert_eq!(
        shader.value_instruction_count(),
        1,
        "only the colour conversion"
    );
    assert_eq!(seen(shader.eval(&ctx(DVec2::ZERO, &[]))), DVec3::Z);
}

// ---------------------------------------------------------------------------------------------
// Textures.

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lux-material-graph-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn file(path: &std::path::Path, colorspace: &str) -> Source {
    Source::Value(Value::File(FileValue {
        asset: AssetRef {
            authored: path.file_name().unwrap().to_string_lossy().into_owned(),
            resolved: Some(path.to_path_buf()),
        },
        colorspace: colorspace.to_owned(),
    }))
}

/// A 2×2 RGB PNG: top row red (200, 0, 0), green (0, 100, 0); bottom row blue (0, 0, 50),
/// white (255, 255, 255).
fn png_2x2(name: &str) -> PathBuf {
    let path = temp_dir().join(format!("{name}.png"));
    let px = vec![200, 0, 0, 0, 100, 0, 0, 0, 50, 255, 255, 255];
    image::RgbImage::from_raw(2, 2, px)
        .unwrap()
        .save(&path)
        .unwrap();
    path
}

fn image_graph(source: Source, u_mode: &str, v_mode: &str, filter: &str) -> ShadingGraph {
    emitting(
        vec![node(
            "image",
            Color3,
            &[
                ("file", ValueType::Filename, source),
                ("layer", ValueType::String, s("")),
                ("default", Color3, num(&[0.1, 0.2, 0.3])),
                ("texcoord", Vector2, geom("UV0")),
                ("uaddressmode", ValueType::String, s(u_mode)),
                ("vaddressmode", ValueType::String, s(v_mode)),
                ("filtertype", ValueType::String, s(filter)),
                ("framerange", ValueType::String, s("")),
                ("frameoffset", Integer, num(&[0.0])),
                ("frameendaction", ValueType::String, s("constant")),
            ],
        )],
        0,
        Color3,
    )
}

fn lin(code: u8) -> f64 {
    f64::from(srgb_to_linear(f32::from(code) / 255.0))
}

#[test]
fn image_reads_texels_with_address_modes_and_colour_spaces() {
    let png = png_2x2("image_reads");
    let g = image_graph(file(&png, ""), "periodic", "periodic", "linear");
    let (shader, warnings) = compile(&g);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(
        shader.value_instruction_count() > 0,
        "a texture lookup runs per hit"
    );
    let at = |uv: DVec2| seen(shader.eval(&ctx(uv, &[])));
    // Texel centres; (0, 0) is the lower left (blue), v = 0.75 the top row.
    let blue = DVec3::new(0.0, 0.0, lin(50));
    let red = DVec3::new(lin(200), 0.0, 0.0);
    let green = DVec3::new(0.0, lin(100), 0.0);
    let tol = 1e-6;
    assert!((at(DVec2::new(0.25, 0.25)) - blue).abs().max_element() < tol);
    assert!((at(DVec2::new(0.25, 0.75)) - red).abs().max_element() < tol);
    assert!((at(DVec2::new(0.75, 0.75)) - green).abs().max_element() < tol);
    // Periodic: one tile over is the same texel; halfway between red and green centres blends.
    assert!((at(DVec2::new(1.25, -0.25)) - red).abs().max_element() < tol);
    assert!(
        (at(DVec2::new(0.5, 0.75)) - (red + green) / 2.0)
            .abs()
            .max_element()
            < tol
    );
    // constant: the default outside [0, 1]; clamp: the edge texel; mirror: reflected.
    let g = image_graph(file(&png, ""), "constant", "clamp", "closest");
    let (shader, _) = compile(&g);
    let at = |uv: DVec2| seen(shader.eval(&ctx(uv, &[])));
    assert_eq!(at(DVec2::new(1.5, 0.5)), DVec3::new(0.1, 0.2, 0.3));
    assert!((at(DVec2::new(0.25, 7.0)) - red).abs().max_element() < tol);
    let g = image_graph(file(&png, ""), "mirror", "mirror", "closest");
    let (shader, _) = compile(&g);
    let at = |uv: DVec2| seen(shader.eval(&ctx(uv, &[])));
    assert!(
        (at(DVec2::new(1.25, 0.25)) - DVec3::ONE)
            .abs()
            .max_element()
            < tol
    );
    assert!((at(DVec2::new(-0.25, 0.25)) - blue).abs().max_element() < tol);
    // raw / lin_rec709: the codes as stored; g22_rec709: code^2.2.
    for (space, f) in [
        ("raw", (|c: u8| f64::from(c) / 255.0) as fn(u8) -> f64),
        ("lin_rec709", |c| f64::from(c) / 255.0),
        ("g22_rec709", |c| (f64::from(c) / 255.0).powf(2.2)),
        ("srgb_texture", lin),
    ] {
        let g = image_graph(file(&png, space), "periodic", "periodic", "closest");
        let (shader, warnings) = compile(&g);
        assert!(warnings.is_empty(), "{warnings:?}");
        let got = seen(shader.eval(&ctx(DVec2::new(0.25, 0.75), &[])));
        assert!(
            (got.x - f(200)).abs() < 1e-5,
            "{space}: {} vs {}",
            got.x,
            f(200)
        );
    }
}

#[test]
fn exr_textures_are_linear_unless_stated() {
    let path = temp_dir().join("texels.exr");
    exr::prelude::write_rgba_file(&path, 2, 2, |x, y| {
        let v = 0.25 + 0.5 * x as f32 + 0.125 * y as f32;
        (v, 0.5f32, 1.5f32, 1.0f32)
    })
    .unwrap();
    // uv (0.25, 0.75): column 0, top row (y = 0): 0.25.
    let at = |space: &str| {
        let g = image_graph(file(&path, space), "periodic", "periodic", "closest");
        let (shader, warnings) = compile(&g);
        assert!(warnings.is_empty(), "{warnings:?}");
        seen(shader.eval(&ctx(DVec2::new(0.25, 0.75), &[])))
    };
    assert_close(at(""), DVec3::new(0.25, 0.5, 1.5), "EXR default linear");
    let s = at("srgb_texture");
    assert!((s.x - f64::from(srgb_to_linear(0.25))).abs() < 1e-6);
    // acescg → Rec.709: grey stays grey (AP1 and Rec.709 share the white point here).
    let a = at("acescg");
    let m = [1.705050992658, -0.621792120657, -0.083258872001];
    assert!(
        (a.x - (m[0] * 0.25 + m[1] * 0.5 + m[2] * 1.5)).abs() < 1e-6,
        "{a}"
    );
}

#[test]
fn a_missing_texture_warns_and_uses_the_default() {
    let g = image_graph(
        file(std::path::Path::new("/no/such/file.png"), ""),
        "periodic",
        "periodic",
        "linear",
    );
    let (shader, warnings) = compile(&g);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("/World/Looks/Test"), "{warnings:?}");
    assert_eq!(shader.value_instruction_count(), 0);
    assert_eq!(
        seen(shader.eval(&ctx(DVec2::ZERO, &[]))),
        DVec3::new(0.1, 0.2, 0.3)
    );
}

#[test]
fn the_texture_cache_loads_a_file_once_per_colour_space() {
    let png = png_2x2("the_texture_cache");
    let mut cache = TextureCache::new();
    let mut warnings = Vec::new();
    for space in ["", "srgb_texture", "", "raw"] {
        GraphShader::compile(
            &image_graph(file(&png, space), "periodic", "periodic", "linear"),
            &mut cache,
            &mut warnings,
        );
    }
    // "" and srgb_texture are the same space for a PNG.
    assert_eq!(cache.len(), 2);
}

// ---------------------------------------------------------------------------------------------
// Folding.

#[test]
fn a_constant_chain_folds_to_no_instruction() {
    let g = emitting(
        vec![
            node(
                "multiply",
                Color3,
                &[
                    ("in1", Color3, num(&[0.2, 0.4, 0.8])),
                    ("in2", Float, num(&[0.5])),
                ],
            ),
            node(
                "power",
                Color3,
                &[("in1", Color3, from(0)), ("in2", Float, num(&[2.0]))],
            ),
            node(
                "add",
                Color3,
                &[
                    ("in1", Color3, from(1)),
                    ("in2", Color3, num(&[0.1, 0.1, 0.1])),
                ],
            ),
            node(
                "clamp",
                Color3,
                &[
                    ("in", Color3, from(2)),
                    ("low", Float, num(&[0.0])),
                    ("high", Float, num(&[0.2])),
                ],
            ),
        ],
        3,
        Color3,
    );
    let (shader, _) = compile(&g);
    assert_eq!(shader.value_instruction_count(), 0);
    assert_eq!(shader.instruction_count(), 1, "the closure");
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &[]))),
        DVec3::new(0.11, 0.14, 0.2),
        "folded",
    );
}

#[test]
fn a_texture_driven_chain_does_not_fold() {
    let png = png_2x2("a_texture_driven");
    let mut g = image_graph(file(&png, ""), "periodic", "periodic", "closest");
    // Scale the image by 2 before it is emitted.
    let mul = node(
        "multiply",
        Color3,
        &[("in1", Color3, from(0)), ("in2", Float, num(&[2.0]))],
    );
    g.nodes.insert(1, mul);
    // Re-point the observing closure (now node 2) at the multiply.
    g.nodes[2].inputs[1].source = from(1);
    g.nodes[3].inputs[0].source = from(2);
    g.surface = Some((3, 0));
    let (shader, _) = compile(&g);
    assert_eq!(shader.value_instruction_count(), 2, "image and multiply");
    let got = seen(shader.eval(&ctx(DVec2::new(0.75, 0.25), &[])));
    assert!((got - DVec3::splat(2.0)).abs().max_element() < 1e-6);
}

#[test]
fn unknown_nodes_warn_and_take_zero() {
    let g = emitting(
        vec![
            node("fancynoise3d", Color3, &[("amplitude", Float, num(&[1.0]))]),
            node(
                "add",
                Color3,
                &[
                    ("in1", Color3, from(0)),
                    ("in2", Color3, num(&[0.5, 0.5, 0.5])),
                ],
            ),
        ],
        1,
        Color3,
    );
    let (shader, warnings) = compile(&g);
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].contains("fancynoise3d") && warnings[0].contains("/World/Looks/Test"));
    assert_eq!(shader.unsupported().len(), 1);
    assert_eq!(seen(shader.eval(&ctx(DVec2::ZERO, &[]))), DVec3::splat(0.5));
}

/// A node lux does not evaluate gives what its nodedef states for that case (MaterialX
/// `stdlib_defs.mtlx`): `blur`'s output passes its `in` through (`defaultinput="in"`),
/// `heighttonormal`'s is the flat normal (0.5, 0.5, 1) (`default`), each with its note.
#[test]
fn unevaluated_nodes_take_their_nodedef_fallbacks() {
    let c = [0.2, 0.4, 0.6];
    let g = emitting(
        vec![node("blur", Color3, &[("in", Color3, num(&c))])],
        0,
        Color3,
    );
    let (shader, warnings) = compile(&g);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("blur"), "{warnings:?}");
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &[]))),
        DVec3::from_array(c),
        "blur passes its input through",
    );
    let g = emitting(
        vec![node(
            "heighttonormal",
            Vector3,
            &[("in", Float, num(&[0.3]))],
        )],
        0,
        Vector3,
    );
    let (shader, _) = compile(&g);
    assert_close(
        seen(shader.eval(&ctx(DVec2::ZERO, &[]))),
        DVec3::new(0.5, 0.5, 1.0),
        "heighttonormal's default",
    );
}

#[test]
fn malformed_graphs_do_not_panic() {
    // A forward connection, a missing output, no surface.
    let mut g = emitting(
        vec![node(
            "add",
            Color3,
            &[
                ("in1", Color3, from(5)),
                ("in2", Color3, Source::Node { node: 0, output: 7 }),
            ],
        )],
        0,
        Color3,
    );
    let (shader, warnings) = compile(&g);
    assert!(!warnings.is_empty());
    assert_eq!(seen(shader.eval(&ctx(DVec2::ZERO, &[]))), DVec3::ZERO);
    g.surface = None;
    let (shader, _) = compile(&g);
    let shaded = shader.eval(&ctx(DVec2::ZERO, &[]));
    assert_eq!(shaded.bsdf.nodes().count(), 0);
    assert_eq!(shaded.opacity, 1.0);
    g.surface = Some((99, 0));
    let (shader, _) = compile(&g);
    assert_eq!(shader.eval(&ctx(DVec2::ZERO, &[])).bsdf.nodes().count(), 0);
}

// ---------------------------------------------------------------------------------------------
// Closures.

fn oren_nayar(weight: f64, color: [f64; 3], roughness: f64) -> GraphNode {
    node(
        "oren_nayar_diffuse_bsdf",
        Bsdf,
        &[
            ("weight", Float, num(&[weight])),
            ("color", Color3, num(&color)),
            ("roughness", Float, num(&[roughness])),
            ("normal", Vector3, geom("Nworld")),
            ("energy_compensation", ValueType::Boolean, num(&[0.0])),
        ],
    )
}

fn dielectric(weight: f64) -> GraphNode {
    node(
        "dielectric_bsdf",
        Bsdf,
        &[
            ("weight", Float, num(&[weight])),
            ("tint", Color3, num(&[1.0, 1.0, 1.0])),
            ("ior", Float, num(&[1.5])),
            ("roughness", Vector2, num(&[0.1, 0.2])),
            ("retroreflective", ValueType::Boolean, num(&[0.0])),
            ("thinfilm_thickness", Float, num(&[0.0])),
            ("thinfilm_ior", Float, num(&[1.5])),
            ("normal", Vector3, geom("Nworld")),
            ("tangent", Vector3, geom("Tworld")),
            ("distribution", ValueType::String, s("ggx")),
            ("scatter_mode", ValueType::String, s("R")),
        ],
    )
}

fn layer(top: usize, base: usize) -> GraphNode {
    node(
        "layer",
        Bsdf,
        &[("top", Bsdf, from(top)), ("base", Bsdf, from(base))],
    )
}

#[test]
fn layer_of_dielectric_over_oren_nayar_builds_the_tree() {
    let g = graph(vec![
        oren_nayar(1.0, [0.8, 0.5, 0.2], 0.3),
        dielectric(1.0),
        layer(1, 0),
        surface(from(2), s(""), 1.0),
    ]);
    let (shader, warnings) = compile(&g);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(
        shader.value_instruction_count(),
        0,
        "constant inputs: closures only"
    );
    assert_eq!(shader.constant_lambert(), None);
    let shaded = shader.eval(&ctx(DVec2::ZERO, &[]));
    let nodes: Vec<Node> = shaded.bsdf.nodes().copied().collect();
    assert_eq!(nodes.len(), 3, "{nodes:?}");
    let frame = lux_bsdf::Frame::new(DVec3::Z, DVec3::X);
    assert_eq!(
        nodes[0],
        Node::Closure(Closure::OrenNayar {
            weight: 1.0,
            color: DVec3::new(0.8, 0.5, 0.2),
            roughness: 0.3,
            energy_compensation: false,
            frame,
        })
    );
    assert_eq!(
        nodes[1],
        Node::Closure(Closure::Dielectric {
            weight: 1.0,
            tint: DVec3::ONE,
            ior: 1.5,
            alpha: DVec2::new(0.1, 0.2),
            retroreflective: false,
            thinfilm: lux_bsdf::ThinFilm {
                thickness: 0.0,
                ior: 1.5
            },
            mode: lux_bsdf::ScatterMode::R,
            frame,
        })
    );
    assert_eq!(
        nodes[2],
        Node::Layer {
            top: NodeId(1),
            base: Some(NodeId(0))
        }
    );
    assert_eq!(shaded.opacity, 1.0);
    assert_eq!(shaded.emission, DVec3::ZERO);
    assert!(!shaded.thin_walled);
}

#[test]
fn zero_weight_closures_fold_away() {
    // A dielectric of weight 0 over a diffuse is the diffuse alone: a constant Lambertian.
    let g = graph(vec![
        oren_nayar(0.5, [0.8, 0.6, 0.4], 0.0),
        dielectric(0.0),
        layer(1, 0),
        surface(from(2), s(""), 1.0),
    ]);
    let (shader, _) = compile(&g);
    assert_eq!(shader.constant_lambert(), Some(DVec3::new(0.4, 0.3, 0.2)));
    let nodes: Vec<Node> = shader
        .eval(&ctx(DVec2::ZERO, &[]))
        .bsdf
        .nodes()
        .copied()
        .collect();
    assert_eq!(nodes.len(), 1);
}

#[test]
fn constant_lambert_only_for_pure_constant_diffuse() {
    let pure = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.0),
        surface(from(0), s(""), 1.0),
    ]);
    assert_eq!(compile(&pure).0.constant_lambert(), Some(DVec3::splat(0.5)));
    let rough = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.4),
        surface(from(0), s(""), 1.0),
    ]);
    assert_eq!(compile(&rough).0.constant_lambert(), None);
    let cutout = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.0),
        surface(from(0), s(""), 0.5),
    ]);
    assert_eq!(compile(&cutout).0.constant_lambert(), None);
    let glossy = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.0),
        dielectric(1.0),
        layer(1, 0),
        surface(from(2), s(""), 1.0),
    ]);
    assert_eq!(compile(&glossy).0.constant_lambert(), None);
    let glowing = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.0),
        node(
            "uniform_edf",
            Edf,
            &[("color", Color3, num(&[1.0, 1.0, 1.0]))],
        ),
        surface(from(0), from(1), 1.0),
    ]);
    assert_eq!(compile(&glowing).0.constant_lambert(), None);
    // A textured colour is not constant.
    let textured = graph(vec![
        node("texcoord", Vector2, &[]),
        node("convert", Color3, &[("in", Vector2, from(0))]),
        node(
            "oren_nayar_diffuse_bsdf",
            Bsdf,
            &[
                ("weight", Float, num(&[1.0])),
                ("color", Color3, from(1)),
                ("roughness", Float, num(&[0.0])),
                ("normal", Vector3, geom("Nworld")),
            ],
        ),
        surface(from(2), s(""), 1.0),
    ]);
    assert_eq!(compile(&textured).0.constant_lambert(), None);
}

#[test]
fn emission_edfs_and_combinators() {
    // generalized_schlick_edf: (r0 + (r90 − r0)(1 − cos θo)^q)·base, cos θo = wo·n = 0.8.
    let g = graph(vec![
        node(
            "uniform_edf",
            Edf,
            &[("color", Color3, num(&[2.0, 2.0, 2.0]))],
        ),
        node(
            "generalized_schlick_edf",
            Edf,
            &[
                ("color0", Color3, num(&[0.5, 0.5, 0.5])),
                ("color90", Color3, num(&[1.0, 1.0, 1.0])),
                ("exponent", Float, num(&[2.0])),
                ("base", Edf, from(0)),
            ],
        ),
        node(
            "multiply",
            Edf,
            &[("in1", Edf, from(1)), ("in2", Float, num(&[0.5]))],
        ),
        surface(s(""), from(2), 1.0),
    ]);
    let (shader, _) = compile(&g);
    let f = 0.5 + 0.5 * 0.2f64.powi(2);
    assert_close(
        shader.eval(&ctx(DVec2::ZERO, &[])).emission,
        DVec3::splat(f * 2.0 * 0.5),
        "schlick edf",
    );
    // mix of BSDFs with a runtime amount, and multiply by a colour.
    let g = graph(vec![
        oren_nayar(1.0, [0.5, 0.5, 0.5], 0.0),
        dielectric(1.0),
        node("texcoord", Vector2, &[]),
        node(
            "extract",
            Float,
            &[("in", Vector2, from(2)), ("index", Integer, num(&[0.0]))],
        ),
        node(
            "mix",
            Bsdf,
            &[
                ("fg", Bsdf, from(1)),
                ("bg", Bsdf, from(0)),
                ("mix", Float, from(3)),
            ],
        ),
        node(
            "multiply",
            Bsdf,
            &[
                ("in1", Bsdf, from(4)),
                ("in2", Color3, num(&[1.0, 0.5, 0.25])),
            ],
        ),
        surface(from(5), s(""), 1.0),
    ]);
    let (shader, _) = compile(&g);
    let nodes: Vec<Node> = shader
        .eval(&ctx(DVec2::new(0.3, 0.0), &[]))
        .bsdf
        .nodes()
        .copied()
        .collect();
    assert_eq!(nodes.len(), 4);
    assert_eq!(
        nodes[2],
        Node::Mix {
            fg: Some(NodeId(1)),
            bg: Some(NodeId(0)),
            mix: 0.3
        }
    );
    assert_eq!(
        nodes[3],
        Node::Multiply {
            a: NodeId(2),
            weight: DVec3::new(1.0, 0.5, 0.25)
        }
    );
}

#[test]
fn pbr_helpers_feed_closures() {
    // roughness_anisotropy(0.5, 0.75) = (0.25/0.5, 0.25·0.5); artistic_ior feeds a conductor.
    let mut ior = node(
        "artistic_ior",
        Color3,
        &[
            ("reflectivity", Color3, num(&[0.9, 0.5, 0.04])),
            ("edge_color", Color3, num(&[1.0, 1.0, 1.0])),
        ],
    );
    ior.outputs = vec![("ior".into(), Color3), ("extinction".into(), Color3)];
    let g = graph(vec![
        node(
            "roughness_anisotropy",
            Vector2,
            &[
                ("roughness", Float, num(&[0.5])),
                ("anisotropy", Float, num(&[0.75])),
            ],
        ),
        ior,
        node(
            "conductor_bsdf",
            Bsdf,
            &[
                ("weight", Float, num(&[1.0])),
                ("ior", Color3, Source::Node { node: 1, output: 0 }),
                ("extinction", Color3, Source::Node { node: 1, output: 1 }),
                ("roughness", Vector2, from(0)),
                ("normal", Vector3, geom("Nworld")),
                ("tangent", Vector3, geom("Tworld")),
            ],
        ),
        surface(from(2), s(""), 1.0),
    ]);
    let (shader, warnings) = compile(&g);
    assert!(warnings.is_empty(), "{warnings:?}");
    let nodes: Vec<Node> = shader
        .eval(&ctx(DVec2::ZERO, &[]))
        .bsdf
        .nodes()
        .copied()
        .collect();
    let Node::Closure(Closure::Conductor {
        ior,
        extinction,
        alpha,
        ..
    }) = nodes[0]
    else {
        panic!("{nodes:?}");
    };
    assert!((alpha - DVec2::new(0.5, 0.125)).abs().max_element() < 1e-12);
    // White edge colour: n = (1 − r)/(1 + r).
    let r = DVec3::new(0.9, 0.5, 0.04);
    assert!((ior - (1.0 - r) / (1.0 + r)).abs().max_element() < 1e-12);
    let k2 = ((ior + 1.0) * (ior + 1.0) * r - (ior - 1.0) * (ior - 1.0)) / (1.0 - r);
    assert!(
        (extinction - k2.max(DVec3::ZERO).map(f64::sqrt))
            .abs()
            .max_element()
            < 1e-12
    );
}

#[test]
fn tiledimage_tiles_and_offsets() {
    // ((uv·uvtiling − uvoffset)/realworldimagesize)·realworldtilesize, periodic: uv (0.125,
    // 0.125) tiled 2× is (0.25, 0.25), the lower-left texel (blue); offset by (0.5, 0) it is
    // (−0.25, 0.25) → (0.75, 0.25), the lower-right texel (white).
    let png = png_2x2("tiledimage_tiles_and_offsets");
    let tiled = |offset: [f64; 2]| {
        emitting(
            vec![node(
                "tiledimage",
                Color3,
                &[
                    ("file", ValueType::Filename, file(&png, "")),
                    ("default", Color3, num(&[0.1, 0.2, 0.3])),
                    ("texcoord", Vector2, geom("UV0")),
                    ("uvtiling", Vector2, num(&[2.0, 2.0])),
                    ("uvoffset", Vector2, num(&offset)),
                    ("realworldimagesize", Vector2, num(&[1.0, 1.0])),
                    ("realworldtilesize", Vector2, num(&[1.0, 1.0])),
                    ("filtertype", ValueType::String, s("closest")),
                ],
            )],
            0,
            Color3,
        )
    };
    let blue = DVec3::new(0.0, 0.0, lin(50));
    let got = value_at(&tiled([0.0, 0.0]), DVec2::splat(0.125));
    assert!((got - blue).abs().max_element() < 1e-6, "{got}");
    let got = value_at(&tiled([0.5, 0.0]), DVec2::splat(0.125));
    assert!((got - DVec3::ONE).abs().max_element() < 1e-6, "{got}");
}
