//! Bad input: a missing or malformed root layer is a typed error naming the file; unresolved
//! and malformed arcs and cycles are composition warnings naming the arc, the layer that
//! authored it and the prim (usd-core's policy: the stage composes without the arc), and typed
//! errors in a strict load; renderer-specific attributes and unknown prim types are ignored
//! without a warning; absurd sizes hit the limits; nothing panics.

use lux_usd::{LoadError, LoadOptions, WarningKind, load_stage, load_usda_str};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

fn bad(name: &str) -> PathBuf {
    scenes().join("bad").join(name)
}

fn strict() -> LoadOptions {
    let mut o = LoadOptions::default();
    o.strict = true;
    o
}

/// Loads `file` strictly expecting a composition error; returns (layer, prim, message) after
/// checking that the error names the root file and the prim in its text, and that the default
/// (usd-core) policy loads the stage with the same problem as a composition warning.
#[track_caller]
fn composition_error(file: &Path) -> (String, String, String) {
    let (layer, prim, message) = strict_composition_error(file);
    let s = load_stage(file, 1.0).expect("the default policy composes the rest");
    let w = s
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::Composition && w.prim == prim)
        .unwrap_or_else(|| panic!("no composition warning at {prim}: {:#?}", s.warnings));
    assert!(w.message.contains(&message), "{w}");
    assert!(w.message.contains(&layer), "{w}");
    assert!(w.message.ends_with("composed without it"), "{w}");
    (layer, prim, message)
}

#[track_caller]
fn strict_composition_error(file: &Path) -> (String, String, String) {
    match lux_usd::load_stage_with(file, 1.0, &strict()) {
        Err(e @ LoadError::Composition { .. }) => {
            let text = e.to_string();
            let LoadError::Composition {
                file: f,
                layer,
                prim,
                message,
            } = e
            else {
                unreachable!()
            };
            assert_eq!(f, file);
            assert!(text.contains(&file.display().to_string()), "{text}");
            assert!(text.contains(&format!("<{prim}>")), "{text}");
            (layer, prim, message)
        }
        Err(e) => panic!(
            "{}: expected a composition error, got {e:?}",
            file.display()
        ),
        Ok(s) => panic!(
            "{}: loaded ({} lights, warnings {:?})",
            file.display(),
            s.lights.len(),
            s.warnings
        ),
    }
}

