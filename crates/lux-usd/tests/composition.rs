//! Composition arcs real scenes use (`tests/data/scenes/compose/`): subLayers (strength
//! order), references with and without a prim target (defaultPrim), internal references,
//! layer offsets, payloads, inherits, `over`s, local and referenced variant selections,
//! instanceable prims, and asset paths resolved against the layer that authored them.

use glam::DVec3;
use lux_math::{LightKind, LightShape};
use lux_usd::{Light, Scene, UpAxis, load_stage};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn root() -> PathBuf {
    data().join("scenes/compose/root.usda")
}

fn load(frame: f64) -> Scene {
    load_stage(root(), frame).unwrap_or_else(|e| panic!("frame {frame}: {e}"))
}

fn light<'a>(s: &'a Scene, path: &str) -> &'a Light {
    s.light(path).unwrap_or_else(|| {
        let all: Vec<&str> = s.lights.iter().map(|l| l.path.as_str()).collect();
        panic!("no light {path}; lights: {all:?}")
    })
}

fn luxtest(name: &str) -> PathBuf {
    data().join("luxtest").join(name).canonicalize().unwrap()
}

fn same_file(p: Option<&PathBuf>, want: &Path) -> bool {
    p.and_then(|p| p.canonicalize().ok()).as_deref() == Some(want)
}

fn ies(l: &Light) -> &lux_usd::AssetRef {
    l.shaping
        .as_ref()
        .and_then(|s| s.ies_file.as_ref())
        .unwrap_or_else(|| panic!("{}: no IES file", l.path))
}

#[test]
fn the_composed_stage_has_exactly_the_defined_lights() {
    let s = load(1.0);
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    assert_eq!(s.up_axis, UpAxis::Z);
    assert_eq!(s.meters_per_unit, 1.0);
    assert_eq!(s.time_code_range, Some([1.0, 10.0]));
    let mut paths: Vec<&str> = s.lights.iter().map(|l| l.path.as_str()).collect();
    paths.sort_unstable();
    assert_eq!(
        paths,
        [
            "/Templates/DiskTemplate",
            "/World/Inherited",
            "/World/Instanced/Bulb",
            "/World/InternalRef",
            "/World/Payloaded/Bulb",
            "/World/RefDefault/Bulb",
            "/World/RefTarget/Bulb",
            "/World/RefVariant/Light",
            "/World/Shared",
            "/World/SubRect",
            "/World/Variant/L",
        ]
    );
    // `over "Ghost"` is never defined: its `def` child is not drawn; the class is abstract.
    assert!(s.light("/Ghost/Hidden").is_none());
}

#[test]
fn sublayers_and_overs() {
    let s = load(1.0);
    // Root layer (strongest) intensity 10 beats the sublayer's 20; the sublayer's radius shows.
    let shared = light(&s, "/World/Shared");
    assert_eq!(shared.params.intensity, 10.0);
    assert_eq!(shared.shape, LightShape::Sphere { radius: 3.0 });
    // An over in a sublayer overrides an opinion that arrives through a reference.
    let bulb = light(&s, "/World/RefDefault/Bulb");
    assert_eq!(bulb.params.intensity, 3.0);
    // A prim defined in a sublayer, under an `over` of a prim defined in the root layer.
    let sub = light(&s, "/World/SubRect");
    assert_eq!(sub.kind, LightKind::Rect);
}

#[test]
fn references_default_prim_targets_and_offsets() {
    let s = load(1.0);
    // No prim target → the layer's defaultPrim /Lamp, whose translate (1, 0, 0) applies.
    let bulb = light(&s, "/World/RefDefault/Bulb");
    assert_eq!(bulb.kind, LightKind::Sphere);
    assert_eq!(bulb.position(), DVec3::new(1.0, 0.0, 0.0));
    assert!(
        bulb.shaping.is_some(),
        "ShapingAPI applied in the referenced layer"
    );
    // Explicit prim target /OtherLamp: a DiskLight, under the referencing prim's translate.
    let t = light(&s, "/World/RefTarget/Bulb");
    assert_eq!(t.kind, LightKind::Disk);
    assert_eq!(t.position(), DVec3::new(0.0, 0.0, 5.0));
    // Internal reference to a prim of the same layer stack; it is a DiskLight by composition.
    let internal = light(&s, "/World/InternalRef");
    assert_eq!(internal.kind, LightKind::Disk);
    assert_eq!(internal.shape, LightShape::Disk { radius: 0.25 });
    // Inherits from a class: its opinions apply, the class itself is not drawn.
    let inh = light(&s, "/World/Inherited");
    assert_eq!(inh.shape, LightShape::Disk { radius: 0.75 });
    assert_eq!(inh.params.intensity, 4.0);
    // Instanceable reference: the instance's children are drawn.
    assert_eq!(light(&s, "/World/Instanced/Bulb").kind, LightKind::Disk);
}

