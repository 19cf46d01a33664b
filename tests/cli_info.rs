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

/// Every bound material with its shading model (its MaterialX graph's surface nodedef) and the
/// graph's notes; a MaterialX surface under `outputs:mtlx:surface` is not "default grey".
#[test]
fn materials_name_their_shading_model_and_notes() {
    let mut args = info::InfoArgs {
        scene: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/materials_mtlx.usda"),
        frame: Some(1.0),
        json: true,
        strict: false,
        disable_camera_light: false,
        subdiv_level: None,
    };
    let v: serde_json::Value = serde_json::from_str(&info::report(&args).unwrap()).unwrap();
    let materials = v["materials"].as_array().unwrap();
    assert_eq!(materials.len(), 2, "{v:#}");
    let m = |p: &str| materials.iter().find(|m| m["path"] == p).unwrap();
    let preview = m("/World/Looks/Preview");
    assert_eq!(preview["preview_surface"], true);
    assert_eq!(preview["model"], "ND_UsdPreviewSurface_surfaceshader");
    let standard = m("/World/Looks/Standard");
    assert_eq!(standard["preview_surface"], false);
    assert_eq!(standard["model"], "ND_standard_surface_surfaceshader");
    // An input standard_surface does not declare is a note of the graph; an object-space
    // normal, read in world space, is one of the renderer's compiler.
    let notes = standard["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 2, "{notes:#?}");
    assert!(
        notes[0].as_str().unwrap().contains("no_such_input"),
        "{notes:#?}"
    );
    assert!(
        notes[1].as_str().unwrap().contains("read in world space"),
        "{notes:#?}"
    );
    let warnings = v["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .all(|w| !w.as_str().unwrap().contains("not UsdPreviewSurface")),
        "{warnings:#?}"
    );
    args.json = false;
    let text = info::report(&args).unwrap();
    assert!(
        text.contains("material /World/Looks/Preview (ND_UsdPreviewSurface_surfaceshader)\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "material /World/Looks/Standard (ND_standard_surface_surfaceshader)\n  note: "
        ),
        "{text}"
    );
}
