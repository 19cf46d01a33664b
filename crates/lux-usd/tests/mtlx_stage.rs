//! `.mtlx` documents composed into USD stages in usdMtlx's layout (`lux_usd::mtlx::usdmtlx`).

mod common;

use common::{bound_materials, listed};
use std::path::Path;

use lux_usd::WarningKind;

/// The StandardShaderBall as the workspace's own tests keep it (`tests/data/realusd/`, CC BY
/// 4.0, see its LICENCE there).
const SHADER_BALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/data/realusd/usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda"
);

#[test]
fn translated_documents_are_usda() {
    for f in [
        "gold.mtlx",
        "graph.mtlx",
        "upgrade_138.mtlx",
        "glass_openpbr.mtlx",
    ] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/mtlx")
            .join(f);
        let doc = lux_usd::mtlx::read_document(&path).unwrap();
        let text = lux_usd::mtlx::usdmtlx::to_usda(&doc);
        openusd::usda::parse(&text).unwrap_or_else(|e| panic!("{f}: {e:#}\n{text}"));
        for m in doc.materials() {
            assert!(text.contains(&format!("def Material \"{m}\"")), "{f}");
        }
    }
}

#[test]
fn shader_ball_mtlx_references_compose() {
    let scene = lux_usd::load_stage(SHADER_BALL, 1.0).unwrap();
    let composition: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Composition || w.message.contains(".mtlx"))
        .collect();
    assert!(composition.is_empty(), "{composition:#?}");
}

#[test]
fn stage_with_mtlx_arcs_loads_without_composition_warnings() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/stage.usda");
    let scene = lux_usd::load_stage(&path, 1.0).unwrap();
    let composition: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Composition)
        .collect();
    assert!(composition.is_empty(), "{composition:#?}");
}

#[test]
fn a_malformed_document_is_a_composition_warning_with_its_line() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/stage_bad.usda");
    let scene = lux_usd::load_stage(&path, 1.0).unwrap();
    let w = scene
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::Composition)
        .expect("a composition warning");
    assert_eq!(w.prim, "/L");
    assert!(
        w.message.contains("bad.mtlx:4:1: not well-formed XML"),
        "{}",
        w.message
    );
}

/// A `.mtlx` document as a sublayer composes too: its materials are prims of the stage, and a
/// binding to one reaches its graph.
#[test]
fn a_mtlx_sublayer_composes() {
    let dir = std::env::temp_dir().join(format!("lux-mtlx-sublayer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let gold = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/gold.mtlx");
    let stage = dir.join("stage.usda");
    std::fs::write(
        &stage,
        format!(
            "#usda 1.0\n(\n    subLayers = [@{}@]\n)\ndef Mesh \"Quad\" (prepend apiSchemas = \
             [\"MaterialBindingAPI\"])\n{{\n    rel material:binding = \
             </MaterialX/Materials/gold>\n    uniform token subdivisionScheme = \"none\"\n    \
             int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n    \
             point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n}}\n",
            gold.display()
        ),
    )
    .unwrap();
    let scene = lux_usd::load_stage(&stage, 1.0).unwrap();
    assert!(scene.warnings.is_empty(), "{:#?}", scene.warnings);
    let m = &scene.materials[scene.meshes[0].material.expect("bound")];
    assert_eq!(m.path, "/MaterialX/Materials/gold");
    let g = m.graph.as_ref().expect("a graph");
    assert_eq!(g.model, "ND_standard_surface_surfaceshader");
    assert!(g.nodes.iter().any(|n| n.category == "conductor_bsdf"));
}

/// usd-core 26.11's bound materials for `tests/data/mtlx/looks.usda`, computed on lux's
/// translation of `graph.mtlx` (usd-core's PyPI wheels have no usdMtlx), printed by
///
/// ```text
/// cargo run -p lux-usd --example mtlx_to_usda -- crates/lux-usd/tests/data/mtlx/graph.mtlx \
///     > /tmp/graph.usda
/// sed 's/graph.mtlx/graph.usda/' crates/lux-usd/tests/data/mtlx/looks.usda > /tmp/looks.usda
/// /work/venv-usd/bin/python - <<'EOF'
/// from pxr import Usd, UsdGeom, UsdShade
/// s = Usd.Stage.Open('/tmp/looks.usda')
/// for p in s.Traverse():
///     if p.IsA(UsdGeom.Mesh):
///         m, _ = UsdShade.MaterialBindingAPI(p).ComputeBoundMaterial(UsdShade.Tokens.full)
///         print(f'("{p.GetPath()}", "{m.GetPath() if m else None}"),')
/// EOF
/// ```
const LOOK_BINDINGS: &[(&str, &str)] = &[
    ("/Asset/World/Table", "/Asset/Materials/MA_wood"),
    ("/Asset/World/Chair", "/Asset/Materials/MA_wood"),
    ("/Asset/World/Props/Box", "/Asset/Materials/MA_preview"),
    ("/Asset/World/Props/Lamp", "None"),
    ("/Asset/World/Floor", "None"),
];

/// A look's `<materialassign>`s bind its materials through the collections usdMtlx makes of
/// `geom` and `<collection>`, and the Material's interface inputs (where usdMtlx authors the
/// document's values) take overrides from the referencing layer.
#[test]
fn a_look_binds_its_materials_and_interface_inputs_take_overrides() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/looks.usda");
    let scene = lux_usd::load_stage(&path, 1.0).unwrap();
    let composition: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Composition)
        .collect();
    assert!(composition.is_empty(), "{composition:#?}");
    assert_eq!(bound_materials(&scene), listed(LOOK_BINDINGS));

    let wood = scene
        .materials
        .iter()
        .find(|m| m.path == "/Asset/Materials/MA_wood")
        .unwrap();
    let g = wood.graph.as_ref().expect("a graph");
    assert_eq!(g.model, "ND_standard_surface_surfaceshader");
    // The overridden interface input reaches the shader: coat 0.75, not the document's 0.25.
    let net = wood.network.as_ref().expect("a network");
    let surface = &net.nodes[net.surface.as_ref().unwrap().node];
    let coat = surface.inputs.iter().find(|i| i.name == "coat").unwrap();
    assert_eq!(
        coat.source,
        lux_usd::shading::NetSource::Value(lux_usd::shading::Value::Numbers(vec![0.75]))
    );
    // An interface input the document leaves unauthored is not an authored input of the
    // shader (the nodedef default applies).
    assert!(surface.inputs.iter().all(|i| i.name != "base"));
    // The nodegraph referenced beneath the material feeds base_color.
    let base = surface
        .inputs
        .iter()
        .find(|i| i.name == "base_color")
        .unwrap();
    assert!(matches!(
        base.source,
        lux_usd::shading::NetSource::Connection(_)
    ));
}

