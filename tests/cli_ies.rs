//! Integration tests of `lux ies info|convert|plot` through the built binary.

use std::path::{Path, PathBuf};
use std::process::Command;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ies")
        .join(rel)
}

fn lux(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lux"))
        .args(args)
        .output()
        .unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lux-cli-ies-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn info_json_reports_the_expected_values() {
    let f = data("luxtest/bega_omni002_4777lm.ies");
    let out = lux(&["ies", "info", f.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["edition"], 1991);
    assert_eq!(v["photometric_type"], "C");
    assert_eq!(v["num_vertical"], 73);
    assert_eq!(v["num_horizontal"], 37);
    let flux = v["flux_lm"].as_f64().unwrap();
    assert!((flux - 4779.19).abs() < 0.02, "{flux}");
    let mean = v["mean_intensity_cd"].as_f64().unwrap();
    assert!((mean - flux / (4.0 * std::f64::consts::PI)).abs() < 1e-9);
    assert!((v["max_cd"].as_f64().unwrap() - 2734.7).abs() < 0.05);
    // text mode works too
    let out = lux(&["ies", "info", f.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("LM-63-1991"));
}

#[test]
fn malformed_input_fails_with_file_line_column() {
    let f = data("mdl-sdk/test_file_format_error.ies");
    let out = lux(&["ies", "info", f.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("{}:3:1:", f.display())), "{err}");
    let f = data("appleseed/test_iesparser_5.ies");
    let out = lux(&["ies", "info", f.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains(":27:1:"));
}

#[test]
fn convert_to_2019_and_back() {
    let f = data("lidrs/iesna2002_example_typec.ies");
    let o = tmp("c2019.ies");
    let out = lux(&[
        "ies",
        "convert",
        f.to_str().unwrap(),
        "-o",
        o.to_str().unwrap(),
        "--edition",
        "2019",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&o).unwrap();
    assert!(text.starts_with("IES:LM-63-2019"));
    let a = lux_ies::IesFile::parse(&std::fs::read_to_string(&f).unwrap()).unwrap();
    let b = lux_ies::IesFile::parse(&text).unwrap();
    assert_eq!(b.edition, lux_ies::Edition::Lm63_2019);
    assert_eq!((a.candela, a.header, a.tilt), (b.candela, b.header, b.tilt));
}

/// `lux ies plot F -o O [extra…]`.
fn plot(f: &std::path::Path, o: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut a = vec![
        "ies",
        "plot",
        f.to_str().unwrap(),
        "-o",
        o.to_str().unwrap(),
    ];
    a.extend_from_slice(extra);
    lux(&a)
}

/// [`plot`], which must succeed.
fn plot_ok(f: &std::path::Path, o: &std::path::Path, extra: &[&str]) {
    let out = plot(f, o, extra);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn plot_writes_a_png_with_both_plane_pairs() {
    let f = data("luxtest/bega_84659K4.ies");
    let o = tmp("polar.png");
    plot_ok(&f, &o, &["--size", "400"]);
    let img = image::open(&o).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (400, 400));
    let red = img.pixels().filter(|p| p.0 == [220, 30, 30]).count();
    let blue = img.pixels().filter(|p| p.0 == [30, 60, 220]).count();
    assert!(red > 100 && blue > 100, "red {red} blue {blue}");
}

#[test]
fn plot_refuses_other_formats_and_leaves_no_file() {
    let f = data("luxtest/bega_84659K4.ies");
    let o = tmp("polar.jpg");
    let _ = std::fs::remove_file(&o);
    let out = plot(&f, &o, &[]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains(".png"));
    assert!(!o.exists());
}

#[test]
fn svg_plot_is_labelled() {
    let f = data("luxtest/bega_omni002_4777lm.ies");
    let o = tmp("polar.svg");
    plot_ok(&f, &o, &[]);
    let svg = std::fs::read_to_string(&o).unwrap();
    assert!(svg.starts_with("<svg"), "{svg}");
    // title: file name and total lumens; legend; angle labels; a candela scale
    assert!(svg.contains("bega_omni002_4777lm.ies — 4779 lm"), "{svg}");
    assert!(svg.contains("C0–C180") && svg.contains("C90–C270"));
    for a in ["0°", "30°", "90°", "180°"] {
        assert!(svg.contains(&format!(">{a}<")), "{a}");
    }
    assert!(svg.contains(" cd</text>"));
    assert_eq!(svg.matches("<path").count(), 2);
}

/// The value of attribute `name` in an SVG element's line.
fn attr<'a>(line: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = line.find(&key)? + key.len();
    Some(&line[start..start + line[start..].find('"')?])
}

fn num(line: &str, name: &str) -> f64 {
    attr(line, name).unwrap().parse().unwrap()
}

/// The same file plotted as SVG and as PNG at the default size: wherever the SVG places a label
/// (title, ring values, angle labels, legend), the PNG has ink (dark pixels: text; the grid is
/// light grey and the curves saturated red and blue); the lower half inside the rings, with
/// curves and grid but no label, has none. Before the PNG had labels it had no ink at all.
#[test]
fn png_plot_is_labelled_where_the_svg_is() {
    let f = data("luxtest/bega_omni002_4777lm.ies");
    let (svg_path, png_path) = (tmp("labels.svg"), tmp("labels.png"));
    for o in [&svg_path, &png_path] {
        plot_ok(&f, o, &[]);
    }
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let img = image::open(&png_path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (800, 800));
    let count = |x0: f64, y0: f64, x1: f64, y1: f64, pred: &dyn Fn(&image::Rgb<u8>) -> bool| {
        let clamp = |v: f64| v.clamp(0.0, 800.0) as u32;
        let mut n = 0;
        for y in clamp(y0)..clamp(y1) {
            for x in clamp(x0)..clamp(x1) {
                n += usize::from(pred(img.get_pixel(x, y)));
            }
        }
        n
    };
    let ink = |p: &image::Rgb<u8>| p.0.iter().all(|&c| c < 128);
    let font = num(svg.lines().next().unwrap(), "font-size");
    let mut texts = Vec::new();
    for line in svg.lines().filter(|l| l.starts_with("<text")) {
        let (x, y) = (num(line, "x"), num(line, "y"));
        let fs = attr(line, "font-size").map_or(font, |v| v.parse().unwrap());
        let text = &line[line.find('>').unwrap() + 1..line.find("</text>").unwrap()];
        // the box the SVG's text covers, widths estimated at 0.6 em a character
        let w = text.chars().count() as f64 * 0.6 * fs;
        let (x0, x1) = match attr(line, "text-anchor") {
            Some("middle") => (x - w / 2.0, x + w / 2.0),
            Some("end") => (x - w, x),
            _ => (x, x + w),
        };
        let (y0, y1) = if attr(line, "dominant-baseline") == Some("middle") {
            (y - 0.6 * fs, y + 0.6 * fs)
        } else {
            (y - fs, y + 0.3 * fs)
        };
        let n = count(x0, y0, x1, y1, &ink);
        assert!(
            n >= 20,
            "{text:?}: {n} ink pixels in the PNG at the SVG's label"
        );
        texts.push(text.to_owned());
    }
    // title, a value per ring, 12 angle labels, 2 legend entries
    let rings = svg.matches("<circle").count();
    assert!(rings >= 2, "{svg}");
    assert_eq!(texts.len(), 1 + rings + 12 + 2, "{texts:?}");
    assert!(texts[0].starts_with("bega_omni002_4777lm.ies"), "{texts:?}");
    // the lower half inside the outer ring: curves and grid, no ink
    let outer = svg.lines().rfind(|l| l.starts_with("<circle")).unwrap();
    let (cx, cy, r) = (num(outer, "cx"), num(outer, "cy"), num(outer, "r"));
    let region = (cx - 0.5 * r, cy + 0.2 * r, cx + 0.5 * r, cy + 0.8 * r);
    let drawn = count(region.0, region.1, region.2, region.3, &|p| p.0 != [255; 3]);
    assert!(drawn > 200, "{drawn} curve and grid pixels");
    assert_eq!(count(region.0, region.1, region.2, region.3, &ink), 0);
}
