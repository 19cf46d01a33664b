//! `lux render SCENE …`: renders a USD stage with the reference renderer, writes the image
//! atomically in the format the output's extension names (`.exr`: RGBA float32, linear;
//! `.png`: 8-bit sRGB, opaque unless `--alpha`), with a progress bar and a closing summary.
//!
//! Arguments are checked before the stage is read: sample counts and depth against the
//! renderer's limits ([`MAX_SPP`], [`MAX_DEPTH`], [`MAX_LIGHT_SAMPLES`]), the output formats,
//! and that the outputs' folders exist.

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use lux_math::Profile;
use lux_render::conformance::{PROFILE_ENV, default_config_paths, resolve_profile};
use lux_render::image_io::{ImageRgba, StagedFile, stage_png, stage_png_opaque};
use lux_render::light::LightSelection;
use lux_render::render::{RenderOptions, RenderStats, Renderer};
use lux_render::settings::{
    AdaptiveSampling, IntegratorKind, MAX_ADAPTIVE_FACTOR, MAX_DEPTH, MAX_LIGHT_SAMPLES,
    MAX_PATH_SPLITS, MAX_SPP, NoiseMeasure, SamplingMode, VisibilityMode,
};
use lux_usd::{LoadOptions, Time, load_stage_with};
use std::path::{Path, PathBuf};

/// An output image format, chosen by the file's extension (as usdrecord does).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.exr`: RGBA float32, linear.
    Exr,
    /// `.png`: 8-bit sRGB (exposure applied), RGB unless `--alpha`.
    Png,
}

impl OutputFormat {
    /// The format of `path` by its extension (case-insensitive); other extensions are errors.
    pub fn of(path: &Path) -> Result<OutputFormat, String> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("exr") => Ok(OutputFormat::Exr),
            Some("png") => Ok(OutputFormat::Png),
            Some(e) => Err(format!(
                "{}: unknown output format .{e}: expected .exr (float, linear) or .png (8-bit sRGB)",
                path.display()
            )),
            None => Err(format!(
                "{}: no file extension: expected .exr (float, linear) or .png (8-bit sRGB)",
                path.display()
            )),
        }
    }
}

/// `--sampling`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SamplingArg {
    /// lux's importance sampling with MIS.
    Lux,
    /// hdEmbree's uniform area / hemisphere sampling, for A/B comparison.
    Reference,
}

/// `--visibility`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum VisibilityArg {
    /// Shadow rays and camera rays through the scene's BVH: the plain renderer.
    Rays,
    /// Closed forms where nothing blocks a light, exact penumbrae, card outlines, tile lists.
    Exact,
}

/// `--surfaces`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SurfacesArg {
    /// The full UsdPreviewSurface (GGX specular, metallic, clearcoat, opacity, normal maps).
    Preview,
    /// Lambertian diffuseColor only, opaque (what the reference renderer shades).
    Lambert,
}

/// `--adaptive-measure`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MeasureArg {
    /// σ/√μ of the neighbourhood: noise as the eye sees it, edges antialiased (the direct
    /// integrator's default).
    Perceived,
    /// σ/μ̄ of the frame: samples where the image's squared error is (the path tracer's default).
    Linear,
}

/// `--light-selection`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SelectionArg {
    /// Every light up to 8 lights, else the light BVH.
    Auto,
    /// Every light at every shading point.
    All,
    /// One light by power.
    Power,
    /// One light by the light BVH.
    Bvh,
}