/// A `.mtlx` document inside a `.usdz` package composes as it does on disk, and the asset
/// paths it holds resolve inside the package (`looks.usdz[textures/wood.ppm]`), not against
/// the package's directory — even where that directory has a file of the same name.
/// `looks.usdz` packs `looks.usda` (as `scene.usda`), `graph.mtlx` and `textures/wood.ppm`.
#[test]
fn a_mtlx_document_inside_a_usdz_composes_and_resolves_inside_the_package() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/looks.usdz");
    let scene = lux_usd::load_stage(&path, 1.0).unwrap();
    assert_eq!(bound_materials(&scene), listed(LOOK_BINDINGS));
    let wood = scene
        .materials
        .iter()
        .find(|m| m.path == "/Asset/Materials/MA_wood")
        .unwrap();
    let net = wood.network.as_ref().unwrap();
    let grain = net
        .nodes
        .iter()
        .find(|n| n.name.ends_with("NG_wood/grain"))
        .unwrap();
    let file = grain.inputs.iter().find(|i| i.name == "file").unwrap();
    let lux_usd::shading::NetSource::Value(lux_usd::shading::Value::File(f)) = &file.source else {
        panic!("{file:?}");
    };
    let resolved = f
        .asset
        .resolved
        .as_ref()
        .expect("resolves")
        .to_string_lossy();
    assert!(
        resolved.ends_with("looks.usdz[textures/wood.ppm]"),
        "{resolved}"
    );
}

/// usd-core 26.11's bound materials for `tests/data/mtlx/looks_inherit.usda` on lux's
/// translation of `looks_inherit.mtlx` (printed as for [`LOOK_BINDINGS`], with
/// `looks_inherit` for `graph`/`looks`): the selected look `L_blue` inherits `L_base`'s
/// assigns; its own come first (a table collection that excludes the top and includes the
/// legs' collection); `L_base`'s `geomprefix` applies to its `geom` paths.
const INHERITED_LOOK_BINDINGS: &[(&str, &str)] = &[
    ("/Asset/Set/Table/Top", "/Asset/Materials/MA_top"),
    ("/Asset/Set/Table/Legs/Leg1", "/Asset/Materials/MA_table"),
    ("/Asset/Set/Table/Apron", "/Asset/Materials/MA_table"),
    ("/Asset/Set/Chair", "/Asset/Materials/MA_chair2"),
    ("/Asset/Set/Lamp", "None"),
];

#[test]
fn an_inherited_look_binds_as_usd_core_binds_its_translation() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mtlx/looks_inherit.usda");
    let scene = lux_usd::load_stage(&path, 1.0).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .all(|w| w.kind != WarningKind::Composition),
        "{:#?}",
        scene.warnings
    );
    assert_eq!(bound_materials(&scene), listed(INHERITED_LOOK_BINDINGS));
    // MA_table is the blue material (0.1, 0.1, 0.8), MA_top the red one (0.8, 0.1, 0.1), as
    // color3f values.
    let colour = |path: &str| -> Vec<f64> {
        let m = scene.materials.iter().find(|m| m.path == path).unwrap();
        let net = m.network.as_ref().unwrap();
        let sr = &net.nodes[net.surface.as_ref().unwrap().node];
        match &sr
            .inputs
            .iter()
            .find(|i| i.name == "base_color")
            .unwrap()
            .source
        {
            lux_usd::shading::NetSource::Value(lux_usd::shading::Value::Numbers(v)) => v.clone(),
            other => panic!("{other:?}"),
        }
    };
    let f = |x: f32| f64::from(x);
    assert_eq!(
        colour("/Asset/Materials/MA_table"),
        [f(0.1), f(0.1), f(0.8)]
    );
    assert_eq!(colour("/Asset/Materials/MA_top"), [f(0.8), f(0.1), f(0.1)]);
}
