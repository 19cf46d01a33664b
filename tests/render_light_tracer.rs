//! The light tracer (`--integrator light`) against the path tracer on the Cornell box: two
//! estimators of the same picture, one from the camera, one from the light. Block means over
//! independent seeds agree within their standard errors, for all bounces and for direct light
//! alone (depth 1, against the direct integrator).

mod common;

use common::blocks::{self, stat};
use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::render::{RenderOptions, Renderer};
use lux::render::settings::{AdaptiveSampling, IntegratorKind, PATH_SPLITS, SurfaceModel};

/// No adaptive sampling: every pixel takes `spp`.
const OFF: AdaptiveSampling = AdaptiveSampling::OFF;

const SIZE: u32 = 32;
/// Blocks of BLOCK × BLOCK pixels compared.
const BLOCK: u32 = 8;
const SEEDS: u64 = 8;

fn cornell() -> lux::usd::Scene {
    let p =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cornell/cornell.usda");
    lux::usd::load_stage(p, 1.0).unwrap()
}

/// Per seed, the mean RGB of each block (`splits` paths continued from each camera sample's
/// first vertex, for the path tracer; surfaces drawn as `surfaces`, `None`: the profile's),
/// with `adaptive` sampling.
fn block_means(
    s: &lux::usd::Scene,
    kind: IntegratorKind,
    depth: u32,
    spp: u32,
    splits: u32,
    surfaces: Option<SurfaceModel>,
    adaptive: AdaptiveSampling,
) -> Vec<Vec<[f64; 3]>> {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.integrator = kind;
    o.max_depth = depth;
    o.path_splits = splits;
    if let Some(m) = surfaces {
        o.surfaces = m;
    }
    o.spp = spp;
    o.adaptive = Some(adaptive);
    blocks::block_means(s, &o, SIZE, BLOCK, SEEDS).0
}

/// Every block's mean agrees within 4 combined standard errors, and some blocks are lit.
fn agree(a: &[Vec<[f64; 3]>], b: &[Vec<[f64; 3]>], what: &str) {
    blocks::agree(a, b, 1e-2, what)
}

/// Also the check of the path tracer's two continuations from the camera's vertex
/// (`PATH_SPLITS`) against an independent estimator.
#[test]
fn light_tracing_matches_path_tracing_on_the_cornell_box() {
    let s = cornell();
    let path = block_means(&s, IntegratorKind::Path, 8, 256, PATH_SPLITS, None, OFF);
    let light = block_means(&s, IntegratorKind::Light, 8, 256, 1, None, OFF);
    agree(&path, &light, "depth 8");
}

/// With Lambertian receivers the box's rect light goes alone at every vertex, and past the
/// camera's vertex the path tracer samples it uniformly by area (`Nee::strategy_for`): still
/// the light tracer's picture.
#[test]
fn lambertian_path_tracing_matches_light_tracing() {
    let s = cornell();
    let lambert = Some(SurfaceModel::Lambert);
    let path = block_means(&s, IntegratorKind::Path, 8, 128, PATH_SPLITS, lambert, OFF);
    let light = block_means(&s, IntegratorKind::Light, 8, 256, 1, lambert, OFF);
    agree(&path, &light, "depth 8, Lambertian");
}

/// The path tracer's adaptive sampling by the linear measure (its default): pixel counts
/// read from the neighbours' samples and the frame pilot's, extra samples continuing each
/// pixel's points, split into as many continuations as the neighbours find cheapest and
/// weighted by their variance (adaptive splitting), also from one sample a pixel, or without
/// splitting. Still the light tracer's picture, block by block.
#[test]
fn adaptive_path_tracing_matches_light_tracing() {
    let s = cornell();
    let lambert = Some(SurfaceModel::Lambert);
    let a = AdaptiveSampling::PATH;
    assert!(a.max_splits > PATH_SPLITS);
    let path = block_means(&s, IntegratorKind::Path, 8, 32, PATH_SPLITS, lambert, a);
    let light = block_means(&s, IntegratorKind::Light, 8, 256, 1, lambert, OFF);
    agree(&path, &light, "depth 8, Lambertian, adaptive");
    // One sample a pixel: the spread across the neighbours stands in for the one within.
    let one = block_means(&s, IntegratorKind::Path, 8, 1, PATH_SPLITS, lambert, a);
    agree(&one, &light, "depth 8, Lambertian, adaptive from 1 spp");
    let plain = AdaptiveSampling { max_splits: 1, ..a };
    let unsplit = block_means(&s, IntegratorKind::Path, 8, 32, PATH_SPLITS, lambert, plain);
    agree(
        &unsplit,
        &light,
        "depth 8, Lambertian, adaptive without splitting",
    );
    // (adaptive splitting acted: other samples, other means)
    assert_ne!(path, unsplit);
}

#[test]
fn light_tracing_of_one_bounce_matches_direct_lighting() {
    let s = cornell();
    let direct = block_means(&s, IntegratorKind::Direct, 1, 256, 1, None, OFF);
    let light = block_means(&s, IntegratorKind::Light, 1, 256, 1, None, OFF);
    agree(&direct, &light, "depth 1");
}

/// Splitting the path at the camera's vertex (4 continuations weighted ¼, each its own
/// sub-sample) estimates what one continuation does: block means over seeds agree within
/// their standard errors, and 4 continuations at 64 spp are less noisy than one at 64 spp.
#[test]
fn first_vertex_splits_match_one_continuation() {
    let s = cornell();
    let one = block_means(&s, IntegratorKind::Path, 8, 64, 1, None, OFF);
    let four = block_means(&s, IntegratorKind::Path, 8, 64, 4, None, OFF);
    agree(&one, &four, "4 splits");
    let spread = |runs: &[Vec<[f64; 3]>]| -> f64 {
        (0..runs[0].len()).map(|k| stat(runs, k, 1).1).sum::<f64>()
    };
    let (a, b) = (spread(&one), spread(&four));
    assert!(
        b < 0.85 * a,
        "standard errors: one continuation {a:.5}, four {b:.5}"
    );
}

/// The light tracer's image is the same bits for any thread count (splats sum in fixed
/// point), and a band of rows is the same bits as those rows of the whole frame.
#[test]
fn light_tracing_is_deterministic_across_threads_and_bands() {
    let s = cornell();
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.integrator = IntegratorKind::Light;
    o.spp = 8;
    o.resolution = Some([40, 24]);
    let render = |threads: usize, band: Option<[u32; 2]>| {
        let mut r = Renderer::new(&s, o.clone()).unwrap();
        if let Some(b) = band {
            r.restrict_rows(b);
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| r.render(&|_| {})).0
    };
    let bits = |img: &lux::render::image_io::ImageRgba| -> Vec<[u32; 4]> {
        img.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
    };
    let one = render(1, None);
    assert!(one.pixels.iter().any(|p| p[1] > 0.0));
    assert_eq!(bits(&one), bits(&render(3, None)));
    let band = render(2, Some([7, 15]));
    for y in 0..24usize {
        for x in 0..40usize {
            let (a, b) = (one.pixels[y * 40 + x], band.pixels[y * 40 + x]);
            if (7..15).contains(&y) {
                assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "({x}, {y})");
            } else {
                assert_eq!(b, [0.0; 4]);
            }
        }
    }
}
