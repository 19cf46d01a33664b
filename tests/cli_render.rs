//! `lux render` and `lux info` through the built binary: outputs, the profile chain in the
//! log, and failures that exit non-zero with a message and leave no output file behind.

use lux::render::image_io::Texture;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn luxtest(name: &str) -> PathBuf {
    root()
        .join("crates/lux-render/tests/data/luxtest/usd")
        .join(name)
}

fn lux(args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lux"));
    c.args(args).env_remove("LUX_CONFORMANCE_PROFILE");
    // Keep the user's config files out of the tests.
    c.env("XDG_CONFIG_HOME", tmp("no-config"));
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lux-cli-render-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn renders_exr_and_png_and_reports_speed_and_profile() {
    let exr = tmp("rect.exr");
    let png = tmp("rect.png");
    let scene = luxtest("rect.usda");
    let o = lux(
        &[
            "render",
            scene.to_str().unwrap(),
            "--frame",
            "1",
            "--spp",
            "4",
            "--resolution",
            "64x64",
            "--threads",
            "2",
            "-o",
            exr.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
            "--quiet",
        ],
        &[("LUX_CONFORMANCE_PROFILE", "hdembree")],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let log = stderr(&o);
    assert!(
        log.contains("profile hdembree (from environment variable LUX_CONFORMANCE_PROFILE)"),
        "{log}"
    );
    assert!(log.contains("samples/s") && log.contains("rays/s"), "{log}");
    let img = Texture::load(&exr).unwrap();
    assert_eq!((img.width(), img.height()), (64, 64));
    assert!(img.texels().iter().any(|p| p[0] > 0.0));
    let p = Texture::load(&png).unwrap();
    assert_eq!((p.width(), p.height()), (64, 64));
    // The flag beats the environment.
    let o = lux(
        &[
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "--resolution",
            "8x8",
            "--profile",
            "spec",
            "-o",
            exr.to_str().unwrap(),
            "--quiet",
        ],
        &[("LUX_CONFORMANCE_PROFILE", "hdembree")],
    );
    assert!(
        stderr(&o).contains("profile spec (from --profile flag)"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn crop_renders_only_the_window() {
    let exr = tmp("crop.exr");
    let o = lux(
        &[
            "render",
            luxtest("sphere.usda").to_str().unwrap(),
            "--spp",
            "2",
            "--resolution",
            "64x64",
            "--crop",
            "16,16,48,40",
            "-o",
            exr.to_str().unwrap(),
            "--quiet",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = Texture::load(&exr).unwrap();
    for (i, p) in img.texels().iter().enumerate() {
        let (x, y) = (i % 64, i / 64);
        let inside = (16..48).contains(&x) && (16..40).contains(&y);
        if !inside {
            assert_eq!(p[3], 0.0, "pixel {x},{y} outside the crop is empty");
        } else {
            assert_eq!(p[3], 1.0, "pixel {x},{y} inside the crop sees the floor");
        }
    }
}

#[test]
fn failures_exit_non_zero_and_leave_no_file() {
    let out = tmp("never.exr");
    let _ = std::fs::remove_file(&out);
    // Missing scene.
    let o = lux(
        &["render", "/no/such/scene.usda", "-o", out.to_str().unwrap()],
        &[],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("/no/such/scene.usda"), "{}", stderr(&o));
    assert!(!out.exists());
    // Bad crop, bad profile, bad environment value.
    let scene = luxtest("rect.usda");
    for (args, env, needle) in [
        (vec!["--crop", "10,10,5,20"], vec![], "crop"),
        (vec!["--profile", "karma"], vec![], "karma"),
        (
            vec![],
            vec![("LUX_CONFORMANCE_PROFILE", "fast")],
            "LUX_CONFORMANCE_PROFILE",
        ),
        (vec!["--spp", "0"], vec![], "samples per pixel"),
    ] {
        let mut a = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        a.extend(args);
        let o = lux(&a, &env);
        assert!(!o.status.success(), "{a:?} should fail");
        assert!(stderr(&o).contains(needle), "{a:?}: {}", stderr(&o));
        assert!(!out.exists(), "{a:?} left {}", out.display());
    }
    // An output directory that does not exist: the render runs, the write fails, nothing is
    // left behind.
    let missing = tmp("no-such-dir").join("x.exr");
    let o = lux(
        &[
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "--resolution",
            "8x8",
            "-o",
            missing.to_str().unwrap(),
            "--quiet",
        ],
        &[],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("x.exr"), "{}", stderr(&o));
    assert!(
        !missing.parent().unwrap().exists()
            || std::fs::read_dir(missing.parent().unwrap())
                .unwrap()
                .next()
                .is_none()
    );
}

#[test]
fn demo_scene_renders_every_light_kind_without_warnings() {
    let exr = tmp("demo.exr");
    let demo = root().join("scenes/demo/demo.usda");
    let o = lux(
        &[
            "render",
            demo.to_str().unwrap(),
            "--spp",
            "2",
            "--resolution",
            "64x36",
            "-o",
            exr.to_str().unwrap(),
            "--quiet",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let info = lux(&["info", demo.to_str().unwrap(), "--json"], &[]);
    assert!(info.status.success());
    let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let mut kinds: Vec<&str> = v["lights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["type"].as_str().unwrap())
        .collect();
    kinds.sort();
    assert_eq!(
        kinds,
        [
            "CylinderLight",
            "DiskLight",
            "DistantLight",
            "DomeLight",
            "RectLight",
            "SphereLight"
        ]
    );
    assert_eq!(v["profile"]["name"], "spec");
    assert_eq!(v["profile"]["source"], "default");
    assert_eq!(
        v["warnings"].as_array().unwrap().len(),
        0,
        "{}",
        v["warnings"]
    );
}