/// Arguments of `lux render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The USD stage (.usda, .usdc or .usdz).
    pub scene: PathBuf,
    /// Time code to render (default: the stage's startTimeCode, as usdrecord).
    #[arg(long, allow_hyphen_values = true)]
    pub frame: Option<f64>,
    /// Samples per pixel, 1 to 1048576 (with adaptive sampling, the least a pixel takes).
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Output resolution WxH (default: the stage's RenderSettings, else usdrecord's 960 wide at
    /// the camera's aspect).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<[u32; 2]>,
    /// Render only pixels X0,Y0,X1,Y1 (end exclusive, y from the top); the rest stays black.
    #[arg(long, value_parser = parse_crop)]
    pub crop: Option<[u32; 4]>,
    /// Camera prim path, or a camera's bare name when unique (default: the RenderSettings'
    /// camera, else the first camera, else usdrecord's camera framing the scene).
    #[arg(long)]
    pub camera: Option<String>,
    /// Turn composition warnings (missing sublayers, references, payloads, unknown formats,
    /// cycles) and unreadable assets into errors.
    #[arg(long)]
    pub strict: bool,
    /// No camera light (usdrecord's default light when the stage has none).
    #[arg(long)]
    pub disable_camera_light: bool,
    /// Conformance profile; else RenderSettings `lux:conformanceProfile`, else
    /// $LUX_CONFORMANCE_PROFILE, else the config files, else spec.
    #[arg(long, value_parser = parse_profile)]
    pub profile: Option<Profile>,
    /// Sampling techniques.
    #[arg(long, value_enum, default_value_t = SamplingArg::Lux)]
    pub sampling: SamplingArg,
    /// Light transport: direct, path or light (particles from the lights, splatted to the
    /// camera) (default: path in the spec profile, direct in hdembree, whose reference renderer
    /// lights surfaces directly).
    #[arg(long, value_parser = parse_integrator)]
    pub integrator: Option<IntegratorKind>,
    /// How what a point sees of a light is found: exact (closed forms where nothing can block a
    /// light, exact penumbrae behind a few triangles, per-tile lists) or rays (shadow rays
    /// through the BVH for every light sample).
    #[arg(long, value_enum, default_value_t = VisibilityArg::Exact)]
    pub visibility: VisibilityArg,
    /// Most surface vertices a path lights, 1 to 128 (`--integrator path`).
    #[arg(long, default_value_t = 8)]
    pub max_depth: u32,
    /// Paths continued from each camera sample's first surface, 1 to 64 (`--integrator path`):
    /// they share the camera ray, the first hit and its direct light.
    #[arg(long, default_value_t = lux::render::settings::PATH_SPLITS)]
    pub splits: u32,
    /// How surfaces scatter (default: preview in the spec profile, lambert in hdembree).
    #[arg(long, value_enum)]
    pub surfaces: Option<SurfacesArg>,
    /// Light selection strategy.
    #[arg(long, value_enum, default_value_t = SelectionArg::Auto)]
    pub light_selection: SelectionArg,
    /// Light samples per light (or per light choice) at each shading point, 1 to 64: more
    /// shadow rays per camera ray, for penumbrae (default with the direct integrator and lux
    /// sampling: 4 shared by the lights sampled at a point, ⌈4/n⌉ each for n lights, 16
    /// choices of one sample each when a light BVH chooses; else 1)
    #[arg(long)]
    pub light_samples: Option<u32>,
    /// Light samples per light in shadowed pixels, 1 to 64 (1: off), times --light-samples: from
    /// 8 spp, a pixel whose pilot sample (not part of the estimate) found a blocked shadow ray
    /// takes this many times more.
    #[arg(long, default_value_t = 1)]
    pub penumbra_samples: u32,
    /// Shadow rays each path vertex past the camera's shares among its light samples, 0 to 64
    /// (`--integrator path`; 0: one per light sample): with more light samples than this, as
    /// many are picked in proportion to what each adds unshadowed, and weighted by their share
    #[arg(long, default_value_t = lux::render::settings::VERTEX_SHADOW_RAYS)]
    pub shadow_rays: u32,
    /// Adaptive sampling's noise threshold t: after --spp samples, a pixel takes spp·s/t in
    /// all, s the luminance noise of one sample by --adaptive-measure (counted from its
    /// neighbours' samples only, so pixels stay unbiased). On by default with lux sampling:
    /// perceived, t = 0.01 for the direct integrator; linear, t = 0.1 for the path tracer
    #[arg(long, allow_negative_numbers = true)]
    pub adaptive_threshold: Option<f64>,
    /// Adaptive sampling's noise measure: perceived σ/√μ (μ the neighbourhood's mean luminance)
    /// or linear σ/μ̄ (μ̄ the frame's, from a sparse pilot); default by integrator
    #[arg(long, value_enum)]
    pub adaptive_measure: Option<MeasureArg>,
    /// Most samples a pixel takes with adaptive sampling, as a multiple of --spp (1 to 1024,
    /// default 16)
    #[arg(long)]
    pub adaptive_max: Option<u32>,
    /// Adaptive splitting, 1 to 64 (1 or no more than --splits: off): the most path
    /// continuations a pixel's extra samples split into at their first surface, by the linear
    /// measure with --integrator path; each pixel's take --splits doubled as often as its
    /// neighbours' first samples find cheapest for their noise (default 8 with the linear
    /// measure, else 1)
    #[arg(long)]
    pub adaptive_splits: Option<u32>,
    /// Every pixel takes exactly --spp samples (no adaptive sampling)
    #[arg(long, conflicts_with_all = ["adaptive_threshold", "adaptive_max", "adaptive_measure", "adaptive_splits"])]
    pub no_adaptive: bool,
    /// Subdivision surfaces' refinement level, 0 to 10: 2^N segments along every cage edge, 0
    /// the cage's polygons (default: by size on screen in the spec profile, refined edges about
    /// 4 pixels where the surface comes nearest the camera, at most 6; 0 in hdembree, as
    /// hdEmbree at usdrecord's default complexity).
    #[arg(long)]
    pub subdiv_level: Option<u32>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output image; the extension names the format: .exr (RGBA float32, linear) or .png
    /// (8-bit sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write an 8-bit sRGB PNG here.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// How PNG outputs are encoded.
    #[command(flatten)]
    pub png_encoding: PngEncoding,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Force every output to disk before it replaces its target, so that it survives a power
    /// loss (an `fsync`: waits for the file system's journal). Without it an output still
    /// appears whole or not at all, as with other renderers.
    #[arg(long)]
    pub fsync: bool,
    /// Render only band I of N (rows ⌊I·H/N⌋ to ⌊(I+1)·H/N⌋ − 1) to an EXR of those rows, for
    /// `lux merge`.
    #[arg(long, value_parser = crate::cli::tile::parse_tile)]
    pub tile: Option<crate::cli::tile::TileSpec>,
}