#[test]
fn missing_file() {
    let f = bad("no_such_file.usda");
    match load_stage(&f, 1.0) {
        Err(e @ LoadError::NotFound { .. }) => {
            assert!(e.to_string().contains("no_such_file.usda"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    // a directory is not a layer either, and the error says so
    match load_stage(scenes(), 1.0) {
        Err(e @ LoadError::IsDirectory { .. }) => {
            assert!(e.to_string().contains("is a directory"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unresolved_reference() {
    let (layer, prim, message) = composition_error(&bad("unresolved_ref.usda"));
    assert_eq!(prim, "/World/A");
    assert!(layer.ends_with("unresolved_ref.usda"), "{layer}");
    assert!(message.contains("does_not_exist.usda"), "{message}");
}

#[test]
fn reference_to_a_missing_prim_or_default_prim() {
    let (layer, prim, message) = composition_error(&bad("missing_prim.usda"));
    assert_eq!(prim, "/Holder");
    assert!(layer.ends_with("missing_prim.usda"), "{layer}");
    assert!(message.contains("NoSuchPrim"), "{message}");
    let (_, prim, message) = composition_error(&bad("no_default_prim.usda"));
    assert_eq!(prim, "/Holder");
    assert!(message.contains("target.usda"), "{message}");
    // an internal reference to a prim that does not exist
    let text = "#usda 1.0\ndef Xform \"A\" (\n    prepend references = </Nope>\n)\n{\n}\n";
    match load_usda_str(text, 1.0, &strict()) {
        Err(LoadError::Composition { prim, message, .. }) => {
            assert_eq!(prim, "/A");
            assert!(message.contains("/Nope"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let s = load_usda_str(text, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.prim_count, 1, "/A is composed without the reference");
    assert!(
        s.warnings.iter().any(|w| w.kind == WarningKind::Composition
            && w.prim == "/A"
            && w.message.contains("/Nope")),
        "{:#?}",
        s.warnings
    );
}

#[test]
fn malformed_layers() {
    // The root layer itself: no prim exists yet; the parser's diagnostic names the file, the
    // line and the column (line 8 ends after `=`, and the `}` of line 9 is not a value).
    let f = bad("malformed.usda");
    let at = format!("{}:9:1: Expected a number", f.display());
    match load_stage(&f, 1.0) {
        Err(e @ LoadError::Malformed { .. }) => {
            assert!(e.to_string().contains(&at), "{e}");
        }
        other => panic!("{other:?}"),
    }
    // A referenced layer: the referencing prim is named, and the position in the bad layer.
    let (layer, prim, message) = composition_error(&bad("ref_malformed.usda"));
    assert_eq!(prim, "/Holder");
    assert!(layer.ends_with("ref_malformed.usda"), "{layer}");
    assert!(message.contains(&at), "{message}");
    // A sublayer: a layer-stack error, prim "/".
    let f = bad("malformed_sublayer.usda");
    match lux_usd::load_stage_with(&f, 1.0, &strict()) {
        Err(LoadError::Composition {
            prim,
            layer,
            message,
            ..
        }) => {
            assert_eq!(prim, "/");
            assert!(layer.ends_with("malformed_sublayer.usda"), "{layer}");
            assert!(message.contains(&at), "{message}");
        }
        Err(e @ LoadError::Malformed { .. }) => {
            assert!(e.to_string().contains("malformed"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unresolved_sublayer() {
    let (layer, prim, message) = composition_error(&bad("unresolved_sublayer.usda"));
    assert_eq!(prim, "/");
    assert!(layer.ends_with("unresolved_sublayer.usda"), "{layer}");
    assert!(message.contains("no_such_sublayer.usda"), "{message}");
}

#[test]
fn cycles() {
    let (layer, prim, message) = composition_error(&bad("cycle_a.usda"));
    assert_eq!(prim, "/A");
    assert!(layer.ends_with("cycle_a.usda"), "{layer}");
    assert!(message.contains("cycle"), "{message}");
    let (_, prim, message) = composition_error(&bad("internal_cycle.usda"));
    assert!(prim == "/A" || prim == "/B", "{prim}");
    assert!(message.contains("cycle"), "{message}");
    let (_, prim, message) = composition_error(&bad("sublayer_cycle_a.usda"));
    assert_eq!(prim, "/");
    assert!(message.contains("cycle"), "{message}");
}

#[test]
fn renderer_specific_attributes_and_unknown_types_are_silent() {
    let s = load_stage(scenes().join("renderer_specific.usda"), 1.0).unwrap();
    // the one warning: the 2-vertex cubic (bezier by fallback) curve, drawn as Storm draws it;
    // the curve and the points are counted and drawn
    assert_eq!(s.warnings.len(), 1, "{:#?}", s.warnings);
    assert_eq!(s.warnings[0].kind, WarningKind::InvalidGeometry);
    assert_eq!(s.warnings[0].prim, "/Typeless/Child/Hair");
    assert!(
        s.warnings[0].message.contains("fewer than 4 vertices"),
        "{}",
        s.warnings[0]
    );
    assert_eq!((s.gprims.curves, s.gprims.points), (1, 1));
    assert!(s.gprims.skipped.is_empty());
    assert_eq!((s.drawn.curves, s.drawn.points), (1, 1));
    let panel = s.light("/Panel").unwrap();
    assert_eq!(
        panel.shape,
        lux_math::LightShape::Rect {
            width: 2.0,
            height: 1.0
        }
    );
    assert!(
        !panel.params.normalize,
        "arnold:normalize is not inputs:normalize"
    );
    assert_eq!(panel.shaping.as_ref().unwrap().cone_angle_deg, 30.0);
    assert!(panel.physical.is_none() && panel.emission_spectrum.is_none());
    assert_eq!(s.cameras.len(), 1);
    assert_eq!(s.cameras[0].focal_length, 20.0);
    assert_eq!(s.render_settings[0].resolution(), [64, 32]);
    // The mesh, the sphere under the unknown-typed prim, the points and the curve are drawn.
    let mut drawn: Vec<&str> = s.meshes.iter().map(|m| m.path.as_str()).collect();
    drawn.sort_unstable();
    assert_eq!(
        drawn,
        [
            "/Tri",
            "/Typeless/Child/Hair",
            "/Typeless/Child/Particles",
            "/Unknown/InsideUnknown"
        ]
    );
}

#[test]
fn wrong_attribute_type_names_file_prim_and_attribute() {
    let text = "#usda 1.0\ndef SphereLight \"L\"\n{\n    string inputs:intensity = \"bright\"\n}\n";
    // usd-core opens it without complaint: a warning, and the schema default
    let s = load_usda_str(text, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.light("/L").unwrap().params.intensity, 1.0);
    assert_eq!(s.warnings.len(), 1, "{:#?}", s.warnings);
    assert_eq!(s.warnings[0].prim, "/L");
    assert_eq!(s.warnings[0].kind, WarningKind::InvalidValue);
    assert!(
        s.warnings[0]
            .message
            .starts_with("inputs:intensity: expected a number, found String"),
        "{}",
        s.warnings[0]
    );
    // a strict load refuses it, naming the file, the prim and the attribute
    match load_usda_str(text, 1.0, &strict()) {
        Err(e @ LoadError::AttributeType { .. }) => {
            let t = e.to_string();
            assert!(t.contains("<stage.usda") || t.contains("stage.usda"), "{t}");
            assert!(t.contains("</L>.inputs:intensity"), "{t}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn non_finite_and_out_of_range_values_are_replaced_with_warnings() {
    let text = r#"#usda 1.0
def SphereLight "L"
{
    float inputs:intensity = inf
    float inputs:radius = -2
}
def RenderSettings "S"
{
    int2 resolution = (1000000, 1000000)
}
"#;
    let s = load_usda_str(text, 1.0, &LoadOptions::default()).unwrap();
    let l = s.light("/L").unwrap();
    assert_eq!(l.params.intensity, 1.0, "schema default replaces inf");
    assert_eq!(l.shape, lux_math::LightShape::Sphere { radius: 2.0 });
    assert_eq!(s.render_settings[0].resolution(), [1920, 1080]);
    let kinds: Vec<_> = s
        .warnings
        .iter()
        .map(|w| (w.prim.as_str(), w.kind))
        .collect();
    assert_eq!(
        kinds,
        [
            ("/L", WarningKind::InvalidValue),
            ("/L", WarningKind::InvalidValue),
            ("/S", WarningKind::InvalidValue),
        ]
    );
}

#[test]
fn invalid_frame() {
    for f in [f64::NAN, f64::INFINITY] {
        assert!(matches!(
            load_stage(scenes().join("xforms.usda"), f),
            Err(LoadError::InvalidFrame { .. })
        ));
    }
}

#[test]
fn absurd_sizes_hit_the_limits() {
    // namespace depth
    let depth = 300;
    let mut text = String::from("#usda 1.0\n");
    for i in 0..depth {
        text.push_str(&format!("def Xform \"x{i}\" {{\n"));
    }
    text.push_str(&"}\n".repeat(depth));
    match load_usda_str(&text, 1.0, &LoadOptions::default()) {
        Err(LoadError::TooLarge {
            what, limit, prim, ..
        }) => {
            assert_eq!((what, limit), ("namespace depth", 256));
            assert!(prim.starts_with("/x0/x1/"), "{prim}");
        }
        other => panic!("{other:?}"),
    }
    // array lengths, with a small limit
    let mesh = "#usda 1.0\ndef Mesh \"M\"\n{\n    int[] faceVertexCounts = [3, 3]\n    int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n}\n";
    let mut small = LoadOptions::default();
    small.max_array_len = 5;
    match load_usda_str(mesh, 1.0, &small) {
        Err(LoadError::TooLarge {
            prim, count, limit, ..
        }) => {
            assert_eq!((prim.as_str(), count, limit), ("/M", 6, 5));
        }
        other => panic!("{other:?}"),
    }
    let s = load_usda_str(mesh, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.meshes[0].triangles.len(), 2);
    // face counts whose sum overflows: the mesh is skipped with a warning
    let huge = "#usda 1.0\ndef Mesh \"M\"\n{\n    int64[] faceVertexCounts = [9223372036854775807, 9223372036854775807]\n    int[] faceVertexIndices = [0, 1, 2]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0)]\n}\n";
    let s = load_usda_str(huge, 1.0, &LoadOptions::default()).unwrap();
    assert!(s.meshes.is_empty());
    assert_eq!(s.warnings[0].kind, WarningKind::InvalidGeometry);
    // out-of-range indices: faces skipped, with a warning
    let oob = "#usda 1.0\ndef Mesh \"M\"\n{\n    int[] faceVertexCounts = [3, 3]\n    int[] faceVertexIndices = [0, 1, 2, 0, 2, 99]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0)]\n}\n";
    let s = load_usda_str(oob, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.meshes[0].triangles.len(), 1);
    assert_eq!(s.warnings[0].kind, WarningKind::InvalidGeometry);
    // a huge implicit radius does not panic
    let big = "#usda 1.0\ndef Sphere \"S\"\n{\n    double radius = 1e300\n}\n";
    let s = load_usda_str(big, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.meshes.len(), 1);
}

#[test]
fn corrupt_binary_layers() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("scene_bad_input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in [
        ("garbage.usdc", b"PXR-USDC\x00\x00\x00\x00garbage".to_vec()),
        ("garbage.usdz", b"PK\x03\x04 not a zip".to_vec()),
        ("empty.usda", Vec::new()),
        ("binary.usda", vec![0xff, 0xfe, 0x00, 0x01]),
    ] {
        let f = dir.join(name);
        std::fs::write(&f, bytes).unwrap();
        match load_stage(&f, 1.0) {
            Err(e @ (LoadError::Malformed { .. } | LoadError::Composition { .. })) => {
                assert!(e.to_string().contains(name), "{e}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// Regressions from the `usda` fuzz target: `openusd` 0.6 accepts any text as a path or prim
/// name, and composing such a prim recursed until the stack overflowed (found as a mutated
/// luxtest scene whose connection path swallowed several lines). The loader now refuses to
/// look up anything that is not a plain prim path.
#[test]
fn fuzz_regressions_non_identifier_paths() {
    let o = LoadOptions::default();
    // a connection path spanning lines (the crash input, minimised)
    let conn = "#usda 1.0\ndef Material \"M\"\n{\n    token outputs:surface.connect = </M/a), (0, 1, 0)]\n        }\n\n    def Sphere \"b\"\n    {\n    }\n    # own iewsurface1/S.outputs:surface>\n}\n\ndef Mesh \"G\"\n{\n    int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n    rel material:binding = </M>\n}\n";
    let s = load_usda_str(conn, 1.0, &o).unwrap();
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(
        s.materials[0].diffuse,
        lux_usd::Input::Value(lux_usd::material::DEFAULT_DIFFUSE)
    );
    // prim names that are not identifiers: skipped with their subtree, with a warning
    let names = "#usda 1.0\ndef Xform \"a b\"\n{\n    def Sphere \"c}d\"\n    {\n    }\n}\ndef Sphere \"ok\"\n{\n}\n";
    let s = load_usda_str(names, 1.0, &o).unwrap();
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.meshes[0].path, "/ok");
    assert_eq!(s.warnings.len(), 1);
    assert_eq!(s.warnings[0].prim, "/a b");
    // relationship targets and reference targets that are not prim paths
    let rels = "#usda 1.0\ndef RenderSettings \"S\"\n{\n    rel products = </x y\n z>\n    rel camera = </q r>\n}\n";
    let s = load_usda_str(rels, 1.0, &o).unwrap();
    assert!(s.render_settings[0].products.is_empty());
    assert_eq!(s.render_settings[0].base.camera, None);
    assert!(
        s.warnings
            .iter()
            .all(|w| w.kind == WarningKind::InvalidValue)
    );
    let reference = "#usda 1.0\ndef Xform \"A\" (\n    prepend references = </x y\n z>\n)\n{\n}\n";
    let s = load_usda_str(reference, 1.0, &o).unwrap();
    assert!(
        s.warnings
            .iter()
            .any(|w| w.kind == WarningKind::Composition && w.prim == "/A"),
        "{:#?}",
        s.warnings
    );
    let mut strict = o.clone();
    strict.strict = true;
    assert!(matches!(
        load_usda_str(reference, 1.0, &strict),
        Err(LoadError::Composition { prim, .. }) if prim == "/A"
    ));
}

/// Regression from the `usda` fuzz target: an `xformOpOrder` entry that is not a property name
/// (a string that swallowed several lines, slashes included) made `openusd` loop without end
/// resolving the attribute.
#[test]
fn fuzz_regressions_non_identifier_property_names() {
    let text = "#usda 1.0\ndef Camera \"C\"\n{\n    double3 xformOp:translate = (1, 2, 3)\n    uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:translates:intensity = 1\\n        @../../../x\u{fffd}.ies@\\n    }\\n}\"]\n}\n";
    let s = load_usda_str(text, 1.0, &LoadOptions::default()).unwrap();
    let p = s.cameras[0]
        .camera_to_world
        .transform_point3(glam::DVec3::ZERO);
    assert_eq!(p, glam::DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert_eq!(s.warnings[0].kind, WarningKind::InvalidValue);
}

#[test]
fn fuzz_regressions_unwalkable_reference_target() {
    // openusd 0.6 walks a reference target's ancestors with a `parent()` that returns a path
    // ending in `}` (not a variant selection) unchanged: composing this hung forever. The
    // layer is refused with the path named, as a typed error, at once.
    let o = LoadOptions::default();
    let text = "#usda 1.0\ndef Xform \"A\" (\n    prepend references = </B>\n)\n{\n}\n\ndef Xform \"B\" (\n    prepend references = </x}}}\n(\n    doc = \"y/A>\n)\n{\n}\n";
    let err = load_usda_str(text, 1.0, &o).unwrap_err();
    assert!(matches!(err, LoadError::Malformed { .. }), "{err:?}");
    assert!(
        err.to_string().contains("malformed prim path </x}}}"),
        "{err}"
    );
    // the same target screened but harmless (a `}` in a relationship target) still loads
    let rel = "#usda 1.0\ndef RenderSettings \"S\"\n{\n    rel camera = </C}>\n}\n";
    assert!(load_usda_str(rel, 1.0, &o).is_ok());
}

/// An `http://` reference (lux resolves files and packages only) is an unresolved arc named as
/// written — not mangled into a local path — and the rest of the stage composes.
#[test]
fn uri_references_are_unresolved_arcs_named_as_written() {
    let text = "#usda 1.0\ndef Xform \"B\" (\n    references = @http://example.com/assets/chair.usda@</Chair>\n)\n{\n}\ndef Sphere \"S\"\n{\n}\n";
    let s = load_usda_str(text, 1.0, &LoadOptions::default()).unwrap();
    assert_eq!(s.meshes.len(), 1);
    let w = s
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::Composition)
        .expect("a composition warning");
    assert_eq!(w.prim, "/B");
    assert!(
        w.message.contains("@http://example.com/assets/chair.usda@"),
        "{w}"
    );
}