#[test]
fn reference_layer_offsets_retime_samples() {
    // OtherLamp authors intensity 2 at 1 and 4 at 3; /World/RefTarget references it with
    // offset 100 (samples at 101 and 103), /World/Payloaded without an offset.
    for (frame, target, payloaded) in [
        (1.0, 2.0, 2.0),
        (2.0, 2.0, 3.0),
        (3.0, 2.0, 4.0),
        (102.0, 3.0, 4.0),
        (103.0, 4.0, 4.0),
    ] {
        let s = load(frame);
        assert_eq!(
            light(&s, "/World/RefTarget/Bulb").params.intensity,
            target,
            "RefTarget at {frame}"
        );
        assert_eq!(
            light(&s, "/World/Payloaded/Bulb").params.intensity,
            payloaded,
            "Payloaded at {frame}"
        );
    }
}

#[test]
fn payloads_are_loaded() {
    let s = load(2.0);
    let p = light(&s, "/World/Payloaded/Bulb");
    assert_eq!(p.kind, LightKind::Disk);
    assert_eq!(p.params.intensity, 3.0);
}

#[test]
fn variant_selections() {
    let s = load(1.0);
    // Local variant set, "big" selected.
    assert_eq!(
        light(&s, "/World/Variant/L").shape,
        LightShape::Sphere { radius: 2.0 }
    );
    // Variant set defined in the referenced layer (its own selection "sphere"), overridden
    // by the referencing prim's selection "rect".
    let v = light(&s, "/World/RefVariant/Light");
    assert_eq!(v.kind, LightKind::Rect);
    assert_eq!(
        v.shape,
        LightShape::Rect {
            width: 4.0,
            height: 1.0
        }
    );
}

#[test]
fn asset_paths_resolve_against_their_authoring_layer() {
    // Every asset below is written `../../../luxtest/…`, which only names tests/data/luxtest
    // from compose/layers/ or compose/refs/, not from the root layer's compose/.
    assert!(
        !data()
            .join("scenes/compose/../../../luxtest/bega_84693k4.ies")
            .exists()
    );
    let s = load(1.0);
    let sub = light(&s, "/World/SubRect");
    let tex = sub.texture.as_ref().expect("texture");
    assert_eq!(
        tex.authored,
        "../../../luxtest/04f377f94ce81cd7b5101fffdf571454.jpg"
    );
    assert!(
        same_file(
            tex.resolved.as_ref(),
            &luxtest("04f377f94ce81cd7b5101fffdf571454.jpg")
        ),
        "{tex:?}"
    );
    let bulb = ies(light(&s, "/World/RefDefault/Bulb"));
    assert!(
        same_file(bulb.resolved.as_ref(), &luxtest("bega_84693k4.ies")),
        "{bulb:?}"
    );
    // Time-sampled asset paths in a referenced layer, through the layer offset of 100:
    // sample 1 (→ 101) holds until sample 103 (→ 203).
    for (frame, target, payloaded) in [
        (2.0, "bega_84693k4.ies", "bega_84693k4.ies"),
        (103.0, "bega_84693k4.ies", "bega_omni002_4777lm.ies"),
        (203.0, "bega_omni002_4777lm.ies", "bega_omni002_4777lm.ies"),
    ] {
        let s = load(frame);
        let t = ies(light(&s, "/World/RefTarget/Bulb"));
        assert!(
            same_file(t.resolved.as_ref(), &luxtest(target)),
            "RefTarget at {frame}: {t:?}"
        );
        let p = ies(light(&s, "/World/Payloaded/Bulb"));
        assert!(
            same_file(p.resolved.as_ref(), &luxtest(payloaded)),
            "Payloaded at {frame}: {p:?}"
        );
    }
}
