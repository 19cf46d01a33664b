//! Lights: every type, every `LightAPI` / `ShapingAPI` / `ShadowAPI` input at its schema
//! default when unauthored (checked against the UsdLux 26.11 schema text in `tests/data/schema`),
//! ShapingAPI only when applied, PluginLight reported as unsupported, and authored values of
//! `roundtrip.usda`.

use glam::{DMat4, DVec3};
use lux_math::{LightKind, LightShape};
use lux_usd::{Light, PoleAxis, Scene, WarningKind, load_stage};
use std::path::PathBuf;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

/// A schema default, as the loader reports it.
#[derive(Clone, Debug, PartialEq)]
enum V {
    F(f64),
    B(bool),
    C(DVec3),
    T(&'static str),
}

/// (schema class, attribute, fallback) for every input the loader fills in.
const SCHEMA: &[(&str, &str, V)] = &[
    ("LightAPI", "inputs:intensity", V::F(1.0)),
    ("LightAPI", "inputs:exposure", V::F(0.0)),
    ("LightAPI", "inputs:diffuse", V::F(1.0)),
    ("LightAPI", "inputs:specular", V::F(1.0)),
    ("LightAPI", "inputs:normalize", V::B(false)),
    ("LightAPI", "inputs:color", V::C(DVec3::ONE)),
    ("LightAPI", "inputs:enableColorTemperature", V::B(false)),
    ("LightAPI", "inputs:colorTemperature", V::F(6500.0)),
    (
        "LightAPI",
        "light:materialSyncMode",
        V::T("noMaterialResponse"),
    ),
    (
        "MeshLightAPI",
        "light:materialSyncMode",
        V::T("materialGlowTintsLight"),
    ),
    ("ShapingAPI", "inputs:shaping:focus", V::F(0.0)),
    ("ShapingAPI", "inputs:shaping:focusTint", V::C(DVec3::ZERO)),
    ("ShapingAPI", "inputs:shaping:cone:angle", V::F(90.0)),
    ("ShapingAPI", "inputs:shaping:cone:softness", V::F(0.0)),
    ("ShapingAPI", "inputs:shaping:ies:angleScale", V::F(0.0)),
    ("ShapingAPI", "inputs:shaping:ies:normalize", V::B(false)),
    ("ShadowAPI", "inputs:shadow:enable", V::B(true)),
    ("ShadowAPI", "inputs:shadow:color", V::C(DVec3::ZERO)),
    ("ShadowAPI", "inputs:shadow:distance", V::F(-1.0)),
    ("ShadowAPI", "inputs:shadow:falloff", V::F(-1.0)),
    ("ShadowAPI", "inputs:shadow:falloffGamma", V::F(1.0)),
    ("DistantLight", "inputs:angle", V::F(0.53)),
    ("DistantLight", "inputs:intensity", V::F(50000.0)),
    ("DiskLight", "inputs:radius", V::F(0.5)),
    ("RectLight", "inputs:width", V::F(1.0)),
    ("RectLight", "inputs:height", V::F(1.0)),
    ("SphereLight", "inputs:radius", V::F(0.5)),
    ("SphereLight", "treatAsPoint", V::B(false)),
    ("CylinderLight", "inputs:length", V::F(1.0)),
    ("CylinderLight", "inputs:radius", V::F(0.5)),
    ("CylinderLight", "treatAsLine", V::B(false)),
    ("DomeLight", "inputs:texture:format", V::T("automatic")),
    ("DomeLight_1", "inputs:texture:format", V::T("automatic")),
    ("DomeLight_1", "poleAxis", V::T("scene")),
    ("PortalLight", "inputs:width", V::F(1.0)),
    ("PortalLight", "inputs:height", V::F(1.0)),
];

/// The UsdLux 26.11 schema text (`tests/data/schema`, with its notice and licence).
fn schema_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/schema/usdLux-schema-26.11.usda")
}

