//! `lux render` and `lux info` through the built binary: outputs, the profile chain in the
//! log, and failures that exit non-zero with a message and leave no output file behind.

mod common;

use common::cli::{lux, render_small};
use lux::render::image_io::Texture;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn luxtest(name: &str) -> PathBuf {
    root().join("tests/data/luxtest/usd").join(name)
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
    let o = render_small(
        &scene,
        &exr,
        &["--profile", "spec"],
        &[("LUX_CONFORMANCE_PROFILE", "hdembree")],
    );
    assert!(
        stderr(&o).contains("profile spec (from --profile flag)"),
        "{}",
        stderr(&o)
    );
}

/// `--fsync` forces the outputs to disk before they replace their targets; what it writes is
/// what the render writes without it, bit for bit, and nothing else is left in the directory.
#[test]
fn fsync_writes_the_same_files() {
    let scene = luxtest("sphere.usda");
    let dir = tmp("fsync");
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for (name, extra) in [("plain", &[][..]), ("synced", &["--fsync"][..])] {
        let exr = dir.join(format!("{name}.exr"));
        let png = dir.join(format!("{name}.png"));
        let mut args = vec!["--png", png.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = render_small(&scene, &exr, &args, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        files.push([std::fs::read(&exr).unwrap(), std::fs::read(&png).unwrap()]);
    }
    assert!(files[0][0].len() > 100 && files[0][1].len() > 50);
    assert!(files[0] == files[1], "--fsync changed the written bytes");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["plain.exr", "plain.png", "synced.exr", "synced.png"]
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
    let o = render_small(&scene, &missing, &[], &[]);
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
fn info_failures_exit_non_zero_naming_the_file_and_prim() {
    let bad = root().join("tests/data/scenes/bad");
    // missing file
    let o = lux(&["info", "/no/such/stage.usda"], &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("/no/such/stage.usda"), "{}", stderr(&o));
    // a reference cycle: usd-core's policy composes without the arc and says so (layer and
    // prim named); --strict makes it an error
    let cycle = bad.join("cycle_a.usda");
    let o = lux(&["info", cycle.to_str().unwrap(), "--json"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let warned = v["warnings"].as_array().unwrap().iter().any(|w| {
        let w = w.as_str().unwrap();
        w.contains("cycle_a.usda") && w.contains("</A>") && w.contains("cycle")
    });
    assert!(warned, "{}", v["warnings"]);
    let o = lux(
        &["info", cycle.to_str().unwrap(), "--json", "--strict"],
        &[],
    );
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("cycle_a.usda") && e.contains("/A") && e.contains("cycle"),
        "{e}"
    );
    assert!(o.stdout.is_empty(), "no partial report on stdout");
    // malformed layer text
    let garbage = tmp("garbage.usda");
    std::fs::write(&garbage, "#usda 1.0\ndef Xform \"A\" {\n  float x = \n").unwrap();
    let o = lux(&["info", garbage.to_str().unwrap()], &[]);
    assert!(!o.status.success());
    // the file, the line and the column of the parse failure
    assert!(
        stderr(&o).contains("garbage.usda:3:11: Unexpected end of tokens"),
        "{}",
        stderr(&o)
    );
    // and a good stage succeeds, with the light's world position and axis in the report
    let o = lux(
        &["info", luxtest("rect.usda").to_str().unwrap(), "--json"],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let l = &v["lights"][0];
    assert_eq!(l["type"], "RectLight");
    // frame 1: the light's own transform is a 45° tilt about X at (0, 1, 0) under an identity
    // parent, so its −Z axis is (0, −√½, −√½)
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for (key, want) in [("position", [0.0, 1.0, 0.0]), ("axis", [0.0, -h, -h])] {
        let got: Vec<f64> = l[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{key}: {got:?} vs {want:?}");
        }
    }
}

#[test]
fn a_failed_png_leaves_no_exr_either() {
    // The render succeeds and the EXR could be written, but the PNG's folder does not exist:
    // both outputs are staged before either is renamed, so the EXR's folder stays empty (no
    // EXR, no temporary file).
    let dir = tmp("pair-out");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("image.exr");
    let scene = luxtest("rect.usda");
    let render = |png: &Path| render_small(&scene, &exr, &["--png", png.to_str().unwrap()], &[]);
    let o = render(&tmp("pair-no-such-dir").join("image.png"));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("image.png"), "{}", stderr(&o));
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    // the same command with a valid PNG path writes both
    let png = dir.join("image.png");
    let o = render(&png);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(exr.is_file() && png.is_file());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
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

/// Decodes a PNG, returning its colour type and pixels as RGBA8.
fn read_png(path: &Path) -> (image::ColorType, image::RgbaImage) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png).unwrap();
    (img.color(), img.to_rgba8())
}

#[test]
fn the_output_extension_picks_the_format() {
    let scene = luxtest("rect.usda");
    // -o x.png: a real PNG, opaque (RGB, no alpha channel)
    let png = tmp("ext.png");
    let _ = std::fs::remove_file(&png);
    let o = render_small(&scene, &png, &[], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (color, img) = read_png(&png);
    assert_eq!(color, image::ColorType::Rgb8);
    assert_eq!(img.dimensions(), (8, 8));
    assert!(img.pixels().all(|p| p[3] == 255));
    // --alpha keeps the coverage: RGBA
    let o = render_small(&scene, &png, &["--alpha"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_png(&png).0, image::ColorType::Rgba8);
    // -o x.EXR: an EXR whatever the case of the extension
    let exr = tmp("ext.EXR");
    let o = render_small(&scene, &exr, &[], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        &std::fs::read(&exr).unwrap()[..4],
        &[0x76, 0x2f, 0x31, 0x01]
    );
    // unknown and missing extensions are refused before anything is read or written
    for name in ["ext.txt", "ext", "ext.jpg"] {
        let out = tmp(name);
        let _ = std::fs::remove_file(&out);
        let o = render_small(&scene, &out, &[], &[]);
        assert!(!o.status.success(), "{name} should be refused");
        let e = stderr(&o);
        assert!(
            e.contains(name) && e.contains(".exr") && e.contains(".png"),
            "{e}"
        );
        assert!(!e.contains("profile"), "refused after loading: {e}");
        assert!(!out.exists(), "{name} was written");
    }
}

#[test]
fn the_png_flag_is_opaque_too() {
    let exr = tmp("pngflag.exr");
    let png = tmp("pngflag.png");
    let o = render_small(
        &luxtest("rect.usda"),
        &exr,
        &["--png", png.to_str().unwrap()],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_png(&png).0, image::ColorType::Rgb8);
    assert!(Texture::load(&exr).is_ok());
}

#[test]
fn arguments_are_checked_before_the_stage_is_read() {
    // The scene does not exist: each argument error must come first.
    let out = tmp("early.exr");
    for (args, needle) in [
        (vec!["--spp", "0"], "--spp 0"),
        (vec!["--spp", "2000000"], "--spp 2000000"),
        (vec!["--max-depth", "0"], "--max-depth 0"),
        (vec!["--max-depth", "129"], "--max-depth 129"),
        (vec!["--light-samples", "65"], "--light-samples 65"),
        (vec!["--penumbra-samples", "0"], "--penumbra-samples 0"),
        (vec!["--shadow-rays", "65"], "--shadow-rays 65"),
        (vec!["--adaptive-max", "0"], "--adaptive-max 0"),
        (vec!["--adaptive-max", "1025"], "--adaptive-max 1025"),
        (vec!["--adaptive-threshold", "0"], "--adaptive-threshold 0"),
        (
            vec!["--adaptive-threshold", "-1"],
            "--adaptive-threshold -1",
        ),
        (
            vec!["--adaptive-threshold", "inf"],
            "--adaptive-threshold inf",
        ),
        (
            vec!["--no-adaptive", "--adaptive-max", "4"],
            "--no-adaptive",
        ),
        (vec!["--threads", "0"], "--threads 0"),
    ] {
        let mut a = vec!["render", "/no/such/scene.usda", "-o", out.to_str().unwrap()];
        a.extend(&args);
        let o = lux(&a, &[]);
        assert!(!o.status.success(), "{args:?}");
        let e = stderr(&o);
        assert!(e.contains(needle), "{args:?}: {e}");
        assert!(
            !e.contains("scene.usda"),
            "{args:?}: the stage was read first: {e}"
        );
    }
    let o = lux(&["render", "/no/such/scene.usda", "-o", "/tmp/x.tiff"], &[]);
    assert!(
        stderr(&o).contains("unknown output format .tiff"),
        "{}",
        stderr(&o)
    );
    // An output folder that does not exist is found before rendering as well.
    let o = lux(
        &[
            "render",
            "/no/such/scene.usda",
            "-o",
            tmp("no-such-folder").join("x.exr").to_str().unwrap(),
        ],
        &[],
    );
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("scene.usda"), "{}", stderr(&o));
}

#[test]
fn a_directory_as_scene_is_called_a_directory() {
    let dir = root().join("scenes/demo");
    let o = lux(
        &[
            "render",
            dir.to_str().unwrap(),
            "-o",
            tmp("dir.exr").to_str().unwrap(),
        ],
        &[],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no such file"), "{}", stderr(&o));
    let o = lux(&["info", dir.to_str().unwrap()], &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
}

/// Runs `lux ARGS` with stdout a pipe whose read end is closed at once, before the report is
/// written: the write meets a broken pipe.
fn closed_pipe(args: &[&str]) -> std::process::Output {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_lux"))
        .args(args)
        .env_remove("LUX_CONFORMANCE_PROFILE")
        .env("XDG_CONFIG_HOME", tmp("no-config"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    child.wait_with_output().unwrap()
}

#[test]
fn a_closed_stdout_pipe_ends_quietly() {
    let demo = root().join("scenes/demo/demo.usda");
    let ies = root().join("tests/data/ies/luxtest/bega_omni002_4777lm.ies");
    for args in [
        vec!["info", demo.to_str().unwrap()],
        vec!["info", demo.to_str().unwrap(), "--json"],
        vec!["ies", "info", ies.to_str().unwrap()],
        vec!["ies", "info", ies.to_str().unwrap(), "--json"],
    ] {
        let o = closed_pipe(&args);
        let e = stderr(&o);
        assert!(
            !e.contains("panicked") && !e.contains("Broken pipe"),
            "{args:?}: {e}"
        );
        assert_eq!(o.status.code(), Some(0), "{args:?}: {e}");
    }
}

#[test]
fn counts_are_singular_for_one() {
    let o = lux(&["info", luxtest("rect.usda").to_str().unwrap()], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("1 camera,") && text.contains("1 light\n"),
        "{text}"
    );
    for wrong in [
        "1 cameras",
        "1 lights",
        "1 meshes",
        "1 prims",
        "1 triangles",
    ] {
        assert!(!text.contains(wrong), "{wrong}: {text}");
    }
}

/// The samples a pixel took on average, as a successful render's closing summary gives them
/// (`… (12.34 a pixel) …`).
fn samples_a_pixel(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    let log = stderr(o);
    log.split(" a pixel)")
        .next()
        .and_then(|s| s.rsplit('(').next())
        .unwrap_or_else(|| panic!("no sample count: {log}"))
        .to_owned()
}

/// `--adaptive-measure` without `--adaptive-threshold` takes that measure's own default
/// threshold (perceived 0.01, linear 0.1), whatever measure the integrator would default to:
/// the same samples (the closing summary's count) and the same pixels as with the threshold
/// written out, and another count than the integrator's default measure.
#[test]
fn an_adaptive_measure_alone_takes_its_own_default_threshold() {
    let sphere = luxtest("sphere.usda");
    let cornell = root().join("tests/data/cornell/cornell.usda");
    let run = |scene: &Path, args: &[&str], name: &str| -> (String, Vec<u8>) {
        let png = tmp(name);
        let mut all = vec![
            "render",
            scene.to_str().unwrap(),
            "--frame",
            "1",
            "--spp",
            "2",
            "--resolution",
            "32x32",
            "--max-depth",
            "3",
            "-o",
            png.to_str().unwrap(),
        ];
        all.extend_from_slice(args);
        let o = lux(&all, &[]);
        (samples_a_pixel(&o), read_png(&png).1.into_raw())
    };
    for (scene, integrator, other, t) in [
        (&sphere, "direct", "linear", "0.1"),
        (&cornell, "path", "perceived", "0.01"),
    ] {
        let base = ["--integrator", integrator];
        let alone = run(
            scene,
            &[&base[..], &["--adaptive-measure", other]].concat(),
            "a.png",
        );
        let spelled = run(
            scene,
            &[
                &base[..],
                &["--adaptive-measure", other, "--adaptive-threshold", t],
            ]
            .concat(),
            "b.png",
        );
        let default = run(scene, &base, "c.png");
        assert_eq!(alone, spelled, "{integrator}, --adaptive-measure {other}");
        assert_ne!(
            alone.0, default.0,
            "{integrator}: the measure changes the counts"
        );
    }
}

/// `--adaptive-splits`: the path tracer's default is 8 (the same samples and pixels as written
/// out), 1 turns adaptive splitting off (other counts: fewer, costlier samples where it splits),
/// and a count outside 1–64 is an error naming it, leaving no file.
#[test]
fn adaptive_splits_default_off_and_out_of_range() {
    let cornell = root().join("tests/data/cornell/cornell.usda");
    let png = tmp("splits.png");
    let run = |extra: &[&str]| {
        let mut all = vec![
            "render",
            cornell.to_str().unwrap(),
            "--integrator",
            "path",
            "--spp",
            "4",
            "--resolution",
            "32x32",
            "-o",
            png.to_str().unwrap(),
        ];
        all.extend_from_slice(extra);
        let _ = std::fs::remove_file(&png);
        lux(&all, &[])
    };
    let count = |o: &std::process::Output| (samples_a_pixel(o), read_png(&png).1.into_raw());
    let default = count(&run(&[]));
    assert_eq!(default, count(&run(&["--adaptive-splits", "8"])));
    assert_ne!(default.0, count(&run(&["--adaptive-splits", "1"])).0);
    for bad in ["0", "65"] {
        let o = run(&["--adaptive-splits", bad]);
        assert!(!o.status.success());
        assert!(
            stderr(&o).contains(&format!("adaptive splits {bad}: expected 1 to 64")),
            "{}",
            stderr(&o)
        );
        assert!(!png.exists());
    }
}
