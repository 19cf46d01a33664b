//! Material binding resolution (UsdShadeMaterialBindingAPI) against usd-core's
//! `ComputeBoundMaterial` on `tests/data/scenes/bindings.usda`: collection bindings, the
//! nearest prim, `strongerThanDescendants`, the `full` purpose, property order.

mod common;

use common::{bound_materials, listed};
use lux_usd::load_stage;
use std::path::PathBuf;

/// usd-core 26.11's bound material (purpose `full`) of every mesh, printed by
///
/// ```text
/// /work/venv-usd/bin/python - <<'EOF'
/// from pxr import Usd, UsdGeom, UsdShade
/// s = Usd.Stage.Open('crates/lux-usd/tests/data/scenes/bindings.usda')
/// for p in s.Traverse():
///     if p.IsA(UsdGeom.Mesh):
///         m, _ = UsdShade.MaterialBindingAPI(p).ComputeBoundMaterial(UsdShade.Tokens.full)
///         print(f'("{p.GetPath()}", "{m.GetPath() if m else None}"),')
/// EOF
/// ```
const USD_CORE: &[(&str, &str)] = &[
    ("/Root/A/G1", "/M/NearA"),
    ("/Root/A/G2", "/M/NearA"),
    ("/Root/B/G3", "/M/Two"),
    ("/Root/C/G4", "/M/NearC"),
    ("/Root/D/G7", "/M/Nine"),
    ("/Root/D/G8", "/M/Direct"),
    ("/Root/G5", "/M/Direct"),
    ("/S/G6", "/M/Strong"),
    ("/P/X/G", "/M/One"),
    ("/P/X/Y/H", "/M/NearY"),
    ("/F/X/G", "/M/Full"),
    ("/Q/G", "/M/One"),
];

#[test]
fn bound_materials_match_usd_core() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/bindings.usda");
    let scene = load_stage(p, 1.0).unwrap();
    assert_eq!(bound_materials(&scene), listed(USD_CORE));
}
