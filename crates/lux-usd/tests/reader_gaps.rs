//! Real-world USD inputs that usd-core (Pixar's reference, 26.11) reads and `openusd` 0.6 does
//! not, each read by the loader through its compatibility pass (`lux_usd::compat`). Every
//! expected number below is what usd-core reports for the same file (derived with usd-core
//! when the test was written; see `tests/data/reader_gaps/README.md`), and each test first
//! checks that `openusd` alone still fails on the input — when one of those checks fails, an
//! `openusd` upgrade has closed the gap and the work-around can go.

use glam::{DVec2, DVec3};
use lux_usd::compat::{self, usda, usdc};
use lux_usd::{Input, LoadError, Scene, UpAxis, load_stage, locate_usda_error};
use openusd::gf;
use openusd::sdf::{self, AbstractData, Value};
use std::fs;
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/reader_gaps")
}

fn load(file: &str, frame: f64) -> Scene {
    let path = data().join(file);
    load_stage(&path, frame).unwrap_or_else(|e| panic!("{file} at {frame}: {e}"))
}

fn text(file: &str) -> String {
    fs::read_to_string(data().join(file)).unwrap()
}

/// The layer `openusd` parses: the file after the loader's compatibility pass.
fn rewritten(file: &str) -> sdf::Data {
    let original = text(file);
    let fixed = usda::rewrite(&original).expect("the file needs the compatibility pass");
    assert_eq!(
        fixed.text.lines().count(),
        original.lines().count(),
        "line numbers are kept"
    );
    openusd::usda::parse(&fixed.text).unwrap_or_else(|e| panic!("{file}: {e:#}"))
}

fn field(data: &sdf::Data, path: &str, name: &str) -> Value {
    data.get_field(&sdf::Path::new(path).unwrap(), name)
        .unwrap_or_else(|e| panic!("{path} {name}: {e:?}"))
        .into_owned()
}

