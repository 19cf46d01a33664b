//! `lux info` report, exercised through the module itself (the binary wiring is the lead's).

#[path = "../src/cli/info.rs"]
#[allow(dead_code)]
mod info;

use std::path::PathBuf;

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/luxtest/usd")
        .join(name)
}

#[test]
fn json_report_of_rect_frame_11() {
    // rect frame 11: intensity 5, normalize on, width 0.2, height 2 → sizeFactor 0.4, L = 12.5.
    let args = info::InfoArgs {
        scene: scene("rect.usda"),
        frame: Some(11.0),
        json: true,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    };
    let v: serde_json::Value = serde_json::from_str(&info::report(&args).unwrap()).unwrap();
    let l = &v["lights"][0];
    assert_eq!(l["type"], "RectLight");
    let spec = &l["profiles"]["spec"];
    assert!((spec["size_factor"].as_f64().unwrap() - 0.4).abs() < 1e-6);
    for c in spec["luminance_rgb"].as_array().unwrap() {
        assert!((c.as_f64().unwrap() - 12.5).abs() < 1e-4, "{c}");
    }
    assert_eq!(l["shaping"]["cone_angle_deg"], 180.0);
}

#[test]
fn missing_file_is_an_error_naming_it() {
    let args = info::InfoArgs {
        scene: scene("nope.usda"),
        frame: Some(1.0),
        json: false,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    };
    let e = info::report(&args).unwrap_err();
    assert!(e.contains("nope.usda") && e.contains("no such file"), "{e}");
}

