//! `lux info` report, exercised through the module itself (the binary wiring is the lead's).

#[path = "../src/cli/info.rs"]
#[allow(dead_code)]
mod info;

use std::path::PathBuf;

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/lux-render/tests/data/luxtest/usd")
        .join(name)
}

#[test]
fn json_report_of_rect_frame_11() {
    // rect frame 11: intensity 5, normalize on, width 0.2, height 2 → sizeFactor 0.4, L = 12.5.
    let args = info::InfoArgs {
        scene: scene("rect.usda"),
        frame: 11.0,
        json: true,
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
        frame: 1.0,
        json: false,
    };
    let e = info::report(&args).unwrap_err();
    assert!(e.contains("nope.usda") && e.contains("no such file"), "{e}");
}