/// How `lux render` and `lux merge` encode PNG outputs: 8-bit sRGB of the linear values times
/// 2^exposure, opaque RGB unless `--alpha`.
#[derive(Debug, Clone, Args)]
pub struct PngEncoding {
    /// Exposure of PNG outputs in stops.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f64,
    /// Keep the alpha channel in PNG outputs (default: opaque RGB, so viewers show the empty
    /// background black rather than transparent).
    #[arg(long)]
    pub alpha: bool,
}

impl PngEncoding {
    /// The exposure is a finite number.
    pub fn check(&self) -> Result<(), String> {
        if self.exposure.is_finite() {
            Ok(())
        } else {
            Err(format!(
                "--exposure {}: expected a finite number",
                self.exposure
            ))
        }
    }

    /// `image` encoded as a PNG at `path`, staged for an atomic rename.
    pub fn stage(&self, path: &Path, image: &ImageRgba) -> Result<StagedFile, String> {
        if self.alpha {
            stage_png(path, image, self.exposure)
        } else {
            stage_png_opaque(path, image, self.exposure)
        }
        .map_err(|e| e.to_string())
    }
}

fn parse_integrator(s: &str) -> Result<IntegratorKind, String> {
    IntegratorKind::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = IntegratorKind::ALL.iter().map(|k| k.name()).collect();
        format!("expected one of {}", names.join(", "))
    })
}

fn parse_profile(s: &str) -> Result<Profile, String> {
    s.parse::<Profile>().map_err(|e| e.to_string())
}

fn parse_list<const N: usize>(s: &str, sep: char, what: &str) -> Result<[u32; N], String> {
    let parts: Vec<&str> = s.split(sep).collect();
    if parts.len() != N {
        return Err(format!(
            "{what}: expected {N} integers separated by '{sep}', got {s:?}"
        ));
    }
    let mut out = [0u32; N];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p
            .trim()
            .parse()
            .map_err(|_| format!("{what}: {p:?} is not a non-negative integer"))?;
    }
    Ok(out)
}

