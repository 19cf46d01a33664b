//! `.mtlx` documents composed into USD stages in usdMtlx's layout (`lux_usd::mtlx::usdmtlx`).

use std::path::Path;

use lux_usd::WarningKind;

const SHADER_BALL: &str = "/work/shared/testdata/realusd/usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda";

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
    if !Path::new(SHADER_BALL).exists() {
        eprintln!("skipped: {SHADER_BALL} not present");
        return;
    }
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
