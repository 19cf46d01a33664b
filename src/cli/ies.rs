//! `lux ies info|convert|plot`: summary, edition conversion and polar candela diagram of an
//! IES LM-63 file.

use clap::Subcommand;
use lux_ies::{Edition, IesFile, ParseOptions, Parsed, PhotometricWeb};
use lux_math::Profile;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// IES file tools.
#[derive(Debug, Subcommand)]
pub enum IesCommand {
    /// Print a summary of an IES file: edition, type, counts, symmetry, multipliers, flux,
    /// mean intensity, peak, beam and field angles, warnings.
    Info {
        /// The IES file.
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Rewrite an IES file as LM-63-2002 or LM-63-2019.
    Convert {
        /// The IES file.
        file: PathBuf,
        /// Output file.
        #[arg(short, long)]
        output: PathBuf,
        /// Target edition: 2002 or 2019.
        #[arg(long, default_value = "2002", value_parser = ["2002", "2019"])]
        edition: String,
    },
    /// Draw the polar candela diagram (C0–C180 and C90–C270 planes) with the title (file
    /// name, total lumens), candela scale, angle labels and plane legend: as SVG, or as a PNG
    /// with the same layout and labels in a bitmap font.
    Plot {
        /// The IES file.
        file: PathBuf,
        /// Output: .svg or .png (both labelled).
        #[arg(short, long)]
        output: PathBuf,
        /// Image size in pixels (square).
        #[arg(long, default_value_t = 800)]
        size: u32,
    },
}

/// Runs an `ies` subcommand; the error string is printed to stderr and the process exits non-zero.
/// Parse errors read `FILE:LINE:COLUMN: message`.
pub fn run(cmd: &IesCommand) -> Result<(), String> {
    match cmd {
        IesCommand::Info { file, json } => info(file, *json),
        IesCommand::Convert {
            file,
            output,
            edition,
        } => {
            let parsed = load(file)?;
            let ed = if edition == "2019" {
                Edition::Lm63_2019
            } else {
                Edition::Lm63_2002
            };
            write_file(output, parsed.file.write(ed).as_bytes())
        }
        IesCommand::Plot { file, output, size } => {
            let ext = output
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase());
            let svg = match ext.as_deref() {
                Some("svg") => true,
                Some("png") => false,
                _ => {
                    return Err(format!(
                        "{}: unknown plot format: name the output .svg or .png",
                        output.display()
                    ));
                }
            };
            let parsed = load(file)?;
            let web = expand(file, &parsed)?;
            let size = (*size).clamp(64, 8192);
            let name = file.file_name().map_or_else(
                || file.display().to_string(),
                |n| n.to_string_lossy().into(),
            );
            if svg {
                return write_file(output, plot_svg(&web, &name, size).as_bytes());
            }
            let img = plot(&web, &name, size);
            let mut png = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                .map_err(|e| format!("{}: cannot encode PNG: {e}", output.display()))?;
            write_file(output, &png)
        }
    }
}

/// Writes `bytes` to `path` atomically (temporary file + rename): a failure leaves no partial
/// file and a previous file as it was.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write as _;
    lux_render::image_io::write_atomically(path, |w| {
        w.write_all(bytes)
            .map_err(|source| lux_render::image_io::ImageError::Io {
                path: path.to_path_buf(),
                action: "write",
                source,
            })
    })
    .map_err(|e| e.to_string())
}

fn load(path: &Path) -> Result<Parsed, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let text = String::from_utf8_lossy(&bytes);
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let resolver = move |name: &str| std::fs::read_to_string(dir.join(name)).ok();
    let opts = ParseOptions {
        tilt_resolver: Some(&resolver),
        ..ParseOptions::default()
    };
    IesFile::parse_with(&text, &opts).map_err(|e| format!("{}:{e}", path.display()))
}

fn expand(path: &Path, parsed: &Parsed) -> Result<PhotometricWeb, String> {
    PhotometricWeb::new(&parsed.file, Profile::Spec).map_err(|e| format!("{}:{e}", path.display()))
}