fn parse_resolution(s: &str) -> Result<[u32; 2], String> {
    let r = parse_list::<2>(&s.to_ascii_lowercase(), 'x', "resolution")?;
    if r[0] == 0 || r[1] == 0 {
        return Err(format!("resolution {s}: both sides must be at least 1"));
    }
    Ok(r)
}

fn parse_crop(s: &str) -> Result<[u32; 4], String> {
    parse_list::<4>(s, ',', "crop")
}

/// Loads `scene` at `frame` (default: its startTimeCode), strictly or with usd-core's policy.
pub fn load(
    scene: &std::path::Path,
    frame: Option<f64>,
    strict: bool,
) -> Result<lux_usd::Scene, String> {
    let mut options = LoadOptions::default();
    options.strict = strict;
    let time = frame.map_or(Time::Start, Time::Code);
    load_stage_with(scene, time, &options).map_err(|e| e.to_string())
}

/// Checks what can be checked without the stage: numeric ranges (the renderer's limits), the
/// output formats and folders. Returns the outputs: `-o` in its format, then `--png`.
pub fn check_args(args: &RenderArgs) -> Result<Vec<(PathBuf, OutputFormat)>, String> {
    args.png_encoding.check()?;
    for (flag, what, v, max) in [
        ("--spp", "samples per pixel", args.spp, MAX_SPP),
        ("--max-depth", "path depth", args.max_depth, MAX_DEPTH),
        ("--splits", "path splits", args.splits, MAX_PATH_SPLITS),
        (
            "--light-samples",
            "light samples",
            args.light_samples.unwrap_or(1),
            MAX_LIGHT_SAMPLES,
        ),
        (
            "--penumbra-samples",
            "penumbra samples",
            args.penumbra_samples,
            MAX_LIGHT_SAMPLES,
        ),
        (
            "--adaptive-max",
            "the adaptive sample factor",
            args.adaptive_max.unwrap_or(1),
            MAX_ADAPTIVE_FACTOR,
        ),
    ] {
        if v == 0 || v > max {
            return Err(format!("{flag} {v}: {what} must be 1 to {max}"));
        }
    }
    if args.shadow_rays > MAX_LIGHT_SAMPLES {
        return Err(format!(
            "--shadow-rays {}: shadow rays must be 0 to {MAX_LIGHT_SAMPLES}",
            args.shadow_rays
        ));
    }
    if let Some(t) = args.adaptive_threshold
        && !(t.is_finite() && t > 0.0)
    {
        return Err(format!(
            "--adaptive-threshold {t}: expected a finite number > 0"
        ));
    }
    if args.threads == Some(0) {
        return Err("--threads 0: expected at least 1".into());
    }
    let mut outputs = vec![(args.output.clone(), OutputFormat::of(&args.output)?)];
    if let Some(png) = &args.png {
        outputs.push((png.clone(), OutputFormat::Png));
    }
    for (path, _) in &outputs {
        if path.is_dir() {
            return Err(format!(
                "{}: is a directory, not an image file",
                path.display()
            ));
        }
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        // A tile's folder is made for it (farm jobs write into fresh directories).
        if !folder.is_dir() && (args.tile.is_none() || folder.exists()) {
            return Err(format!(
                "{}: cannot write: the folder {} does not exist",
                path.display(),
                folder.display()
            ));
        }
    }
    Ok(outputs)
}

/// Encodes `image` to a temporary file next to `path` in `format` ([`StagedFile`]).
fn stage(
    path: &Path,
    format: OutputFormat,
    image: &ImageRgba,
    args: &RenderArgs,
    header: &crate::cli::tile::FrameHeader,
    tile: Option<(crate::cli::tile::TileSpec, [u32; 2])>,
) -> Result<StagedFile, String> {
    match format {
        // The EXR records the lux:* header (and, for a tile, only its rows).
        OutputFormat::Exr => crate::cli::tile::stage_exr(path, image, header, tile),
        OutputFormat::Png => args.png_encoding.stage(path, image),
    }
}

