//! `lux render --tile`, `lux merge` and `lux farm` through the built binary: tiles merge into
//! the single-process render bit for bit; merge refuses tiles that do not belong together and
//! then leaves no output; the OpenJD job template has both steps and the dependency.

use lux::render::image_io::{ExrBand, read_exr_band};
use std::path::{Path, PathBuf};
use std::process::Command;

fn luxtest(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/luxtest/usd")
        .join(name)
}

/// A fresh directory for one test.
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lux-cli-farm-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn lux(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lux"))
        .args(args)
        .env_remove("LUX_CONFORMANCE_PROFILE")
        .env(
            "XDG_CONFIG_HOME",
            std::env::temp_dir().join("lux-cli-farm-no-config"),
        )
        .output()
        .unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Small, quick render options that still exercise the penumbra pass (≥ 8 spp; `render`
/// replaces `--spp` and `--seed` given in its `extra`).
const OPTS: [&str; 10] = [
    "--spp",
    "8",
    "--resolution",
    "48x32",
    "--seed",
    "7",
    "--penumbra-samples",
    "2",
    "--frame",
    "1",
];

/// `lux render SCENE OPTS extra… -o out --quiet`, which must succeed.
fn render(scene: &Path, out: &Path, extra: &[&str]) {
    let mut a = vec!["render", scene.to_str().unwrap()];
    for pair in OPTS.chunks(2) {
        if !extra.contains(&pair[0]) {
            a.extend_from_slice(pair);
        }
    }
    a.extend_from_slice(extra);
    a.extend(["-o", out.to_str().unwrap(), "--threads", "2", "--quiet"]);
    let o = lux(&a);
    assert!(o.status.success(), "{a:?}: {}", stderr(&o));
}

fn bits(b: &ExrBand) -> Vec<u32> {
    b.image
        .pixels
        .iter()
        .flatten()
        .map(|v| v.to_bits())
        .collect()
}

/// Renders the frame whole and as 3 tiles (with `extra` options), merges, and compares bits.
fn tiles_equal_whole(test: &str, extra: &[&str]) -> ExrBand {
    let d = dir(test);
    let scene = luxtest("sphere.usda");
    let whole = d.join("whole.exr");
    let whole_png = d.join("whole.png");
    let mut e = extra.to_vec();
    e.extend(["--png", whole_png.to_str().unwrap()]);
    render(&scene, &whole, &e);
    let mut tiles = Vec::new();
    // Out of order on purpose.
    for i in [2, 0, 1] {
        let t = d.join(format!("tiles/t{i}.exr"));
        let spec = format!("{i}/3");
        let mut e = extra.to_vec();
        e.extend(["--tile", &spec]);
        render(&scene, &t, &e);
        let band = read_exr_band(&t).unwrap();
        let rows = [[0, 9], [10, 20], [21, 31]][i];
        assert_eq!(band.y0, rows[0]);
        assert_eq!(band.image.height, rows[1] - rows[0] + 1);
        assert_eq!(band.display, [48, 32]);
        assert_eq!(band.attributes["lux:tile"], spec);
        assert_eq!(
            band.attributes["lux:rows"],
            format!("{}-{}", rows[0], rows[1])
        );
        tiles.push(t);
    }
    let merged = d.join("out/merged.exr");
    let png = d.join("out/merged.png");
    let mut a = vec!["merge"];
    a.extend(tiles.iter().map(|t| t.to_str().unwrap()));
    a.extend([
        "-o",
        merged.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    let o = lux(&a);
    assert!(o.status.success(), "{}", stderr(&o));
    // The merged PNG is the single-process render's, byte for byte (opaque RGB, as `render`
    // writes without --alpha).
    assert_eq!(
        std::fs::read(&png).unwrap(),
        std::fs::read(&whole_png).unwrap(),
        "merged PNG"
    );
    let (w, m) = (
        read_exr_band(&whole).unwrap(),
        read_exr_band(&merged).unwrap(),
    );
    assert_eq!((m.image.width, m.image.height, m.y0), (48, 32, 0));
    assert_eq!(
        bits(&m),
        bits(&w),
        "merged tiles differ from the whole render"
    );
    assert_eq!(m.attributes, w.attributes);
    for k in ["lux:scene", "lux:frame", "lux:settings", "lux:resolution"] {
        assert!(w.attributes.contains_key(k), "{k}: {:?}", w.attributes);
    }
    assert_eq!(w.attributes["lux:frame"], "1");
    assert_eq!(w.attributes["lux:resolution"], "48x32");
    assert!(w.attributes["lux:settings"].contains("spp=8;"));
    assert!(!w.attributes.contains_key("lux:tile"));
    w
}

#[test]
fn three_tiles_merge_into_the_single_process_render_bit_for_bit() {
    let w = tiles_equal_whole("whole", &[]);
    assert!(w.image.pixels.iter().filter(|p| p[3] > 0.0).count() > 100);
    assert!(w.image.pixels.iter().any(|p| p[0] > 0.0));
}

#[test]
fn tiles_of_a_crop_merge_bit_for_bit_even_when_a_tile_is_outside_it() {
    // The crop's rows 2..9 lie in tile 0 only: tiles 1 and 2 render nothing.
    let w = tiles_equal_whole("crop", &["--crop", "5,2,40,9"]);
    let mut lit = 0;
    for (i, p) in w.image.pixels.iter().enumerate() {
        let (x, y) = (i % 48, i / 48);
        let inside = (5..40).contains(&x) && (2..9).contains(&y);
        if inside {
            lit += usize::from(p[3] > 0.0);
        } else {
            assert_eq!(*p, [0.0; 4], "{x},{y}");
        }
    }
    assert!(lit > 0);
}

/// `lux merge tiles… -o out` must fail with a message containing `needle`, leaving nothing.
fn refuses(d: &Path, tiles: &[&Path], needle: &str) {
    let out = d.join("merged.exr");
    let png = d.join("merged.png");
    let mut a = vec!["merge"];
    a.extend(tiles.iter().map(|t| t.to_str().unwrap()));
    a.extend(["-o", out.to_str().unwrap(), "--png", png.to_str().unwrap()]);
    let o = lux(&a);
    assert!(!o.status.success());
    let log = stderr(&o);
    assert!(log.contains(needle), "expected {needle:?} in: {log}");
    assert!(!out.exists() && !png.exists(), "{log}");
    let stray: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".merged"))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");
}

#[test]
fn merge_refuses_missing_duplicate_and_foreign_tiles() {
    let d = dir("refuse");
    let scene = luxtest("sphere.usda");
    let t: Vec<PathBuf> = (0..3).map(|i| d.join(format!("t{i}.exr"))).collect();
    for (i, p) in t.iter().enumerate() {
        render(&scene, p, &["--tile", &format!("{i}/3")]);
    }
    let spp = d.join("spp.exr");
    render(&scene, &spp, &["--tile", "1/3", "--spp", "4"]);
    let seed = d.join("seed.exr");
    render(&scene, &seed, &["--tile", "1/3", "--seed", "8"]);
    let of4 = d.join("of4.exr");
    render(&scene, &of4, &["--tile", "1/4"]);
    let whole = d.join("whole.exr");
    render(&scene, &whole, &[]);

    refuses(&d, &[&t[0], &t[2]], "tile 1/3 missing");
    refuses(&d, &[&t[0], &t[1], &t[1], &t[2]], "given twice");
    refuses(&d, &[&t[0], &t[1], &t[1], &t[2]], t[1].to_str().unwrap());
    // lux:settings differ (the spp, the seed): the message names the file.
    let msg = format!("{}: lux:settings", spp.display());
    refuses(&d, &[&t[0], &spp, &t[2]], &msg);
    let msg = format!("{}: lux:settings", seed.display());
    refuses(&d, &[&t[0], &seed, &t[2]], &msg);
    refuses(&d, &[&t[0], &of4, &t[2]], &of4.display().to_string());
    refuses(&d, &[&t[0], &whole], "not a lux tile");
    // And the good set merges.
    let o = lux(&[
        "merge",
        t[0].to_str().unwrap(),
        t[1].to_str().unwrap(),
        t[2].to_str().unwrap(),
        "-o",
        d.join("merged.exr").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn render_refuses_bad_tiles() {
    let d = dir("badtile");
    let scene = luxtest("sphere.usda");
    let out = d.join("t.exr");
    for (tile, needle) in [
        ("3/3", "0 ≤ I < N"),
        ("1/0", "0 ≤ I < N"),
        ("a/3", "not a non-negative integer"),
        ("0/33", "exceed the image height of 32"),
    ] {
        let mut a = vec!["render", scene.to_str().unwrap()];
        a.extend_from_slice(&OPTS);
        a.extend(["--tile", tile, "-o", out.to_str().unwrap(), "--quiet"]);
        let o = lux(&a);
        assert!(!o.status.success(), "{tile}");
        assert!(stderr(&o).contains(needle), "{tile}: {}", stderr(&o));
        assert!(!out.exists());
    }
}

#[test]
fn farm_writes_an_openjd_template_with_render_and_merge_steps() {
    let d = dir("farm");
    let scene = luxtest("sphere.usda");
    let job = d.join("job.yaml");
    let frames = d.join("frames");
    let o = lux(&[
        "farm",
        scene.to_str().unwrap(),
        "--frames",
        "1-2",
        "--tiles",
        "3",
        "--output-dir",
        frames.to_str().unwrap(),
        "-o",
        job.to_str().unwrap(),
        "--png",
        "--",
        "--spp",
        "4",
        "--resolution",
        "48x32",
        "--alpha",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let y = std::fs::read_to_string(&job).unwrap();
    let lines: Vec<&str> = y.lines().collect();
    let has = |l: &str| lines.contains(&l);
    assert!(has("specificationVersion: jobtemplate-2023-09"), "{y}");
    for l in [
        "- name: ScenePath",
        "- name: OutputDir",
        "- name: Lux",
        "steps:",
        "- name: Render",
        "- name: Merge",
        "  dependencies:",
        "  - dependsOn: Render",
        "    - name: Frame",
        "    - name: Tile",
        "      type: INT",
        "      range: \"1-2\"",
        "      range: \"0-2\"",
        "        command: \"{{Param.Lux}}\"",
    ] {
        assert!(has(l), "missing line {l:?} in\n{y}");
    }
    // The Merge step (after Render) depends on it and has only the Frame parameter.
    let render = y.find("- name: Render").unwrap();
    let merge = y.find("- name: Merge").unwrap();
    assert!(render < merge);
    let merge_step = &y[merge..];
    assert!(merge_step.contains("dependsOn: Render") && !merge_step.contains("name: Tile"));
    // Every top-level key and list item is at a consistent indentation (2 spaces per level).
    for l in &lines {
        let indent = l.len() - l.trim_start().len();
        assert!(indent % 2 == 0 && !l.contains('\t'), "{l:?}");
    }
    let render_args = lines
        .iter()
        .find(|l| l.contains("\"render\""))
        .expect("render args");
    for a in [
        "\"{{Param.ScenePath}}\"",
        "\"--frame\", \"{{Task.Param.Frame}}\"",
        "\"--tile\", \"{{Task.Param.Tile}}/3\"",
        "\"--spp\", \"4\", \"--resolution\", \"48x32\"",
        "\"-o\", \"{{Param.OutputDir}}/sphere.{{Task.Param.Frame}}.tile{{Task.Param.Tile}}.exr\"",
    ] {
        assert!(render_args.contains(a), "{a} in {render_args}");
    }
    let merge_args = lines
        .iter()
        .find(|l| l.contains("\"merge\""))
        .expect("merge args");
    for i in 0..3 {
        let t = format!("\"{{{{Param.OutputDir}}}}/sphere.{{{{Task.Param.Frame}}}}.tile{i}.exr\"");
        assert!(merge_args.contains(&t), "{t} in {merge_args}");
    }
    assert!(merge_args.contains("\"-o\", \"{{Param.OutputDir}}/sphere.{{Task.Param.Frame}}.exr\""));
    // --alpha is for the PNG, which the merge writes.
    assert!(
        merge_args.contains(
            "\"--png\", \"{{Param.OutputDir}}/sphere.{{Task.Param.Frame}}.png\", \"--alpha\""
        ),
        "{merge_args}"
    );
    // OpenJD wants default paths relative to the template's directory.
    assert!(has("  default: \"frames\""), "{y}");
    // and none outside it: the scene has no default.
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("  # (no default: ") && l.contains("sphere.usda")),
        "{y}"
    );

    // Render options the template sets itself, or that lux render rejects, are refused.
    for bad in [&["--frame", "3"][..], &["--tile", "0/2"], &["--spp", "x"]] {
        let mut a = vec![
            "farm",
            scene.to_str().unwrap(),
            "--frames",
            "1-2",
            "-o",
            job.to_str().unwrap(),
            "--",
        ];
        a.extend_from_slice(bad);
        let before = std::fs::read_to_string(&job).unwrap();
        let o = lux(&a);
        assert!(!o.status.success(), "{bad:?}");
        assert_eq!(std::fs::read_to_string(&job).unwrap(), before);
    }
    // Render options also pass through without `--`.
    let o = lux(&[
        "farm",
        scene.to_str().unwrap(),
        "--frames",
        "4",
        "-o",
        job.to_str().unwrap(),
        "--spp",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let y = std::fs::read_to_string(&job).unwrap();
    assert!(
        y.contains("range: \"4-4\"") && y.contains("\"--spp\", \"2\""),
        "{y}"
    );
}