fn info(path: &Path, json: bool) -> Result<(), String> {
    let parsed = load(path)?;
    let web = expand(path, &parsed)?;
    let f = &parsed.file;
    // lux-ies gives radians; the summary prints degrees
    let deg = |a: lux_ies::SpreadAngles| [a.c0_c180, a.c90_c270].map(|x| x.map(f64::to_degrees));
    let (beam, field) = (deg(web.beam_angles()), deg(web.field_angles()));
    let (mt, mp) = web.max_direction();
    let warnings: Vec<String> = parsed.warnings.iter().map(ToString::to_string).collect();
    let mut s = String::new();
    if json {
        let v = serde_json::json!({
            "file": path.display().to_string(),
            "edition": f.edition.year(),
            "photometric_type": f.photometric_type.letter().to_string(),
            "num_vertical": f.num_vertical(),
            "num_horizontal": f.num_horizontal(),
            "symmetry": format!("{:?}", web.symmetry()),
            "lamp_count": f.lamp_count,
            "lumens_per_lamp": f.lumens_per_lamp,
            "candela_multiplier": f.candela_multiplier,
            "ballast_factor": f.ballast_factor,
            "third_factor": f.third_factor,
            "input_watts": f.input_watts,
            "flux_lm": web.flux_exact(),
            "flux_midpoint_lm": web.flux_midpoint(),
            "mean_intensity_cd": web.mean_intensity(),
            "max_cd": web.max_candela(),
            "max_direction_deg": [mt.to_degrees(), mp.to_degrees()],
            "beam_angle_deg": {"c0_c180": beam[0], "c90_c270": beam[1]},
            "field_angle_deg": {"c0_c180": field[0], "c90_c270": field[1]},
            "warnings": warnings,
        });
        let _ = writeln!(
            s,
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        let opt = |a: Option<f64>| a.map_or("-".to_string(), |x| format!("{x:.2}°"));
        let _ = writeln!(s, "file               {}", path.display());
        let _ = writeln!(s, "edition            {}", f.edition);
        let _ = writeln!(s, "photometric type   {}", f.photometric_type.letter());
        let _ = writeln!(
            s,
            "angles             {} vertical × {} horizontal ({:?})",
            f.num_vertical(),
            f.num_horizontal(),
            web.symmetry()
        );
        let _ = writeln!(
            s,
            "multipliers        candela {} × ballast {} × third {} ({})",
            f.candela_multiplier,
            f.ballast_factor,
            f.third_factor,
            if f.edition == Edition::Lm63_2019 {
                "file generation type, not applied"
            } else {
                "ballast-lamp factor"
            }
        );
        if f.is_absolute() {
            let _ = writeln!(
                s,
                "lamps              {} (absolute photometry)",
                f.lamp_count
            );
        } else {
            let _ = writeln!(
                s,
                "lamps              {} × {} lm",
                f.lamp_count, f.lumens_per_lamp
            );
        }
        let _ = writeln!(
            s,
            "flux               {:.3} lm (exact; midpoint {:.3} lm)",
            web.flux_exact(),
            web.flux_midpoint()
        );
        let _ = writeln!(
            s,
            "mean intensity     {:.4} cd (flux / {})",
            web.mean_intensity(),
            if web.covers_sphere() { "4π" } else { "2π" }
        );
        let _ = writeln!(
            s,
            "max intensity      {:.3} cd at θ {:.2}°, φ {:.2}°",
            web.max_candela(),
            mt.to_degrees(),
            mp.to_degrees()
        );
        let _ = writeln!(
            s,
            "beam angle (50 %)  C0-C180 {}, C90-C270 {}",
            opt(beam[0]),
            opt(beam[1])
        );
        let _ = writeln!(
            s,
            "field angle (10 %) C0-C180 {}, C90-C270 {}",
            opt(field[0]),
            opt(field[1])
        );
        for w in &warnings {
            let _ = writeln!(s, "warning            {w}");
        }
    }
    super::out::print(&s)
}

/// A round candela step for about four rings up to `peak`: 1, 2, 2.5 or 5 × 10^k.
fn ring_step(peak: f64) -> f64 {
    if !(peak > 0.0 && peak.is_finite()) {
        return 1.0;
    }
    let raw = peak / 4.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// The intensity curve of plane `phi` (right half, γ ≥ 0) and `phi + 180°` (left half,
/// γ < 0), γ from −180° to 180° measured from nadir.
fn plane_curve(web: &PhotometricWeb, phi: f64) -> Vec<(f64, f64)> {
    use std::f64::consts::PI;
    let samples = 721;
    (0..samples)
        .map(|k| {
            let g = -PI + 2.0 * PI * k as f64 / (samples - 1) as f64;
            let i = if g >= 0.0 {
                web.intensity(g.min(PI - 1e-12), phi)
            } else {
                web.intensity((-g).min(PI - 1e-12), phi + PI)
            };
            (g, i)
        })
        .collect()
}

/// Escapes text for SVG.
fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The geometry both diagrams share: font size, centre and radius of the polar grid, the two
/// plane curves and their candela rings.
struct Layout {
    s: f64,
    font: f64,
    cx: f64,
    cy: f64,
    r_max: f64,
    step: f64,
    rings: usize,
    scale: f64,
    c0: Vec<(f64, f64)>,
    c90: Vec<(f64, f64)>,
}

impl Layout {
    fn new(web: &PhotometricWeb, size: u32) -> Self {
        use std::f64::consts::PI;
        let s = size as f64;
        let font = (s / 45.0).max(8.0);
        let title_h = 2.2 * font;
        let legend_h = 2.0 * font;
        let r_max = ((s - title_h - legend_h) / 2.0 - 2.2 * font).max(10.0);
        let c0 = plane_curve(web, 0.0);
        let c90 = plane_curve(web, 0.5 * PI);
        let peak = c0.iter().chain(&c90).map(|p| p.1).fold(0.0, f64::max);
        let step = ring_step(peak);
        let rings = ((peak / step).ceil() as usize).max(1);
        Layout {
            s,
            font,
            cx: s / 2.0,
            cy: title_h + 1.6 * font + r_max,
            r_max,
            step,
            rings,
            scale: r_max / (rings as f64 * step),
            c0,
            c90,
        }
    }

    /// A curve point (γ from nadir, candela) in image coordinates: nadir down, γ > 0 right.
    fn xy(&self, (g, i): (f64, f64)) -> (f64, f64) {
        (
            self.cx + i * self.scale * g.sin(),
            self.cy + i * self.scale * g.cos(),
        )
    }
}

/// The labelled polar candela diagram as SVG: title (file name, total lumens); rings at round
/// candela values, labelled inside each ring above the right 90° radial; radials every 30°
/// labelled with γ (0° at nadir, down); C0–C180 (red, C0 on the right) and C90–C270 (blue,
/// C90 on the right) with a legend.
fn plot_svg(web: &PhotometricWeb, name: &str, size: u32) -> String {
    use std::f64::consts::PI;
    let l = Layout::new(web, size);
    let (s, font, cx, cy, r_max) = (l.s, l.font, l.cx, l.cy, l.r_max);
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" viewBox="0 0 {size} {size}" font-family="sans-serif" font-size="{font:.1}">"#
    );
    let _ = writeln!(o, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        o,
        r#"<text x="{cx:.1}" y="{:.1}" text-anchor="middle" font-size="{:.1}" font-weight="bold">{}</text>"#,
        1.5 * font,
        1.2 * font,
        xml(&title(web, name)),
    );
    for k in 1..=l.rings {
        let r = k as f64 * l.step * l.scale;
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="{r:.1}" fill="none" stroke="#c8c8c8"/>"##
        );
        let _ = writeln!(
            o,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="end" fill="#555">{} cd</text>"##,
            cx + r - 0.2 * font,
            cy - 0.3 * font,
            fmt_cd(k as f64 * l.step)
        );
    }
    for k in 0..12 {
        let g = k as f64 * PI / 6.0;
        let (dx, dy) = (g.sin(), g.cos());
        let _ = writeln!(
            o,
            r##"<line x1="{cx:.1}" y1="{cy:.1}" x2="{:.1}" y2="{:.1}" stroke="#c8c8c8"/>"##,
            cx + r_max * dx,
            cy + r_max * dy
        );
        let _ = writeln!(
            o,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" dominant-baseline="middle">{}</text>"#,
            cx + (r_max + 1.2 * font) * dx,
            cy + (r_max + 1.0 * font) * dy,
            angle_label(k)
        );
    }
    let path = |pts: &[(f64, f64)]| {
        let mut d = String::new();
        for (k, &p) in pts.iter().enumerate() {
            let (x, y) = l.xy(p);
            let _ = write!(d, "{}{x:.2},{y:.2}", if k == 0 { "M" } else { " L" });
        }
        d
    };
    for (pts, color) in [(&l.c90, "#1e3cdc"), (&l.c0, "#dc1e1e")] {
        let _ = writeln!(
            o,
            r#"<path d="{}" fill="none" stroke="{color}" stroke-width="2"/>"#,
            path(pts)
        );
    }
    let ly = s - 0.9 * font;
    for (k, (label, color)) in LEGEND.into_iter().enumerate() {
        let x = cx - 7.0 * font + k as f64 * 7.5 * font;
        let _ = writeln!(
            o,
            r#"<line x1="{x:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{color}" stroke-width="3"/>"#,
            ly - 0.35 * font,
            x + 1.8 * font,
            ly - 0.35 * font
        );
        let _ = writeln!(
            o,
            r#"<text x="{:.1}" y="{ly:.1}">{label}</text>"#,
            x + 2.2 * font
        );
    }
    let _ = writeln!(o, "</svg>");
    o
}