#[test]
fn the_default_table_matches_the_schema_text() {
    let path = schema_file();
    let text = std::fs::read_to_string(&path).unwrap();
    let data = openusd::usda::parse(&text).expect("schema parses");
    let layer_value = |class: &str, attr: &str| -> openusd::sdf::Value {
        let p = openusd::sdf::Path::new(&format!("/{class}.{attr}")).unwrap();
        openusd::sdf::AbstractData::get_field(&data, &p, "default")
            .unwrap_or_else(|_| panic!("{class}.{attr} in the schema"))
            .into_owned()
    };
    for (class, attr, want) in SCHEMA {
        let v = layer_value(class, attr);
        let got = match want {
            V::F(_) => V::F(lux_value_f64(&v)),
            V::B(_) => V::B(matches!(v, openusd::sdf::Value::Bool(true))),
            V::C(_) => match v {
                openusd::sdf::Value::Vec3f(c) => {
                    V::C(DVec3::new(c.x.into(), c.y.into(), c.z.into()))
                }
                other => panic!("{class}.{attr}: {other:?}"),
            },
            V::T(_) => match v {
                openusd::sdf::Value::Token(t) => V::T(Box::leak(t.as_str().to_owned().into())),
                other => panic!("{class}.{attr}: {other:?}"),
            },
        };
        let close = match (&got, want) {
            (V::F(a), V::F(b)) => (a - b).abs() <= 1e-6 * b.abs().max(1.0),
            _ => got == *want,
        };
        assert!(close, "{class}.{attr}: schema {got:?}, table {want:?}");
    }
}

fn lux_value_f64(v: &openusd::sdf::Value) -> f64 {
    use openusd::sdf::Value as S;
    match v {
        S::Float(x) => f64::from(*x),
        S::Double(x) => *x,
        S::Int(x) => f64::from(*x),
        S::Int64(x) => *x as f64,
        other => panic!("not a number: {other:?}"),
    }
}

/// The loader's value of `attr` on `l`, where the loader exposes it.
fn loaded(l: &Light, attr: &str) -> V {
    let s = l.shaping.clone().unwrap_or_default();
    match attr {
        "inputs:intensity" => V::F(l.params.intensity),
        "inputs:exposure" => V::F(l.params.exposure),
        "inputs:diffuse" => V::F(l.diffuse),
        "inputs:specular" => V::F(l.specular),
        "inputs:normalize" => V::B(l.params.normalize),
        "inputs:color" => V::C(l.params.color),
        "inputs:enableColorTemperature" => V::B(l.params.enable_color_temperature),
        "inputs:colorTemperature" => V::F(l.params.color_temperature),
        "light:materialSyncMode" => V::T(l.material_sync_mode.token()),
        "inputs:shaping:focus" => V::F(s.focus),
        "inputs:shaping:focusTint" => V::C(s.focus_tint),
        "inputs:shaping:cone:angle" => V::F(s.cone_angle_deg),
        "inputs:shaping:cone:softness" => V::F(s.cone_softness),
        "inputs:shaping:ies:angleScale" => V::F(s.ies_angle_scale),
        "inputs:shaping:ies:normalize" => V::B(s.ies_normalize),
        "inputs:shadow:enable" => V::B(l.shadow.enable),
        "inputs:shadow:color" => V::C(l.shadow.color),
        "inputs:shadow:distance" => V::F(l.shadow.distance),
        "inputs:shadow:falloff" => V::F(l.shadow.falloff),
        "inputs:shadow:falloffGamma" => V::F(l.shadow.falloff_gamma),
        "inputs:angle" => match l.shape {
            LightShape::Distant { angle_deg } => V::F(angle_deg),
            _ => unreachable!(),
        },
        "inputs:radius" => match l.shape {
            LightShape::Disk { radius }
            | LightShape::Sphere { radius }
            | LightShape::Cylinder { radius, .. } => V::F(radius),
            _ => unreachable!(),
        },
        "inputs:length" => match l.shape {
            LightShape::Cylinder { length, .. } => V::F(length),
            _ => unreachable!(),
        },
        "inputs:width" => match l.shape {
            LightShape::Rect { width, .. } | LightShape::Portal { width, .. } => V::F(width),
            _ => unreachable!(),
        },
        "inputs:height" => match l.shape {
            LightShape::Rect { height, .. } | LightShape::Portal { height, .. } => V::F(height),
            _ => unreachable!(),
        },
        "treatAsPoint" => V::B(l.treat_as_point),
        "treatAsLine" => V::B(l.treat_as_line),
        "inputs:texture:format" => V::T(l.texture_format.token()),
        "poleAxis" => V::T(match l.pole_axis {
            PoleAxis::Scene => "scene",
            PoleAxis::Y => "Y",
            PoleAxis::Z => "Z",
        }),
        other => panic!("{other}"),
    }
}

