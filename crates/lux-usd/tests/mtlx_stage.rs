//! `.mtlx` documents composed into USD stages in usdMtlx's layout (`lux_usd::mtlx::usdmtlx`).

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
