//! The `lux` command line: `lux render`, `lux info`, `lux ies …`, `lux merge`, `lux farm`.
//! With no arguments it renders the bundled demo scene to `lux-demo.exr` and `lux-demo.png`,
//! saying so first on stderr.
//!
//! Exit status: 0 on success, 1 on an error (the message on stderr; no partial output file is
//! left), 2 on a usage error. A reader closing stdout early (`lux info … | head`) is not an
//! error: the report stops and `lux` exits 0 without a message.

mod cli;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "lux",
    version,
    about = "UsdLux lighting, exactly",
    long_about = "UsdLux lighting, exactly. Without a subcommand, renders the bundled demo \
                  scene to lux-demo.exr and lux-demo.png in the current directory."
)]
struct Args {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render a USD stage (direct lighting of every UsdLux light) to EXR and PNG.
    Render(cli::render::RenderArgs),
    /// Summarise a USD stage: lights, their size factors and emission per profile, warnings.
    Info(cli::info::InfoArgs),
    /// IES (LM-63) photometric file tools.
    #[command(subcommand)]
    Ies(cli::ies::IesCommand),
    /// Assemble the tiles of `lux render --tile I/N` into the frame (checked, atomic).
    Merge(cli::merge::MergeArgs),
    /// Write an Open Job Description job template rendering frames as tiles, then merging them.
    Farm(cli::farm::FarmArgs),
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result = match &args.command {
        Some(Command::Render(r)) => cli::render::run(r),
        Some(Command::Info(i)) => cli::info::run(i),
        Some(Command::Ies(cmd)) => cli::ies::run(cmd),
        Some(Command::Merge(m)) => cli::merge::run(m),
        Some(Command::Farm(f)) => cli::farm::run(f),
        None => {
            eprintln!(
                "lux: no command given, so rendering the bundled demo scene to lux-demo.exr and \
                 lux-demo.png here (`lux --help` lists the commands)"
            );
            cli::demo::scene_path(&std::env::temp_dir().join("lux-demo-scene")).and_then(|scene| {
                eprintln!("lux: demo scene {}", scene.display());
                cli::render::run(&cli::render::RenderArgs {
                    scene,
                    frame: Some(1.0),
                    spp: 32,
                    resolution: None,
                    crop: None,
                    camera: None,
                    strict: false,
                    disable_camera_light: false,
                    profile: None,
                    sampling: cli::render::SamplingArg::Lux,
                    light_selection: cli::render::SelectionArg::Auto,
                    integrator: None,
                    visibility: cli::render::VisibilityArg::Exact,
                    max_depth: 8,
                    splits: lux::render::settings::PATH_SPLITS,
                    surfaces: None,
                    light_samples: None,
                    penumbra_samples: 1,
                    shadow_rays: lux::render::settings::VERTEX_SHADOW_RAYS,
                    adaptive_threshold: None,
                    adaptive_max: None,
                    adaptive_splits: None,
                    adaptive_measure: None,
                    no_adaptive: false,
                    subdiv_level: None,
                    threads: None,
                    seed: 0,
                    output: PathBuf::from("lux-demo.exr"),
                    png: Some(PathBuf::from("lux-demo.png")),
                    png_encoding: cli::render::PngEncoding {
                        exposure: 0.0,
                        alpha: false,
                    },
                    quiet: false,
                    fsync: false,
                    tile: None,
                })
            })
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("lux: {msg}");
            ExitCode::FAILURE
        }
    }
}
