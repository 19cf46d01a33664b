//! Resampled shadow rays (`RenderOptions::shadow_rays`): past the camera's vertex, a path
//! vertex lit by several lights traces one shadow ray for their light samples, picked in
//! proportion to what each adds unshadowed and weighted by its share. The picture is the one a
//! shadow ray per light sample draws, block by block within the standard errors over seeds,
//! for fewer shadow rays.

mod common;

use common::blocks::{agree, block_means};
use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::render::RenderOptions;
use lux::render::settings::{AdaptiveSampling, IntegratorKind, SurfaceModel, VERTEX_SHADOW_RAYS};

/// clutter_mix seed 1 (`make_scenes.py`; tests/data/clutter): boxes and a torus under a
/// sphere, a rect, a disk and a distant light, each casting shadows on the others' ground.
fn clutter_mix() -> lux::usd::Scene {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/clutter/clutter_mix_seed1.usda");
    lux::usd::load_stage(p, 1.0).unwrap()
}

fn path_options(shadow_rays: u32) -> RenderOptions {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.integrator = IntegratorKind::Path;
    o.surfaces = SurfaceModel::Lambert;
    o.max_depth = 4;
    o.spp = 32;
    o.adaptive = Some(AdaptiveSampling::OFF);
    o.shadow_rays = shadow_rays;
    o
}

/// Per block and channel, the mean over seeds of `a − b` (the two estimators with the same
/// seed: their camera vertices and path directions agree, so the difference holds what the
/// resampling adds) lies within 4 standard errors of that difference (paired test), and the
/// largest such z.
fn paired(a: &[Vec<[f64; 3]>], b: &[Vec<[f64; 3]>], what: &str) -> f64 {
    let n = a.len() as f64;
    let mut worst = 0.0f64;
    for k in 0..a[0].len() {
        for c in 0..3 {
            let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x[k][c] - y[k][c]).collect();
            let m = d.iter().sum::<f64>() / n;
            let se = (d.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
            let z = m.abs() / se.max(1e-9);
            worst = worst.max(z);
            assert!(
                z < 4.0,
                "{what}: block {k} channel {c}: difference {m:.6} ± {se:.6}"
            );
        }
    }
    eprintln!("{what}: worst paired difference {worst:.2} standard errors");
    worst
}

#[test]
fn one_resampled_shadow_ray_draws_the_picture_of_one_per_light_sample() {
    // The default, fewer rays than the scene's four lights: resampling acts.
    assert!((1..4).contains(&VERTEX_SHADOW_RAYS));
    let s = clutter_mix();
    let (plain, plain_stats) = block_means(&s, &path_options(0), 32, 8, 24);
    let (pooled, pooled_stats) = block_means(&s, &path_options(VERTEX_SHADOW_RAYS), 32, 8, 24);
    agree(
        &pooled,
        &plain,
        1e-3,
        "one shadow ray a vertex past the camera's",
    );
    // The estimators differ (resampling acted) and by nothing but noise.
    assert!(paired(&pooled, &plain, "paired") > 0.0);
    // The camera's vertex is the same in both; past it, 4 lights' shadow rays become fewer.
    let rays =
        |st: &[lux::render::stats::RenderStats]| st.iter().map(|s| s.shadow_rays).sum::<u64>();
    let (a, b) = (rays(&plain_stats), rays(&pooled_stats));
    assert!(
        (b as f64) < 0.9 * a as f64,
        "shadow rays: one per light sample {a}, resampled {b}"
    );
}

/// As many shadow rays as the vertex has light samples: every sample keeps its own, the plain
/// estimator (to rounding: the pooled samples are added after the others).
#[test]
fn as_many_shadow_rays_as_light_samples_is_the_plain_estimator() {
    let s = clutter_mix();
    let (plain, plain_stats) = block_means(&s, &path_options(0), 16, 8, 1);
    let (all, all_stats) = block_means(&s, &path_options(4), 16, 8, 1);
    assert_eq!(plain_stats[0].shadow_rays, all_stats[0].shadow_rays);
    for (p, q) in plain[0].iter().zip(&all[0]) {
        for c in 0..3 {
            assert!(
                (p[c] - q[c]).abs() <= 1e-6 * p[c].abs().max(1e-6),
                "{p:?} vs {q:?}"
            );
        }
    }
}