/// Renders according to `args` and writes the outputs; the summary goes to stderr.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let outputs = check_args(args)?;
    let mut scene = load(&args.scene, args.frame, args.strict)?;
    for note in scene.add_usdrecord_defaults(!args.disable_camera_light) {
        eprintln!("lux: {note}");
    }
    let env = std::env::var(PROFILE_ENV).ok();
    let profile = resolve_profile(
        args.profile,
        &scene,
        env.as_deref(),
        &default_config_paths(),
    )
    .map_err(|e| e.to_string())?;
    let announce = format!(
        "lux: profile {} (from {}), sampling {:?}",
        profile.profile, profile.source, args.sampling
    );
    let camera = match &args.camera {
        Some(name) => scene.find_camera(name)?,
        None => scene
            .render_camera()
            .ok_or_else(|| format!("{} has no camera", scene.source.display()))?,
    };
    let mut options = RenderOptions::new(profile);
    options.spp = args.spp;
    options.resolution = Some(
        args.resolution
            .unwrap_or_else(|| scene.default_resolution(camera)),
    );
    options.crop = args.crop;
    options.camera = Some(camera.path.clone());
    options.strict = args.strict;
    options.seed = args.seed;
    options.light_samples = args.light_samples;
    if let Some(i) = args.integrator {
        options.integrator = i;
    }
    options.visibility = match args.visibility {
        VisibilityArg::Rays => VisibilityMode::Rays,
        VisibilityArg::Exact => VisibilityMode::Exact,
    };
    options.max_depth = args.max_depth;
    options.path_splits = args.splits;
    if let Some(m) = args.surfaces {
        options.surfaces = match m {
            SurfacesArg::Preview => lux::render::settings::SurfaceModel::Preview,
            SurfacesArg::Lambert => lux::render::settings::SurfaceModel::Lambert,
        };
    }
    options.penumbra_samples = args.penumbra_samples;
    options.shadow_rays = args.shadow_rays;
    options.subdiv_level = args.subdiv_level;
    options.sampling = match args.sampling {
        SamplingArg::Lux => SamplingMode::Lux,
        SamplingArg::Reference => SamplingMode::Reference,
    };
    options.selection = match args.light_selection {
        SelectionArg::Auto => LightSelection::Auto,
        SelectionArg::All => LightSelection::All,
        SelectionArg::Power => LightSelection::Power,
        SelectionArg::Bvh => LightSelection::Bvh,
    };
    options.adaptive = if args.no_adaptive {
        Some(AdaptiveSampling::OFF)
    } else if args.adaptive_threshold.is_some()
        || args.adaptive_max.is_some()
        || args.adaptive_measure.is_some()
        || args.adaptive_splits.is_some()
    {
        // The asked measure, else the integrator's (the direct one's when it has none);
        // unset values from that measure's default.
        let measure = match args.adaptive_measure {
            Some(MeasureArg::Perceived) => NoiseMeasure::Perceived,
            Some(MeasureArg::Linear) => NoiseMeasure::Linear,
            None => Some(options.adaptive())
                .filter(|a| a.is_on())
                .map_or(NoiseMeasure::Perceived, |a| a.measure),
        };
        let d = AdaptiveSampling::default_for(measure);
        Some(AdaptiveSampling {
            threshold: args.adaptive_threshold.unwrap_or(d.threshold),
            max_factor: args.adaptive_max.unwrap_or(d.max_factor),
            measure,
            max_splits: args.adaptive_splits.unwrap_or(d.max_splits),
        })
    } else {
        None
    };
    // (the reference estimator is direct lighting only)
    let transport = match (options.integrator, options.sampling) {
        (IntegratorKind::Path, SamplingMode::Lux) => {
            format!("path tracing (depth {})", options.max_depth)
        }
        (IntegratorKind::Light, _) => {
            format!("light tracing (depth {})", options.max_depth)
        }
        _ => "direct lighting".to_owned(),
    };
    eprintln!("{announce}, {transport}, {} spp", args.spp);
    let header = crate::cli::tile::FrameHeader::new(args, &scene, &options);
    // Subdivision surfaces refined in place (the renderer would refine a copy).
    let start = std::time::Instant::now();
    let refined = lux::render::settings::refine_subdivision(&mut scene, &options)
        .map_err(|e| e.to_string())?;
    if !refined.is_empty() {
        let (lo, hi) = refined
            .iter()
            .fold((u32::MAX, 0), |(l, h), r| (l.min(r.level), h.max(r.level)));
        eprintln!(
            "lux: {} refined at level {} in {:.3} s ({})",
            plural(
                refined.len() as u64,
                "subdivision surface",
                "subdivision surfaces"
            ),
            if lo == hi {
                lo.to_string()
            } else {
                format!("{lo} to {hi}")
            },
            start.elapsed().as_secs_f64(),
            match options.subdiv_level {
                Some(n) => format!("--subdiv-level {n}"),
                None => format!(
                    "by size on screen, at most level {}",
                    lux::render::settings::SCREEN_LEVEL_CAP
                ),
            }
        );
    }
    let mut renderer = Renderer::new(&scene, options).map_err(|e| e.to_string())?;
    let rows = crate::cli::tile::restrict(&mut renderer, args)?;
    for w in &scene.warnings {
        eprintln!("lux: warning: {w}");
    }
    for w in renderer.warnings() {
        eprintln!("lux: warning: {w}");
    }
    let total = renderer.progress_total();
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(total);
        b.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}%  eta {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    };
    let pool = match args.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| format!("cannot start {n} threads: {e}"))?,
        None => rayon::ThreadPoolBuilder::new()
            .build()
            .map_err(|e| format!("cannot start the thread pool: {e}"))?,
    };
    let threads = pool.current_num_threads();
    let (image, stats) = pool.install(|| renderer.render(&|n| bar.inc(n)));
    bar.finish_and_clear();
    for w in renderer.late_warnings() {
        eprintln!("lux: warning: {w}");
    }
    // Every output is encoded to a temporary file before any replaces its target: a failed
    // encode or write leaves none (and no temporary file).
    let tile = args.tile.zip(rows);
    // (On the render's pool: the EXR's blocks are compressed in parallel.)
    let staged = pool.install(|| {
        outputs
            .iter()
            .map(|(path, format)| stage(path, *format, &image, args, &header, tile))
            .collect::<Result<Vec<_>, _>>()
    })?;
    for file in staged {
        if args.fsync {
            file.commit_durable()
        } else {
            file.commit()
        }
        .map_err(|e| e.to_string())?;
    }
    eprintln!("{}", summary(&stats, threads));
    if stats.non_finite_samples > 0 {
        eprintln!(
            "lux: warning: {} NaN or infinite radiance and were written as black",
            plural(stats.non_finite_samples, "sample had", "samples had")
        );
    }
    let names: Vec<String> = outputs
        .iter()
        .map(|(p, _)| p.display().to_string())
        .collect();
    eprintln!("lux: wrote {}", names.join(" and "));
    Ok(())
}

/// `n` and the singular or plural noun.
fn plural(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The closing line: time, samples/s, rays/s.
pub fn summary(stats: &RenderStats, threads: usize) -> String {
    let t = stats.seconds.max(1e-9);
    let samples = if stats.adaptive_samples > 0 {
        format!(
            "{} px × spp + {} adaptive = {} samples ({:.2} a pixel)",
            stats.pixels,
            stats.adaptive_samples,
            stats.samples,
            stats.samples as f64 / stats.pixels.max(1) as f64
        )
    } else {
        format!("{} px × spp = {} samples", stats.pixels, stats.samples)
    };
    format!(
        "lux: {samples} in {:.3} s on {}: {:.3} M samples/s, {:.3} M rays/s ({} rays, {} shadow)",
        stats.seconds,
        plural(threads as u64, "thread", "threads"),
        stats.samples as f64 / t / 1e6,
        stats.rays as f64 / t / 1e6,
        stats.rays,
        stats.shadow_rays
    )
}