fn defaults() -> Scene {
    load_stage(scenes().join("light_defaults.usda"), 1.0).unwrap()
}

#[test]
fn unauthored_inputs_take_the_schema_defaults() {
    let s = defaults();
    let cases = [
        ("/Distant", "DistantLight", LightKind::Distant),
        ("/Disk", "DiskLight", LightKind::Disk),
        ("/Rect", "RectLight", LightKind::Rect),
        ("/Sphere", "SphereLight", LightKind::Sphere),
        ("/Cylinder", "CylinderLight", LightKind::Cylinder),
        ("/Dome", "DomeLight", LightKind::Dome),
        ("/Dome1", "DomeLight_1", LightKind::Dome),
        ("/Portal", "PortalLight", LightKind::Portal),
        ("/MeshLight", "Mesh", LightKind::Mesh),
    ];
    let mut checked = 0;
    for (path, type_name, kind) in cases {
        let l = s.light(path).unwrap_or_else(|| panic!("{path}"));
        assert_eq!(l.kind, kind, "{path}");
        assert_eq!(l.type_name, type_name, "{path}");
        assert_eq!(l.light_to_world, DMat4::IDENTITY);
        assert!(l.shaping.is_none(), "{path}: ShapingAPI not applied");
        assert!(!l.shadow.applied, "{path}");
        assert!(
            !l.visible_to_camera,
            "{path}: inputs:visibility:camera default false"
        );
        assert!(l.texture.is_none() && l.portals.is_empty());
        // The LightAPI row, overridden by the type's own row when it has one.
        let class = if kind == LightKind::Mesh {
            "MeshLightAPI"
        } else {
            type_name
        };
        for (c, attr, want) in SCHEMA {
            let own = SCHEMA.iter().any(|(k, a, _)| k == &class && a == attr);
            let applies = *c == class || (*c == "LightAPI" && !own);
            if applies {
                assert_eq!(loaded(l, attr), *want, "{path}.{attr}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 9 * 9, "{checked}");
    // Mesh light geometry: the mesh's own triangle, in light space.
    let m = s.light("/MeshLight").unwrap();
    match &m.shape {
        LightShape::Mesh { triangles } => {
            assert_eq!(triangles, &vec![[DVec3::ZERO, DVec3::X, DVec3::Y]])
        }
        other => panic!("{other:?}"),
    }
    assert!(
        s.meshes
            .iter()
            .any(|x| x.path == "/MeshLight" && x.light.is_some())
    );
}

#[test]
fn applied_shaping_and_shadow_take_their_defaults() {
    let s = defaults();
    let l = s.light("/Shaped").unwrap();
    let sh = l.shaping.as_ref().expect("ShapingAPI applied");
    assert!(sh.ies_file.is_none());
    assert!(l.shadow.applied);
    for (class, attr, want) in SCHEMA {
        if matches!(*class, "ShapingAPI" | "ShadowAPI") {
            assert_eq!(loaded(l, attr), *want, "{attr}");
        }
    }
    assert_eq!(l.api_schemas, ["ShapingAPI", "ShadowAPI"]);
}

#[test]
fn shaping_inputs_without_the_api_are_ignored_and_reported() {
    let s = defaults();
    let l = s.light("/UnappliedShaping").unwrap();
    assert!(l.shaping.is_none());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.prim == "/UnappliedShaping" && w.kind == WarningKind::ShapingNotApplied)
    );
}

#[test]
fn plugin_light_is_reported_as_unsupported() {
    let s = defaults();
    assert!(s.light("/Plugin").is_none());
    let w: Vec<_> = s.warnings.iter().filter(|w| w.prim == "/Plugin").collect();
    assert_eq!(w.len(), 1, "{:?}", s.warnings);
    assert_eq!(w[0].kind, WarningKind::UnsupportedLight);
    // The only other warning of the file is the unapplied shaping input.
    assert_eq!(s.warnings.len(), 2, "{:#?}", s.warnings);
}

#[test]
fn authored_light_inputs() {
    let s = load_stage(scenes().join("roundtrip.usda"), 1.0).unwrap();
    let sun = s.light("/World/Lights/Sun").unwrap();
    assert_eq!(sun.shape, LightShape::Distant { angle_deg: 1.5 });
    assert_eq!(sun.params.intensity, 1000.0);
    assert!(sun.shadow.applied);
    assert!(!sun.shadow.enable);
    assert_eq!(
        sun.shadow.color,
        DVec3::new(0.1f32.into(), 0.1f32.into(), 0.2f32.into())
    );
    assert_eq!(
        (
            sun.shadow.distance,
            sun.shadow.falloff,
            sun.shadow.falloff_gamma
        ),
        (100.0, 5.0, 2.0)
    );
    let spot = s.light("/World/Lights/Spot").unwrap();
    let sh = spot.shaping.as_ref().unwrap();
    assert_eq!(
        (sh.cone_angle_deg, sh.cone_softness, sh.focus),
        (40.0, 0.25, 2.0)
    );
    assert_eq!(sh.focus_tint, DVec3::new(1.0, 0.5, 0.0));
    assert_eq!(sh.ies_angle_scale, f64::from(-0.3f32));
    assert!(sh.ies_normalize);
    assert_eq!(sh.ies_file.as_ref().unwrap().authored, "assets/tiny.ies");
    assert_eq!(spot.position(), DVec3::new(1.0, 2.0, 3.0));
    let panel = s.light("/World/Lights/Panel").unwrap();
    assert_eq!(
        panel.shape,
        LightShape::Rect {
            width: 2.0,
            height: 0.5
        }
    );
    assert_eq!((panel.params.exposure, panel.params.normalize), (2.0, true));
    assert_eq!((panel.diffuse, panel.specular), (0.5, 0.25));
    assert!(panel.visible_to_camera);
    assert_eq!(panel.texture.as_ref().unwrap().authored, "assets/grid.png");
    let bulb = s.light("/World/Lights/Bulb").unwrap();
    assert!(bulb.treat_as_point);
    assert!(bulb.params.enable_color_temperature);
    assert_eq!(bulb.params.color_temperature, 3000.0);
    let tube = s.light("/World/Lights/Tube").unwrap();
    assert!(tube.treat_as_line);
    assert_eq!(
        tube.shape,
        LightShape::Cylinder {
            radius: f64::from(0.05f32),
            length: 3.0
        }
    );
    assert_eq!(tube.params.color, DVec3::new(0.5, 1.0, 0.25));
    let sky = s.light("/World/Lights/Sky").unwrap();
    assert_eq!(sky.texture_format.token(), "latlong");
    assert_eq!(sky.portals, ["/World/Lights/Window"]);
    assert_eq!(sky.pole_axis, PoleAxis::Scene);
    assert_eq!(
        s.light("/World/Lights/Sky1").unwrap().pole_axis,
        PoleAxis::Z
    );
    assert_eq!(
        s.light("/World/Lights/Window").unwrap().shape,
        LightShape::Portal {
            width: 2.0,
            height: 3.0
        }
    );
    let glow = s.light("/World/Lights/Glow").unwrap();
    assert_eq!((glow.kind, glow.params.intensity), (LightKind::Mesh, 7.0));
    // Lights carry world transforms: /World/Lights rotates 0 → 90° about Z over frames 1 → 4,
    // so at frame 4 the spot at (1, 2, 3) sits at (−2, 1, 3).
    let s4 = load_stage(scenes().join("roundtrip.usda"), 4.0).unwrap();
    let p = s4.light("/World/Lights/Spot").unwrap().position();
    assert!((p - DVec3::new(-2.0, 1.0, 3.0)).length() < 1e-6, "{p}");
    assert_eq!(
        s4.light("/World/Lights/Sun").unwrap().params.intensity,
        4000.0
    );
}