#[test]
fn physical_units_and_spectra_are_reported_with_their_converted_radiance() {
    let args = info::InfoArgs {
        scene: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/physical_lights.usda"),
        frame: Some(1.0),
        json: true,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    };
    let v: serde_json::Value = serde_json::from_str(&info::report(&args).unwrap()).unwrap();
    let light = |p: &str| {
        v["lights"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["path"] == p)
            .unwrap()
            .clone()
    };
    let l = light("/World/Lumens");
    assert_eq!(l["physical"]["quantity"]["attribute"], "photometric:power");
    assert_eq!(l["physical"]["quantity"]["value"], 800.0);
    assert_eq!(l["physical"]["illuminant"], "Blackbody");
    // 800 lm over 2 × 0.5 with G = π: luminance 800/π nits (the blackbody colour has
    // Rec.709 luminance 1).
    let rgb: Vec<f64> = l["profiles"]["spec"]["luminance_rgb"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    let y = lux::math::luminance(glam::DVec3::new(rgb[0], rgb[1], rgb[2]));
    assert!(
        (y - 800.0 / std::f64::consts::PI).abs() < 1e-6 * y,
        "{rgb:?}"
    );
    assert!(rgb[0] > rgb[2], "3000 K is warm: {rgb:?}");
    let p = light("/World/Preset");
    assert_eq!(p["emission_spectrum"]["illuminant_preset"], "D65");
    let text = info::report(&info::InfoArgs {
        json: false,
        ..args
    })
    .unwrap();
    assert!(text.contains("photometric:power = 800"), "{text}");
    assert!(text.contains("conformance profile"), "{text}");
}

#[test]
fn light_and_shadow_links_are_listed_when_authored() {
    let linking = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/linking.usda");
    let args = |json| info::InfoArgs {
        scene: linking.clone(),
        frame: Some(1.0),
        json,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    };
    let text = info::report(&args(false)).unwrap();
    let block = |light: &str| {
        let start = text
            .find(&format!("light /World/Lights/{light} "))
            .unwrap_or_else(|| panic!("{light} in {text}"));
        let rest = &text[start + 1..];
        let end = rest.find("\nlight ").or(rest.find("\nwarning")).unwrap();
        rest[..end].to_owned()
    };
    let only_a = block("OnlyA");
    assert!(
        only_a.contains("  lightLink: includes /World/A, excludes /World/A/m1 (expandPrims)\n"),
        "{only_a}"
    );
    assert!(
        only_a.contains("  shadowLink: includes /World/B, /World/m6 (expandPrims)"),
        "{only_a}"
    );
    let nothing = block("Nothing");
    assert!(nothing.contains("  lightLink: nothing\n"), "{nothing}");
    assert!(nothing.contains("  shadowLink: all"), "{nothing}");
    // Nothing authored: no lines.
    assert!(!block("Default").contains("Link:"));
    let v: serde_json::Value = serde_json::from_str(&info::report(&args(true)).unwrap()).unwrap();
    let explicit = v["lights"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["path"] == "/World/Lights/Explicit")
        .unwrap();
    assert_eq!(
        explicit["light_link"],
        "includes /World/A, /World/B/m4 (explicitOnly)"
    );
    assert_eq!(
        explicit["shadow_link"],
        "includes /, excludes /World/B (expandPrims)"
    );
}

#[test]
fn text_report_prints_floats_as_authored_with_units() {
    let dir = std::env::temp_dir().join(format!("lux-cli-info-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let usda = dir.join("floats.usda");
    std::fs::write(
        &usda,
        r#"#usda 1.0
(
    metersPerUnit = 1
)
def Camera "Cam"
{
}
def SphereLight "Key" (
    prepend apiSchemas = ["ShapingAPI"]
)
{
    float inputs:intensity = 0.3
    float inputs:radius = 0.1
    float inputs:shaping:cone:angle = 30.7
    float inputs:shaping:cone:softness = 0.3
    double3 xformOp:translate = (0.1, 2, -0.7)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
"#,
    )
    .unwrap();
    let text = info::report(&info::InfoArgs {
        scene: usda,
        frame: Some(1.0),
        json: false,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    })
    .unwrap();
    assert!(!text.contains("0.30000001"), "{text}");
    assert!(!text.contains("0.699999"), "{text}");
    assert!(text.contains("softness 0.3 "), "{text}");
    assert!(text.contains("cone 30.7°"), "{text}");
    assert!(text.contains("position (0.1, 2, -0.7) m"), "{text}");
    assert!(text.contains("L = (0.3, 0.3, 0.3) nits"), "{text}");
    assert!(
        text.contains("1 camera,") && text.contains("1 light\n"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `lux info --json` reports the world box of what is drawn — posed, refined, curves and
/// points included — and how many of each: a skinned arm (usd-core's `UsdSkel.BakeSkinning`
/// and `BBoxCache` give (−0.5, −0.5, 0)..(0.5, 0.5, 4) at time 1, `SOURCES.md` of the skel test
/// data; its limit surface inside that box in spec), a default-scheme cube refined by the spec
/// profile (its face centres, the limit points 68/81 out, bound it), OpenUSD's basicDrawing
/// and instancing test (curves and points drawn).
#[test]
fn json_report_gives_drawn_bounds_and_counts() {
    let report = |path: PathBuf, frame: Option<f64>| -> serde_json::Value {
        let args = info::InfoArgs {
            scene: path,
            frame,
            json: true,
            strict: false,
            disable_camera_light: false,
            subdiv_level: None,
        };
        serde_json::from_str(&info::report(&args).unwrap()).unwrap()
    };
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let arm_path = root.join("crates/lux-usd/tests/data/skel/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdSkel/arm.usda");
    let v3 = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let close = |got: Vec<f64>, want: [f64; 3]| {
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-5 * 4.0, "{got:?} vs {want:?}");
        }
    };
    // The arm is a subdivision surface: in the hdembree profile (its polygons, as usd-core
    // bounds its points) the box is usd-core's; in spec its limit surface lies inside it.
    let dir = std::env::temp_dir().join(format!("lux-info-bounds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let hdembree = dir.join("arm_hdembree.usda");
    std::fs::write(
        &hdembree,
        format!(
            "#usda 1.0\n(\n    subLayers = [@{}@]\n)\ndef RenderSettings \"Settings\" {{\n    uniform token lux:conformanceProfile = \"hdembree\"\n}}\n",
            arm_path.display()
        ),
    )
    .unwrap();
    let arm = report(hdembree, Some(1.0));
    assert_eq!(arm["profile"]["name"], "hdembree", "{}", arm["profile"]);
    assert_eq!(arm["counts"]["posed_meshes"], 1);
    assert_eq!(arm["counts"]["refined_meshes"], 0);
    close(v3(&arm["bounds"]["min"]), [-0.5, -0.5, 0.0]);
    close(v3(&arm["bounds"]["max"]), [0.5, 0.5, 4.0]);
    let arm = report(arm_path, Some(1.0));
    assert_eq!(arm["counts"]["posed_meshes"], 1);
    assert_eq!(arm["counts"]["refined_meshes"], 1);
    let (lo, hi) = (v3(&arm["bounds"]["min"]), v3(&arm["bounds"]["max"]));
    for k in 0..3 {
        assert!(lo[k] >= [-0.5, -0.5, 0.0][k] - 1e-9 && hi[k] <= [0.5, 0.5, 4.0][k] + 1e-9);
    }
    // A cube left at the default scheme, with a camera 10 away.
    let cube = dir.join("cube.usda");
    std::fs::write(
        &cube,
        r#"#usda 1.0
def Mesh "Cube" {
    int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
    int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
    point3f[] points = [(-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1), (-1, -1, -1), (1, -1, -1)]
}
def Camera "Cam" {
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
"#,
    )
    .unwrap();
    let c = report(cube, None);
    assert_eq!(c["counts"]["refined_meshes"], 1);
    let limit = 68.0 / 81.0;
    close(v3(&c["bounds"]["min"]), [-limit; 3]);
    close(v3(&c["bounds"]["max"]), [limit; 3]);
    let drawing = report(
        root.join("tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLBasicLighting/basicDrawing.usda"),
        None,
    );
    let counts = &drawing["counts"];
    assert_eq!(counts["curves"], 3, "{counts}");
    assert!(
        counts["not_drawn"].as_object().unwrap().is_empty(),
        "{counts}"
    );
    // OpenUSD's instancing test: 7 meshes (default scheme) refined, 1 curve and 2 points
    // prims drawn through the instance, the Volume not drawn.
    let inst = report(
        root.join("tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/instance.usda"),
        None,
    );
    let counts = &inst["counts"];
    assert_eq!(
        [
            &counts["refined_meshes"],
            &counts["curves"],
            &counts["points"]
        ],
        [7, 1, 2],
        "{counts}"
    );
    assert_eq!(counts["not_drawn"]["Volume"], 1);
}