/// The diagram's title: file name and total lumens.
fn title(web: &PhotometricWeb, name: &str) -> String {
    format!("{name} — {:.0} lm", web.flux_exact())
}

/// The label of radial `k` (every 30°, clockwise from nadir): γ, 0° to 180° on either side.
fn angle_label(k: usize) -> String {
    let deg = if k <= 6 { k * 30 } else { 360 - k * 30 };
    format!("{deg}°")
}

/// The legend's entries: plane pair and its SVG colour.
const LEGEND: [(&str, &str); 2] = [("C0–C180", "#dc1e1e"), ("C90–C270", "#1e3cdc")];

/// A ring's candela value: no trailing zeros.
fn fmt_cd(v: f64) -> String {
    let t = format!("{v:.3}");
    t.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The polar candela diagram as pixels, laid out and labelled as [`plot_svg`]'s: nadir
/// (θ = 0) points down; the right half shows C0 (red) and C90 (blue), the left half C180 and
/// C270; circles at round candela values, radials every 30°. The labels are drawn with an 8×8
/// bitmap font (font8x8) scaled by a whole factor (2 at the default 800 px), so they are
/// crisp; where the SVG's proportional text would fit and the wider monospace glyphs would
/// not, the PNG shrinks them (ring values, long titles), moves them (angle labels just outside
/// the outer ring, the legend centred) or, for ring values that overlap even at scale 1 (small
/// images), leaves out those that would cover the one outside them.
fn plot(web: &PhotometricWeb, name: &str, size: u32) -> image::RgbImage {
    use std::f64::consts::PI;
    let mut img = image::RgbImage::from_pixel(size, size, image::Rgb([255, 255, 255]));
    let l = Layout::new(web, size);
    let (s, font, cx, cy, r_max) = (l.s, l.font, l.cx, l.cy, l.r_max);
    let grey = image::Rgb([200, 200, 200]);
    for ring in 1..=l.rings {
        let r = ring as f64 * l.step * l.scale;
        let n = 720;
        let pts: Vec<(f64, f64)> = (0..=n)
            .map(|k| {
                let a = 2.0 * PI * k as f64 / n as f64;
                (cx + r * a.cos(), cy + r * a.sin())
            })
            .collect();
        polyline(&mut img, &pts, grey, 0);
    }
    for k in 0..12 {
        let a = k as f64 * PI / 6.0;
        polyline(
            &mut img,
            &[(cx, cy), (cx + r_max * a.sin(), cy + r_max * a.cos())],
            grey,
            0,
        );
    }
    let pts0: Vec<_> = l.c0.iter().map(|&p| l.xy(p)).collect();
    let pts90: Vec<_> = l.c90.iter().map(|&p| l.xy(p)).collect();
    polyline(&mut img, &pts90, image::Rgb([30, 60, 220]), 1);
    polyline(&mut img, &pts0, image::Rgb([220, 30, 30]), 1);

    let ink = image::Rgb([0, 0, 0]);
    let k = ((font / 8.0).floor() as u32).max(1);
    // title: bold, at 1.2 × the labels' font size as the SVG's, smaller if too wide
    let t = title(web, name);
    let mut kt = ((1.2 * font / 8.0).floor() as u32).max(1);
    while kt > 1 && text_width(&t, kt, true) > s - 2.0 * font {
        kt -= 1;
    }
    let x = cx - text_width(&t, kt, true) / 2.0;
    draw_text(&mut img, &t, x, 1.5 * font - 7.0 * kt as f64, kt, true, ink);
    // ring values: right-aligned inside each ring above the right radial; a size down if the
    // widest would reach into the next ring in
    let values: Vec<String> = (1..=l.rings)
        .map(|r| format!("{} cd", fmt_cd(r as f64 * l.step)))
        .collect();
    let gap = l.step * l.scale;
    let mut kr = k;
    while kr > 1
        && values
            .iter()
            .any(|v| text_width(v, kr, false) + 0.4 * font > gap)
    {
        kr -= 1;
    }
    // (at the smallest size, from the outer ring in, a value that would overlap the one drawn
    // outside it is left out)
    let mut free_to = f64::INFINITY;
    for (r, v) in values.iter().enumerate().rev() {
        let end = cx + (r + 1) as f64 * gap - 0.2 * font;
        let x = end - text_width(v, kr, false);
        if end > free_to {
            continue;
        }
        let top = cy - 0.3 * font - 7.0 * kr as f64;
        draw_text(&mut img, v, x, top, kr, false, image::Rgb([85, 85, 85]));
        free_to = x - 0.4 * font;
    }
    // angle labels: centred on their radial, just outside the outer ring
    for a in 0..12 {
        let g = a as f64 * PI / 6.0;
        let (dx, dy) = (g.sin(), g.cos());
        let v = angle_label(a);
        let (w, h) = (text_width(&v, k, false), 7.0 * k as f64);
        let d = r_max + 0.4 * font + dx.abs() * w / 2.0 + dy.abs() * h / 2.0;
        let (x, y) = (cx + d * dx, cy + d * dy);
        draw_text(&mut img, &v, x - w / 2.0, y - h / 2.0, k, false, ink);
    }
    // legend: a coloured stroke and the plane pair, the entries centred on the bottom row
    let ly = s - 0.9 * font;
    let colors = [image::Rgb([220, 30, 30]), image::Rgb([30, 60, 220])];
    let entry = |label: &str| 2.2 * font + text_width(label, k, false);
    let total = LEGEND.iter().map(|(t, _)| entry(t)).sum::<f64>() + 1.5 * font;
    let mut x = cx - total / 2.0;
    for ((label, _), color) in LEGEND.into_iter().zip(colors) {
        let y = ly - 0.35 * font;
        polyline(&mut img, &[(x, y), (x + 1.8 * font, y)], color, 1);
        draw_text(
            &mut img,
            label,
            x + 2.2 * font,
            ly - 7.0 * k as f64,
            k,
            false,
            ink,
        );
        x += entry(label) + 1.5 * font;
    }
    img
}

/// The 8×8 bitmap of `c` (row by row, bit 0 the leftmost pixel; row 7 below the baseline):
/// font8x8's Basic Latin and Latin-1 glyphs; the en and em dash, which it lacks, as bars;
/// anything else as `?`.
fn glyph(c: char) -> [u8; 8] {
    use font8x8::UnicodeFonts;
    match c {
        '–' => [0, 0, 0, 0x7e, 0, 0, 0, 0],
        '—' => [0, 0, 0, 0xff, 0, 0, 0, 0],
        _ => font8x8::BASIC_FONTS
            .get(c)
            .or_else(|| font8x8::LATIN_FONTS.get(c))
            .or_else(|| font8x8::BASIC_FONTS.get('?'))
            .unwrap_or_default(),
    }
}

/// The width in pixels of `text` drawn by [`draw_text`] at scale `k`.
fn text_width(text: &str, k: u32, bold: bool) -> f64 {
    (text.chars().count() as u32 * 8 * k + u32::from(bold)) as f64
}

/// Draws `text` with its top-left corner at (`x`, `top`), each glyph pixel a `k`×`k` square
/// (one pixel wider when `bold`); pixels outside the image are skipped.
fn draw_text(
    img: &mut image::RgbImage,
    text: &str,
    x: f64,
    top: f64,
    k: u32,
    bold: bool,
    color: image::Rgb<u8>,
) {
    let (w, h) = (img.width() as i64, img.height() as i64);
    let (x0, y0, k) = (x.round() as i64, top.round() as i64, k as i64);
    for (n, c) in text.chars().enumerate() {
        let gx = x0 + 8 * k * n as i64;
        for (row, bits) in glyph(c).into_iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                for py in y0 + row as i64 * k..y0 + (row as i64 + 1) * k {
                    let px0 = gx + col * k;
                    for px in px0..px0 + k + i64::from(bold) {
                        if px >= 0 && py >= 0 && px < w && py < h {
                            img.put_pixel(px as u32, py as u32, color);
                        }
                    }
                }
            }
        }
    }
}

