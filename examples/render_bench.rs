//! The render benchmark of issue 7: luxtest rect and sphere frame 1 at 512×512, 64 spp, with
//! `--sampling lux` and `--sampling reference`: wall time, samples/s, RMSE against a
//! high-sample ground truth rendered with lux sampling, and the equal-time variance ratio
//! `(MSE_ref · t_ref) / (MSE_lux · t_lux)` (how much longer the reference strategy must run to
//! reach lux's error).
//!
//! ```sh
//! cargo run --release --example render_bench -- [GROUND_TRUTH_SPP=4096] [SPP=64]
//! ```
//!
//! The ground truth is cached next to the target directory (`target/render_bench_*.exr`) so
//! that re-runs only re-measure the 64-spp renders.

use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::image_io::{ImageRgba, Texture, write_exr};
use lux::render::render::{RenderOptions, Renderer};
use lux::render::settings::SamplingMode;
use lux::usd::load_stage;
use std::path::PathBuf;

fn render(
    scene: &lux::usd::Scene,
    mode: SamplingMode,
    spp: u32,
    seed: u64,
) -> (ImageRgba, f64, u64) {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::HdEmbree,
        source: ProfileSource::CommandLine,
    });
    o.spp = spp;
    o.sampling = mode;
    o.seed = seed;
    let r = Renderer::new(scene, o).expect("scene prepares");
    let (img, stats) = r.render(&|_| {});
    (img, stats.seconds, stats.samples)
}

fn mse(a: &ImageRgba, b: &ImageRgba) -> f64 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| ((p[c] - q[c]) as f64).powi(2)).sum::<f64>() / 3.0)
        .sum::<f64>()
        / a.pixels.len() as f64
}

fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let gt_spp = args.first().copied().unwrap_or(4096);
    let spp = args.get(1).copied().unwrap_or(64);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let data = root.join("tests/data/luxtest/usd");
    println!(
        "threads: {}; ground truth {gt_spp} spp (lux sampling); measured {spp} spp",
        rayon::current_num_threads()
    );
    for name in ["rect", "sphere"] {
        let scene = load_stage(data.join(format!("{name}.usda")), 1.0).expect("luxtest loads");
        let cache = root.join(format!("target/render_bench_{name}_{gt_spp}.exr"));
        let gt = match Texture::load(&cache) {
            Ok(t) => ImageRgba {
                width: t.width(),
                height: t.height(),
                pixels: t.texels().to_vec(),
            },
            Err(_) => {
                let (img, t, _) = render(&scene, SamplingMode::Lux, gt_spp, 99);
                println!("{name}: ground truth rendered in {t:.1} s");
                write_exr(&cache, &img).expect("cache written");
                img
            }
        };
        let mut res = Vec::new();
        for mode in [SamplingMode::Lux, SamplingMode::Reference] {
            let (img, t, samples) = render(&scene, mode, spp, 1);
            let e = mse(&img, &gt);
            println!(
                "{name} {mode:?}: {t:.3} s, {:.3} M samples/s, RMSE {:.5}",
                samples as f64 / t / 1e6,
                e.sqrt()
            );
            res.push((e, t));
        }
        let (lux, reference) = (res[0], res[1]);
        println!(
            "{name}: variance ratio at equal spp {:.2}, at equal time {:.2}",
            reference.0 / lux.0,
            (reference.0 * reference.1) / (lux.0 * lux.1)
        );
    }
}
