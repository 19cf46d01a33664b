//! `lux ies info|convert|plot`: summary, edition conversion and polar candela diagram of an
//! IES LM-63 file.

use clap::Subcommand;
use lux_ies::{Edition, IesFile, ParseOptions, Parsed, PhotometricWeb};
use lux_math::Profile;
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
    /// Draw the polar candela diagram (C0–C180 and C90–C270 planes) as a PNG.
    Plot {
        /// The IES file.
        file: PathBuf,
        /// Output PNG.
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
            std::fs::write(output, parsed.file.write(ed))
                .map_err(|e| format!("{}: cannot write: {e}", output.display()))
        }
        IesCommand::Plot { file, output, size } => {
            let parsed = load(file)?;
            let web = expand(file, &parsed)?;
            let img = plot(&web, (*size).clamp(64, 8192));
            img.save(output)
                .map_err(|e| format!("{}: cannot write PNG: {e}", output.display()))
        }
    }
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
    let beam = web.beam_angles();
    let field = web.field_angles();
    let (mt, mp) = web.max_direction();
    let warnings: Vec<String> = parsed.warnings.iter().map(ToString::to_string).collect();
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
            "mean_intensity_cd": web.mean_intensity(Profile::Spec),
            "max_cd": web.max_candela(),
            "max_direction_deg": [mt.to_degrees(), mp.to_degrees()],
            "beam_angle_deg": {"c0_c180": beam.c0_c180, "c90_c270": beam.c90_c270},
            "field_angle_deg": {"c0_c180": field.c0_c180, "c90_c270": field.c90_c270},
            "warnings": warnings,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        let opt = |a: Option<f64>| a.map_or("-".to_string(), |x| format!("{x:.2}°"));
        println!("file               {}", path.display());
        println!("edition            {}", f.edition);
        println!("photometric type   {}", f.photometric_type.letter());
        println!(
            "angles             {} vertical × {} horizontal ({:?})",
            f.num_vertical(),
            f.num_horizontal(),
            web.symmetry()
        );
        println!(
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
            println!("lamps              {} (absolute photometry)", f.lamp_count);
        } else {
            println!(
                "lamps              {} × {} lm",
                f.lamp_count, f.lumens_per_lamp
            );
        }
        println!(
            "flux               {:.3} lm (exact; midpoint {:.3} lm)",
            web.flux_exact(),
            web.flux_midpoint()
        );
        println!(
            "mean intensity     {:.4} cd (flux / {})",
            web.mean_intensity(Profile::Spec),
            if web.covers_sphere() { "4π" } else { "2π" }
        );
        println!(
            "max intensity      {:.3} cd at θ {:.2}°, φ {:.2}°",
            web.max_candela(),
            mt.to_degrees(),
            mp.to_degrees()
        );
        println!(
            "beam angle (50 %)  C0-C180 {}, C90-C270 {}",
            opt(beam.c0_c180),
            opt(beam.c90_c270)
        );
        println!(
            "field angle (10 %) C0-C180 {}, C90-C270 {}",
            opt(field.c0_c180),
            opt(field.c90_c270)
        );
        for w in &warnings {
            println!("warning            {w}");
        }
    }
    Ok(())
}

/// The polar candela diagram: nadir (θ = 0) points down; the right half shows C0 (red) and C90
/// (blue), the left half C180 and C270; circles every 1/4 of the peak, radials every 30°.
fn plot(web: &PhotometricWeb, size: u32) -> image::RgbImage {
    use std::f64::consts::PI;
    let mut img = image::RgbImage::from_pixel(size, size, image::Rgb([255, 255, 255]));
    let c = size as f64 / 2.0;
    let r_max = c * 0.9;
    let samples = 721;
    let curve = |phi: f64| -> Vec<(f64, f64)> {
        // γ from -180 (plane φ+180, left) to +180 (plane φ, right)
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
    };
    let c0 = curve(0.0);
    let c90 = curve(0.5 * PI);
    let peak = c0.iter().chain(&c90).map(|p| p.1).fold(0.0, f64::max);
    let scale = if peak > 0.0 { r_max / peak } else { 0.0 };
    let grey = image::Rgb([200, 200, 200]);
    for ring in 1..=4 {
        let r = r_max * ring as f64 / 4.0;
        let n = 720;
        let pts: Vec<(f64, f64)> = (0..=n)
            .map(|k| {
                let a = 2.0 * PI * k as f64 / n as f64;
                (c + r * a.cos(), c + r * a.sin())
            })
            .collect();
        polyline(&mut img, &pts, grey, 0);
    }
    for k in 0..12 {
        let a = k as f64 * PI / 6.0;
        polyline(
            &mut img,
            &[(c, c), (c + r_max * a.sin(), c + r_max * a.cos())],
            grey,
            0,
        );
    }
    // γ measured from straight down; positive γ to the right
    let to_xy = |(g, i): &(f64, f64)| (c + i * scale * g.sin(), c + i * scale * g.cos());
    let pts0: Vec<_> = c0.iter().map(to_xy).collect();
    let pts90: Vec<_> = c90.iter().map(to_xy).collect();
    polyline(&mut img, &pts90, image::Rgb([30, 60, 220]), 1);
    polyline(&mut img, &pts0, image::Rgb([220, 30, 30]), 1);
    img
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