fn polyline(img: &mut image::RgbImage, pts: &[(f64, f64)], color: image::Rgb<u8>, radius: i64) {
    let (w, h) = (img.width() as i64, img.height() as i64);
    for seg in pts.windows(2) {
        let (x0, y0) = seg[0];
        let (x1, y1) = seg[1];
        let n = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as usize).clamp(1, 100_000);
        for s in 0..=n {
            let t = s as f64 / n as f64;
            let x = (x0 + t * (x1 - x0)).round() as i64;
            let y = (y0 + t * (y1 - y0)).round() as i64;
            for dy in -radius..=radius {
                for dx in -radius..=radius {
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && px < w && py < h {
                        img.put_pixel(px as u32, py as u32, color);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn label_glyphs_cover_the_labels_characters() {
        let question = glyph('?');
        for c in "bega_omni002.ies — 4779 lm 1000 cd 180° C0–C180".chars() {
            let g = glyph(c);
            assert_eq!(g == [0; 8], c == ' ', "{c:?}");
            assert_ne!(g, question, "{c:?} falls back to ?");
        }
        assert_eq!(glyph('\u{4e00}'), question);
    }

    #[test]
    fn draw_text_scales_each_glyph_pixel_to_a_square() {
        let white = image::Rgb([255, 255, 255]);
        let ink = image::Rgb([0, 0, 0]);
        let mut img = image::RgbImage::from_pixel(40, 20, white);
        draw_text(&mut img, "1°", 2.0, 3.0, 2, false, ink);
        let lit = |g: [u8; 8]| g.iter().map(|r| r.count_ones()).sum::<u32>();
        let n = img.pixels().filter(|&&p| p == ink).count() as u32;
        assert_eq!(n, 4 * (lit(glyph('1')) + lit(glyph('°'))));
        // within the text's box: 2 × 8 columns of 2 pixels from x = 2, 8 rows of 2 from y = 3
        assert_eq!(text_width("1°", 2, false), 32.0);
        for (x, y, p) in img.enumerate_pixels() {
            if *p == ink {
                assert!((2..34).contains(&x) && (3..19).contains(&y), "({x}, {y})");
            }
        }
    }
}