/// `openusd` 0.6 by itself still rejects the text (the gap is open).
fn openusd_rejects(file: &str, what: &str) {
    let err = openusd::usda::parse(&text(file)).err().unwrap_or_else(|| {
        panic!("openusd now parses {file}: the `{what}` work-around in lux_usd::compat can go")
    });
    assert!(
        format!("{err:#}").contains(what),
        "{file}: openusd fails differently now: {err:#}"
    );
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[track_caller]
fn assert_close(a: DVec3, b: DVec3, tol: f64) {
    assert!(close(a, b, tol), "{a} != {b}");
}

// --- 1. `//` line comments and `/* … */` block comments -------------------------------------

#[test]
fn line_and_block_comments_load() {
    // line 1 carries `// …` after the magic, which openusd reads as one `#` comment
    openusd_rejects("comments.usda", "must start with magic token");
    let s = load("comments.usda", 1.0);
    assert_eq!(s.up_axis, UpAxis::Z);
    assert_eq!(s.meters_per_unit, 1.0);
    let key = s
        .light("/World/Key")
        .expect("SphereLight after a `//` comment");
    assert_close(key.position(), DVec3::new(1.0, 2.0, 3.0), 0.0);
    assert_eq!(key.params.intensity, 2.5);
    assert_eq!(key.params.color, DVec3::new(1.0, 0.5, 0.25));
    assert_eq!(
        key.shape,
        lux_math::LightShape::Sphere { radius: 0.25 },
        "a block comment inside a value"
    );
    // usd-core: cone angle 30 (t ≤ 1), 40 (t = 3), 50 (t ≥ 5) across commented samples
    for (frame, angle) in [
        (0.0, 30.0),
        (1.0, 30.0),
        (3.0, 40.0),
        (5.0, 50.0),
        (9.0, 50.0),
    ] {
        let s = load("comments.usda", frame);
        let shaping = s.light("/World/Key").unwrap().shaping.clone().unwrap();
        assert_eq!(shaping.cone_angle_deg, angle, "frame {frame}");
    }
    let sign = s.light("/World/Sign").unwrap();
    assert_eq!(
        sign.texture.as_ref().unwrap().authored,
        "tex//sign.png",
        "`//` inside an asset path is not a comment"
    );
    let data = rewritten("comments.usda");
    assert_eq!(
        field(&data, "/World/Sign.lux:note", "default"),
        Value::String("http://example.com/a//b".into()),
        "`//` inside a string is not a comment"
    );
    // a `.usd` file holding text goes through the same pass
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("reader_gaps-usd-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    let usd = dir.join("comments.usd");
    fs::write(&usd, text("comments.usda")).unwrap();
    let from_usd = load_stage(&usd, 3.0).unwrap();
    let key3 = load("comments.usda", 3.0).light("/World/Key").cloned();
    assert_eq!(from_usd.light("/World/Key").cloned(), key3);
    // without the magic-line tail, `//` itself is what openusd rejects
    let body = text("comments.usda").replacen(
        "#usda 1.0 // written for lux: comments wherever the Sdf text grammar allows them",
        "#usda 1.0",
        1,
    );
    let err = openusd::usda::parse(&body).unwrap_err();
    assert!(format!("{err:#}").contains("Logos error"), "{err:#}");
}

// --- 2. quoted strings as asset values ---------------------------------------------------------

#[test]
fn quoted_strings_load_as_asset_paths() {
    openusd_rejects("asset_strings.usda", "Asset reference expected");
    let dir = data();
    let s = load("asset_strings.usda", 1.0);
    assert_eq!(s.up_axis, UpAxis::Z);
    let dome = s.light("/Scene/Dome").unwrap().texture.clone().unwrap();
    assert_eq!(dome.authored, "sky.png");
    assert_eq!(dome.resolved, Some(dir.join("sky.png")));
    let ies = s.light("/Scene/Spot").unwrap().shaping.clone().unwrap();
    let ies = ies.ies_file.unwrap();
    assert_eq!(ies.authored, "profile.ies");
    assert_eq!(ies.resolved, Some(dir.join("profile.ies")));
    let mat = s.materials.iter().find(|m| m.path == "/Scene/Mat").unwrap();
    let Input::Texture(tex) = &mat.diffuse else {
        panic!("diffuse is a texture: {:?}", mat.diffuse)
    };
    let file = tex.file.clone().unwrap();
    assert_eq!(file.authored, "tex/other.png", "a triple-quoted string");
    assert_eq!(file.resolved, Some(dir.join("tex/other.png")));
    // time samples mixing a string and an asset path: held like any asset (usd-core: sky.png
    // for t < 5, tex/other.png from 5)
    for (frame, want) in [
        (0.0, "sky.png"),
        (1.0, "sky.png"),
        (3.0, "sky.png"),
        (5.0, "tex/other.png"),
        (9.0, "tex/other.png"),
    ] {
        let s = load("asset_strings.usda", frame);
        let t = s.light("/Scene/Screen").unwrap().texture.clone().unwrap();
        assert_eq!(t.authored, want, "frame {frame}");
        assert_eq!(t.resolved, Some(dir.join(want)), "frame {frame}");
    }
    // asset[] arrays and typed dictionary entries (usd-core: three paths, the last one with a
    // backslash after escape evaluation; customData preview = sky.png)
    let data = rewritten("asset_strings.usda");
    let Value::AssetPathVec(paths) = field(&data, "/Scene/Card.lux:layers", "default") else {
        panic!("asset[]")
    };
    let paths: Vec<&str> = paths.iter().map(|p| p.asset_path()).collect();
    assert_eq!(paths, ["sky.png", "tex/other.png", "tex\\other.png"]);
    let Value::Dictionary(custom) = field(&data, "/Scene", "customData") else {
        panic!("customData")
    };
    let Some(Value::AssetPath(preview)) = custom.get("preview") else {
        panic!("{custom:?}")
    };
    assert_eq!(preview.asset_path(), "sky.png");
}

// --- 3. the legacy `config` variability --------------------------------------------------------

#[test]
fn config_variability_loads_as_uniform() {
    openusd_rejects("config.usda", "attribute type expected");
    let s = load("config.usda", 1.0);
    let light = s.light("/World/Light").unwrap();
    assert_eq!(light.params.intensity, 4.0);
    assert_eq!(light.params.exposure, 1.0);
    assert_eq!(
        light.shape,
        lux_math::LightShape::Rect {
            width: 9.0,
            height: 2.0
        }
    );
    let red = s.materials.iter().find(|m| m.path == "/World/Red").unwrap();
    assert_eq!(
        red.diffuse,
        Input::Value(DVec3::new(0.8763, 0.2168, 0.2168).as_vec3().as_dvec3())
    );
    let quad = s.meshes.iter().find(|m| m.path == "/World/Quad").unwrap();
    assert_eq!(
        quad.triangles.len(),
        2,
        "`config int[] faceVertexCounts = [4]`"
    );
    // usd-core's specs: `config` attributes are uniform, `custom config` stays custom; a
    // property *named* config is an ordinary varying token
    let data = rewritten("config.usda");
    for p in [
        "/World/Light.inputs:intensity",
        "/World/Red/Surface.info:id",
    ] {
        assert_eq!(
            field(&data, p, "variability"),
            Value::Variability(sdf::Variability::Uniform),
            "{p}"
        );
    }
    assert_eq!(
        field(&data, "/World/Light.inputs:exposure", "custom"),
        Value::Bool(true)
    );
    assert_eq!(
        field(&data, "/World.config", "default"),
        Value::token("a property named config is not the keyword")
    );
    assert!(
        data.get_field(&sdf::Path::new("/World.config").unwrap(), "variability")
            .is_err(),
        "varying (the default) is not authored"
    );
}

// --- 4. legacy type names ----------------------------------------------------------------------

#[test]
fn legacy_type_names_load() {
    openusd_rejects("legacy_types.usda", "unrecognized type");
    let s = load("legacy_types.usda", 1.0);
    // usd-core: Tri's world transform is scale 2 then translate (1, 2, 13)
    let tri = s.meshes.iter().find(|m| m.path == "/W/Tri").unwrap();
    let want = [
        DVec3::new(1.0, 2.0, 13.0),
        DVec3::new(3.0, 2.0, 13.0),
        DVec3::new(1.0, 4.0, 13.0),
    ];
    assert_eq!(tri.positions, want);
    assert_eq!(tri.triangles, [[0, 1, 2]]);
    let normals = tri.normals.as_ref().expect("NormalFloat[] normals");
    assert!(normals[0].iter().all(|n| close(*n, DVec3::Z, 1e-12)));
    let colors = tri.colors.as_ref().expect("ColorFloat[] displayColor");
    assert!(colors[0].iter().all(|c| *c == DVec3::new(1.0, 0.5, 0.25)));
    // Quatf orient then a Transform op under the scaled parent; usd-core's matrix rows
    let disk = s.light("/W/Turned/Disk").unwrap();
    let m = disk.light_to_world;
    assert_close(
        m.x_axis.truncate(),
        DVec3::new(-6.845708355740499e-8, 2.0, 0.0),
        1e-6,
    );
    assert_close(
        m.y_axis.truncate(),
        DVec3::new(-2.0, -6.845708355740499e-8, 0.0),
        1e-6,
    );
    assert_close(m.z_axis.truncate(), DVec3::new(0.0, 0.0, 2.0), 1e-12);
    assert_close(
        m.w_axis.truncate(),
        DVec3::new(0.9999993154291644, 22.0, 3.0),
        1e-6,
    );
    assert_eq!(disk.params.color, DVec3::new(1.0, 0.5, 0.25));
    assert_eq!(disk.shape, lux_math::LightShape::Disk { radius: 0.75 });
    // a Frame-typed transform op and a Vec2f clipping range
    let cam = s.cameras.iter().find(|c| c.path == "/W/Cam").unwrap();
    assert_close(
        cam.camera_to_world.w_axis.truncate(),
        DVec3::new(1.0, 2.0, 23.0),
        0.0,
    );
    assert_eq!(cam.clipping_range, DVec2::new(0.5, 500.0));
}

/// A value flattened to numbers, with the name of its `openusd` variant.
fn flat(v: &Value) -> (&'static str, Vec<f64>) {
    let h = |x: gf::f16| x.to_f64();
    match v {
        Value::Int(i) => ("Int", vec![f64::from(*i)]),
        Value::IntVec(a) => ("IntVec", a.iter().map(|i| f64::from(*i)).collect()),
        Value::Vec2i(v) => ("Vec2i", vec![v.x.into(), v.y.into()]),
        Value::Vec3i(v) => ("Vec3i", vec![v.x.into(), v.y.into(), v.z.into()]),
        Value::Vec4i(v) => (
            "Vec4i",
            vec![v.x.into(), v.y.into(), v.z.into(), v.w.into()],
        ),
        Value::Vec2h(v) => ("Vec2h", vec![h(v.x), h(v.y)]),
        Value::Vec3h(v) => ("Vec3h", vec![h(v.x), h(v.y), h(v.z)]),
        Value::Vec4h(v) => ("Vec4h", vec![h(v.x), h(v.y), h(v.z), h(v.w)]),
        Value::Vec2f(v) => ("Vec2f", vec![v.x.into(), v.y.into()]),
        Value::Vec3f(v) => ("Vec3f", vec![v.x.into(), v.y.into(), v.z.into()]),
        Value::Vec4f(v) => (
            "Vec4f",
            vec![v.x.into(), v.y.into(), v.z.into(), v.w.into()],
        ),
        Value::Vec2d(v) => ("Vec2d", vec![v.x, v.y]),
        Value::Vec3d(v) => ("Vec3d", vec![v.x, v.y, v.z]),
        Value::Vec4d(v) => ("Vec4d", vec![v.x, v.y, v.z, v.w]),
        Value::Vec3fVec(a) => (
            "Vec3fVec",
            a.iter()
                .flat_map(|v| [v.x, v.y, v.z])
                .map(f64::from)
                .collect(),
        ),
        Value::Vec3dVec(a) => ("Vec3dVec", a.iter().flat_map(|v| [v.x, v.y, v.z]).collect()),
        Value::Quath(q) => ("Quath", vec![h(q.w), h(q.x), h(q.y), h(q.z)]),
        Value::Quatf(q) => ("Quatf", [q.w, q.x, q.y, q.z].map(f64::from).to_vec()),
        Value::Quatd(q) => ("Quatd", vec![q.w, q.x, q.y, q.z]),
        Value::Matrix2d(m) => ("Matrix2d", m.0.to_vec()),
        Value::Matrix3d(m) => ("Matrix3d", m.0.to_vec()),
        Value::Matrix4d(m) => ("Matrix4d", m.0.to_vec()),
        Value::Matrix4dVec(a) => ("Matrix4dVec", a.iter().flat_map(|m| m.0).collect()),
        other => panic!("unexpected value {other:?}"),
    }
}

#[test]
fn every_legacy_type_name_parses_to_its_value() {
    openusd_rejects("legacy_all.usda", "unrecognized type");
    let data = rewritten("legacy_all.usda");
    let t4 = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 3.0, 1.0,
    ];
    // (attribute, current type name, openusd value, numbers): usd-core's GfVec2i(1, 2),
    // GfVec2h(1.5, 2.5), …, GfMatrix4d with translation (1, 2, 3), int 7 / 8 / 9
    let cases: Vec<(&str, &str, &str, Vec<f64>)> = vec![
        ("a_Vec2i", "int2", "Vec2i", vec![1.0, 2.0]),
        ("a_Vec2h", "half2", "Vec2h", vec![1.5, 2.5]),
        ("a_Vec2f", "float2", "Vec2f", vec![1.5, 2.5]),
        ("a_Vec2d", "double2", "Vec2d", vec![1.5, 2.5]),
        ("a_Vec3i", "int3", "Vec3i", vec![1.0, 2.0, 3.0]),
        ("a_Vec3h", "half3", "Vec3h", vec![1.5, 2.5, 3.5]),
        ("a_Vec3f", "float3", "Vec3f", vec![1.5, 2.5, 3.5]),
        ("a_Vec3d", "double3", "Vec3d", vec![1.5, 2.5, 3.5]),
        ("a_Vec4i", "int4", "Vec4i", vec![1.0, 2.0, 3.0, 4.0]),
        ("a_Vec4h", "half4", "Vec4h", vec![1.5, 2.5, 3.5, 4.5]),
        ("a_Vec4f", "float4", "Vec4f", vec![1.5, 2.5, 3.5, 4.5]),
        ("a_Vec4d", "double4", "Vec4d", vec![1.5, 2.5, 3.5, 4.5]),
        ("a_Point", "point3d", "Vec3d", vec![1.5, 2.5, 3.5]),
        ("a_PointFloat", "point3f", "Vec3f", vec![1.5, 2.5, 3.5]),
        ("a_Normal", "normal3d", "Vec3d", vec![0.0, 0.0, 1.0]),
        ("a_NormalFloat", "normal3f", "Vec3f", vec![0.0, 0.0, 1.0]),
        ("a_Vector", "vector3d", "Vec3d", vec![1.5, 2.5, 3.5]),
        ("a_VectorFloat", "vector3f", "Vec3f", vec![1.5, 2.5, 3.5]),
        ("a_Color", "color3d", "Vec3d", vec![0.25, 0.5, 0.75]),
        ("a_ColorFloat", "color3f", "Vec3f", vec![0.25, 0.5, 0.75]),
        ("a_Quath", "quath", "Quath", vec![1.0, 0.0, 0.0, 0.0]),
        ("a_Quatf", "quatf", "Quatf", vec![0.5, 0.5, 0.5, 0.5]),
        ("a_Quatd", "quatd", "Quatd", vec![0.5, 0.5, 0.5, 0.5]),
        (
            "a_Matrix2d",
            "matrix2d",
            "Matrix2d",
            vec![1.0, 2.0, 3.0, 4.0],
        ),
        (
            "a_Matrix3d",
            "matrix3d",
            "Matrix3d",
            (1..=9).map(f64::from).collect(),
        ),
        ("a_Matrix4d", "matrix4d", "Matrix4d", t4.to_vec()),
        ("a_Frame", "frame4d", "Matrix4d", t4.to_vec()),
        ("a_Transform", "matrix4d", "Matrix4d", t4.to_vec()),
        ("a_PointIndex", "int", "Int", vec![7.0]),
        ("a_EdgeIndex", "int", "Int", vec![8.0]),
        ("a_FaceIndex", "int", "Int", vec![9.0]),
        (
            "arr_Vec3f",
            "float3[]",
            "Vec3fVec",
            (1..=6).map(f64::from).collect(),
        ),
        (
            "arr_PointFloat",
            "point3f[]",
            "Vec3fVec",
            vec![1.0, 2.0, 3.0],
        ),
        ("arr_Color", "color3d[]", "Vec3dVec", vec![0.25, 0.5, 0.75]),
        ("arr_Matrix4d", "matrix4d[]", "Matrix4dVec", t4.to_vec()),
        ("arr_FaceIndex", "int[]", "IntVec", vec![1.0, 2.0, 3.0]),
    ];
    assert_eq!(
        cases.iter().filter(|c| c.0.starts_with("a_")).count(),
        usda::LEGACY_TYPE_NAMES.len(),
        "every legacy name is covered"
    );
    for (name, type_name, variant, numbers) in cases {
        let path = format!("/Legacy.{name}");
        assert_eq!(
            field(&data, &path, "typeName"),
            Value::token(type_name),
            "{name}"
        );
        assert_eq!(
            flat(&field(&data, &path, "default")),
            (variant, numbers),
            "{name}"
        );
    }
    // time samples of a legacy-typed attribute keep their declared precision
    let Value::TimeSamples(samples) = field(&data, "/Legacy.ts_Vec3f", "timeSamples") else {
        panic!("timeSamples")
    };
    let samples: Vec<(f64, (&str, Vec<f64>))> =
        samples.iter().map(|(t, v)| (*t, flat(v))).collect();
    assert_eq!(
        samples,
        [
            (1.0, ("Vec3f", vec![1.0, 2.0, 3.0])),
            (2.0, ("Vec3f", vec![3.0, 4.0, 5.0]))
        ]
    );
}

// --- 5. usdc crate files older than 0.7.0 with time samples ------------------------------------

/// The time-sample times `openusd` reads for `attr` in crate bytes.
fn crate_times(bytes: Vec<u8>, attr: &str) -> Result<Vec<f64>, String> {
    let data = openusd::usdc::CrateData::open(std::io::Cursor::new(bytes), true)
        .map_err(|e| format!("{e:#}"))?;
    match data.get_field(&sdf::Path::new(attr).unwrap(), "timeSamples") {
        Ok(v) => match v.into_owned() {
            Value::TimeSamples(s) => Ok(s.iter().map(|(t, _)| *t).collect()),
            other => Err(format!("{other:?}")),
        },
        Err(e) => Err(format!("{e:?}")),
    }
}

#[test]
fn old_crate_time_samples_read_right() {
    // usd-core: world points of /W/m (points and translate sampled at 1 and 3, linear between,
    // held outside), identical for anim.usda and its 0.4.0 / 0.5.0 / 0.6.0 crate exports
    let expected = [
        (0.0, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        (1.0, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        (1.5, [[0.5, 1.0, 2.0], [2.0, 1.0, 2.0], [0.5, 2.5, 2.0]]),
        (2.0, [[1.0, 2.0, 4.0], [3.0, 2.0, 4.0], [1.0, 4.0, 4.0]]),
        (3.0, [[2.0, 4.0, 8.0], [5.0, 4.0, 8.0], [2.0, 7.0, 8.0]]),
        (4.0, [[2.0, 4.0, 8.0], [5.0, 4.0, 8.0], [2.0, 7.0, 8.0]]),
    ];
    for file in [
        "anim.usda",
        "anim_v0_4_0.usdc",
        "anim_v0_5_0.usdc",
        "anim_v0_6_0.usdc",
    ] {
        if file.ends_with(".usdc") {
            let bytes = fs::read(data().join(file)).unwrap();
            let version = usdc::crate_version(&bytes).unwrap();
            let raw = crate_times(bytes.clone(), "/W/m.points");
            // the gap: openusd 0.6 reads these times with its array layout
            assert_ne!(
                raw.as_deref(),
                Ok(&[1.0, 3.0][..]),
                "openusd now reads {file}: the compat::usdc work-around can go"
            );
            if version.1 < 5 {
                assert!(raw.unwrap_err().contains("timeSamples"), "{file}");
            }
            let mut fixed = bytes;
            // the points, the extent and the translate share one times vector
            assert_eq!(usdc::fix_time_samples(&mut fixed), 3, "{file}");
            assert_eq!(
                crate_times(fixed.clone(), "/W/m.points"),
                Ok(vec![1.0, 3.0])
            );
            assert_eq!(
                crate_times(fixed, "/W.xformOp:translate"),
                Ok(vec![1.0, 3.0])
            );
        }
        for (frame, points) in expected {
            let s = load(file, frame);
            assert_eq!(s.meshes.len(), 1, "{file}");
            let want: Vec<DVec3> = points.iter().map(|p| DVec3::from_array(*p)).collect();
            assert_eq!(s.meshes[0].positions, want, "{file} at frame {frame}");
        }
    }
}

#[test]
fn pixar_animated_top_loads() {
    // OpenUSD's extras/usd/tutorials/animatedTop/top.geom.usd: crate 0.4.0, one Mesh whose
    // points (and topology) are sampled once, at 48
    let bytes = fs::read(data().join("top.geom.usd")).unwrap();
    assert_eq!(usdc::crate_version(&bytes), Some((0, 4, 0)));
    assert!(
        crate_times(bytes, "/Top/mesh_0.points").is_err(),
        "openusd now reads top.geom.usd: the compat::usdc work-around can go"
    );
    // usd-core at 1, 48 and 100: 180 points (the held sample), 170 quads and triangles fans
    // = 340 triangles, these three points, coordinate sum 74.55362782108786
    for frame in [1.0, 48.0, 100.0] {
        let s = load("top.geom.usd", frame);
        assert_eq!(s.up_axis, UpAxis::Z);
        assert_eq!(s.meshes.len(), 1);
        let m = &s.meshes[0];
        assert_eq!(m.path, "/Top/mesh_0");
        assert_eq!(m.positions.len(), 180);
        assert_eq!(m.triangles.len(), 340);
        let f = |x: f32, y: f32, z: f32| DVec3::new(x.into(), y.into(), z.into());
        assert_eq!(m.positions[0], f(-0.00291886, -2.5517485e-10, 1.00214));
        assert_eq!(m.positions[1], f(-0.002361407, -0.0017156631, 1.00214));
        assert_eq!(m.positions[179], f(0.002361408, -0.001715662, 0.0019459));
        let sum: f64 = m.positions.iter().map(|p| p.x + p.y + p.z).sum();
        assert!((sum - 74.55362782108786).abs() < 1e-9, "{sum}");
    }
    // the same layer inside a package
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("reader_gaps-usdz-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    let usdz = dir.join("top.usdz");
    let mut w = openusd::usdz::ArchiveWriter::create(&usdz).unwrap();
    w.add_layer(
        "top.geom.usdc",
        &fs::read(data().join("top.geom.usd")).unwrap(),
    )
    .unwrap();
    w.finish().unwrap();
    let packaged = load_stage(&usdz, 48.0).unwrap();
    assert_eq!(
        packaged.meshes[0].positions,
        load("top.geom.usd", 48.0).meshes[0].positions
    );
}

/// Start of the structural sections of a crate file (the lowest section start in its table of
/// contents: bootstrap `tocOffset`, then a `uint64_t` count and 32-byte section records).
fn structural_start(b: &[u8]) -> usize {
    let word = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize;
    let toc = word(16);
    (0..word(toc))
        .map(|i| word(toc + 8 + 32 * i + 16))
        .min()
        .unwrap()
}

#[test]
fn bad_crates_fail_with_typed_errors() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("reader_gaps-bad-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    let good = fs::read(data().join("anim_v0_4_0.usdc")).unwrap();
    // every 8-byte word overwritten in turn by all-ones (sizes and offsets far past the file,
    // negative relative offsets, invalid types): the time-sample fix never panics, and leaves
    // what it cannot follow as it is
    for at in (8..good.len() - 8).step_by(4) {
        let mut b = good.clone();
        b[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        let mut fixed = b.clone();
        let n = usdc::fix_time_samples(&mut fixed);
        assert!(n <= 3, "{at}: {n}");
        let _ = usdc::read_crate(&fixed, |_| ());
    }
    // A truncated file, a bare header and garbled structural sections (tables of tokens,
    // fields, paths, specs, the table of contents): the loader refuses them with a typed
    // error naming the file. (Garbled *value* data is openusd's own business: its 0.6 crate
    // reader allocates what an array header claims, see the README.)
    let mut cases: Vec<(String, Vec<u8>)> = vec![
        ("truncated.usdc".into(), good[..good.len() / 2].to_vec()),
        ("header_only.usdc".into(), good[..16].to_vec()),
    ];
    for at in (structural_start(&good)..good.len() - 8).step_by(8) {
        let mut b = good.clone();
        b[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        cases.push((format!("garbled_{at}.usdc"), b));
    }
    let mut refused = 0;
    for (name, bytes) in cases {
        let path = dir.join(&name);
        fs::write(&path, &bytes).unwrap();
        match load_stage(&path, 2.0) {
            Ok(_) => {}
            Err(e @ (LoadError::Malformed { .. } | LoadError::Usd { .. })) => {
                assert!(e.to_string().contains(&name), "{e}");
                refused += 1;
            }
            Err(e) => panic!("{name}: unexpected error kind {e:?}"),
        }
    }
    assert!(refused >= 2, "{refused}");
}

// --- 6. parse errors with a line and column ----------------------------------------------------

#[test]
fn parse_errors_name_line_and_column() {
    let path = data().join("bad_value.usda");
    let src = fs::read_to_string(&path).unwrap();
    // the loader cannot open it, with a typed error naming the file
    match load_stage(&path, 1.0) {
        Err(e @ LoadError::Malformed { .. }) => {
            assert!(e.to_string().contains("bad_value.usda"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    // line 9 is `    config Vec3f v = (1, 2, $)`: the compatibility pass lengthens its start
    // (`uniform float3`), the column is still the one written
    let loc = locate_usda_error(&src).expect("a parse error");
    assert_eq!((loc.line, loc.column), (9, 29), "{loc:?}");
    assert_eq!(loc.line_text, "    config Vec3f v = (1, 2, $)");
    assert!(
        loc.message.contains("unrecognized token starting with '$'"),
        "{}",
        loc.message
    );
    let described = compat::describe_usda_error(&path, src.as_bytes()).unwrap();
    assert!(
        described.starts_with(&format!("{}:9:29: ", path.display())),
        "{described}"
    );
    assert_eq!(
        compat::describe_usda_layer_error(path.to_str().unwrap()),
        Some(described.clone())
    );
    // a malformed sublayer (which the loader's messages name, as an error or a warning) is
    // located the same way
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("reader_gaps-sub-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    fs::write(dir.join("bad.usda"), &src).unwrap();
    let sub = dir.join("bad.usda");
    let described = compat::describe_usda_layer_error(sub.to_str().unwrap()).unwrap();
    assert!(
        described.starts_with(&format!("{}:9:29: ", sub.display())),
        "{described}"
    );
    // the same text with the bad token fixed parses (the compatibility constructs before it
    // are not errors)
    assert_eq!(locate_usda_error(&src.replace("$", "3")), None);
    // an error openusd detects one token late points at the token it last read
    let loc = locate_usda_error("#usda 1.0\ndef X \"a\" {\n    asset a = 12\n}\n").unwrap();
    assert_eq!((loc.line, loc.column), (3, 15), "{loc:?}");
    assert!(loc.message.contains("Asset reference expected"), "{loc}");
    // not UTF-8: the first bad byte
    let loc = compat::locate_usda_error_in_bytes(b"#usda 1.0\ndef X \"\xc3(\" {}\n").unwrap();
    assert_eq!((loc.line, loc.column), (2, 8), "{loc:?}");
}

#[test]
fn rewriting_keeps_every_line_and_the_common_case_is_not_copied() {
    for file in [
        "comments.usda",
        "asset_strings.usda",
        "config.usda",
        "legacy_types.usda",
        "legacy_all.usda",
        "bad_value.usda",
    ] {
        let src = text(file);
        let r = usda::rewrite(&src).unwrap();
        let lines: Vec<&str> = src.split('\n').collect();
        let new_lines: Vec<&str> = r.text.split('\n').collect();
        assert_eq!(lines.len(), new_lines.len(), "{file}");
        for (a, b) in lines.iter().zip(&new_lines) {
            // a line without a comment, string, asset path or type, `config` or legacy type
            // name is handed over as written
            let candidate = a.contains("//")
                || a.contains(['"', '\'', '@'])
                || a.contains("asset")
                || a.contains("config")
                || a.split(|c: char| !c.is_ascii_alphanumeric())
                    .any(|w| usda::legacy_type_name(w).is_some());
            assert!(candidate || a == b, "{file}: {a:?} → {b:?}");
        }
    }
    // a stage with none of these constructs is handed to openusd as it is
    let plain = "#usda 1.0\ndef Xform \"W\" {\n    asset inputs:file = @a.png@\n    color3f[] primvars:displayColor = [(1, 0, 0)]\n}\n";
    assert_eq!(usda::rewrite(plain), None);
}

#[test]
fn asset_paths_in_rewritten_files_resolve_like_usd_core() {
    // the three spellings of one texture in asset_strings.usda resolve to the same file
    let dir = data();
    let s = load("asset_strings.usda", 5.0);
    let screen = s.light("/Scene/Screen").unwrap().texture.clone().unwrap();
    let mat = s.materials.iter().find(|m| m.path == "/Scene/Mat").unwrap();
    let Input::Texture(tex) = &mat.diffuse else {
        panic!()
    };
    assert_eq!(screen.resolved, tex.file.as_ref().unwrap().resolved);
    assert_eq!(
        screen.resolved.as_deref(),
        Some(Path::new(&dir.join("tex/other.png")))
    );
}
