//! Shaped-light sampling benchmark: the equal-time variance of luxtest frames lit through a
//! ShapingAPI cone, with the light sampled only where its cone reaches the receiver
//! (lux-sample's `with_emission_cone`, the default) against the whole light (the technique
//! before it, `RenderOptions::cone_clipping = false`), and with 4 light samples per camera
//! sample.
//!
//! Frames: rect 25 (cone 10°), cylinder 25 (cone 10°), cylinder 32 and 33 (cone 45°, softness
//! 0.25 and 0.5). 256 × 256, `hdembree` profile, 16 spp; the variance of each configuration is
//! estimated from two renders with different seeds (`mean((a − b)²)/2` per pixel and channel),
//! its time is the mean render time. The ratio printed is `(V·t)_whole / (V·t)_config`.
//!
//! ```sh
//! cargo run --release --example shaped_variance -- [SPP=16]
//! ```

use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::image_io::ImageRgba;
use lux::render::render::{RenderOptions, Renderer};
use lux::render::settings::AdaptiveSampling;
use lux::usd::load_stage;
use std::path::PathBuf;

fn render(
    scene: &lux::usd::Scene,
    spp: u32,
    clip: bool,
    light_samples: u32,
    seed: u64,
) -> (ImageRgba, f64) {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::HdEmbree,
        source: ProfileSource::CommandLine,
    });
    o.spp = spp;
    o.resolution = Some([256, 256]);
    o.cone_clipping = clip;
    o.light_samples = Some(light_samples);
    // The light sampling itself is measured: every pixel takes exactly `spp` samples.
    o.adaptive = Some(AdaptiveSampling::OFF);
    o.seed = seed;
    let r = Renderer::new(scene, o).expect("scene prepares");
    let (img, stats) = r.render(&|_| {});
    (img, stats.seconds)
}

/// (per-pixel variance of one render, mean seconds, image mean)
fn measure(scene: &lux::usd::Scene, spp: u32, clip: bool, light_samples: u32) -> (f64, f64, f64) {
    let (a, ta) = render(scene, spp, clip, light_samples, 1);
    let (b, tb) = render(scene, spp, clip, light_samples, 2);
    let (mut v, mut m) = (0.0, 0.0);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let (x, y) = (p[c] as f64, q[c] as f64);
            v += (x - y) * (x - y) / 2.0;
            m += (x + y) / 2.0;
        }
    }
    let n = 3.0 * a.pixels.len() as f64;
    (v / n, 0.5 * (ta + tb), m / n)
}

fn main() {
    let spp = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(16);
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/luxtest/usd");
    println!(
        "threads: {}; 256×256, {spp} spp, hdembree profile",
        rayon::current_num_threads()
    );
    println!(
        "| frame | configuration | variance | seconds | image mean | equal-time variance ratio |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, frame) in [
        ("rect", 25.0),
        ("cylinder", 25.0),
        ("cylinder", 32.0),
        ("cylinder", 33.0),
    ] {
        let scene = load_stage(data.join(format!("{name}.usda")), frame).expect("luxtest loads");
        let whole = measure(&scene, spp, false, 1);
        for (label, clip, k) in [
            ("whole light", false, 1),
            ("cone-clipped", true, 1),
            ("cone-clipped, 4 light samples", true, 4),
        ] {
            let r = if clip {
                measure(&scene, spp, clip, k)
            } else {
                whole
            };
            println!(
                "| {name} {frame} | {label} | {:.3e} | {:.3} | {:.5} | {:.2} |",
                r.0,
                r.1,
                r.2,
                (whole.0 * whole.1) / (r.0 * r.1)
            );
        }
    }
}
