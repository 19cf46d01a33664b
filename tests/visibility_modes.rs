//! The exact visibility changes the cost and the noise, never the picture: every scene here is
//! rendered with `--visibility rays` (shadow rays through the BVH for every light sample) and
//! `exact` (closed forms, exact penumbrae, card outlines, tile lists), each over its own seeds,
//! and the two agree block by block — 8 × 8-pixel blocks, each channel — within 5 combined
//! standard errors, and over the whole image within 4. Scenes: the luxtest frames the
//! accelerations were made for, generated clutter scenes they were not (`tests/data/clutter`),
//! an instanced stage and a light- and shadow-linked one, direct lighting (`hdembree`) and
//! path tracing (`spec`).

use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::render::{RenderOptions, Renderer};
use lux::render::settings::VisibilityMode;
use lux::usd::{Membership, Rule, Scene};
use std::path::Path;

const SIZE: u32 = 48;
const BLOCK: u32 = 8;
const SEEDS: u64 = 8;

fn load(rel: &str) -> Scene {
    lux::usd::load_stage(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel), 1.0).unwrap()
}

/// Per seed: each block's mean RGB, and the shadow rays traced.
fn blocks(s: &Scene, profile: Profile, spp: u32, vis: VisibilityMode) -> (Vec<Vec<[f64; 3]>>, u64) {
    let mut shadow = 0;
    let runs = (0..SEEDS)
        .map(|seed| {
            let mut o = RenderOptions::new(ResolvedProfile {
                profile,
                source: ProfileSource::CommandLine,
            });
            o.spp = spp;
            // (independent seeds for the two modes: a two-sample comparison, not a paired one)
            o.seed = 77 + seed + 1000 * (vis == VisibilityMode::Exact) as u64;
            o.resolution = Some([SIZE, SIZE]);
            o.visibility = vis;
            let r = Renderer::new(s, o).unwrap();
            let (img, stats) = r.render(&|_| {});
            assert_eq!(stats.non_finite_samples, 0);
            shadow += stats.shadow_rays;
            let nb = SIZE / BLOCK;
            let mut b = vec![[0.0; 3]; (nb * nb) as usize];
            for y in 0..SIZE {
                for x in 0..SIZE {
                    let p = img.pixels[(y * SIZE + x) as usize];
                    for c in 0..3 {
                        b[((y / BLOCK) * nb + x / BLOCK) as usize][c] +=
                            p[c] as f64 / (BLOCK * BLOCK) as f64;
                    }
                }
            }
            b
        })
        .collect();
    (runs, shadow)
}

/// Mean and standard error over seeds of `f(run)`.
fn stat(runs: &[Vec<[f64; 3]>], f: impl Fn(&Vec<[f64; 3]>) -> f64) -> (f64, f64) {
    let n = runs.len() as f64;
    let v: Vec<f64> = runs.iter().map(f).collect();
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Renders `s` both ways and holds the blocks and the image equal within their errors; returns
/// the shadow rays of (rays, exact).
fn same_picture(name: &str, s: &Scene, profile: Profile, spp: u32) -> (u64, u64) {
    let (rays, n_rays) = blocks(s, profile, spp, VisibilityMode::Rays);
    let (exact, n_exact) = blocks(s, profile, spp, VisibilityMode::Exact);
    let nb = rays[0].len();
    let whole = |r: &Vec<[f64; 3]>, c: usize| r.iter().map(|b| b[c]).sum::<f64>() / nb as f64;
    let top = (0..nb)
        .map(|k| stat(&rays, |r| r[k][1]).0)
        .fold(0.0f64, f64::max);
    assert!(top > 1e-3, "{name}: lit ({top})");
    // (a floor for blocks both modes find exactly, to the rounding of their sums)
    let floor = 1e-4 * top;
    let mut worst = 0.0f64;
    for c in 0..3 {
        for k in 0..nb {
            let ((a, sa), (b, sb)) = (stat(&rays, |r| r[k][c]), stat(&exact, |r| r[k][c]));
            let z = (a - b).abs() / (sa * sa + sb * sb).sqrt().max(floor);
            worst = worst.max(z);
            assert!(
                z < 5.0,
                "{name}: block {k} channel {c}: rays {a:.5} ± {sa:.5}, exact {b:.5} ± {sb:.5}"
            );
        }
        let ((a, sa), (b, sb)) = (stat(&rays, |r| whole(r, c)), stat(&exact, |r| whole(r, c)));
        let z = (a - b).abs() / (sa * sa + sb * sb).sqrt().max(floor);
        assert!(
            z < 4.0,
            "{name}: image channel {c}: rays {a:.5} ± {sa:.5}, exact {b:.5} ± {sb:.5}"
        );
    }
    eprintln!("{name}: worst block {worst:.2} σ; shadow rays {n_rays} (rays) vs {n_exact} (exact)");
    (n_rays, n_exact)
}

#[test]
fn luxtest_frames_look_the_same_with_rays_and_exact_visibility() {
    for name in ["sphere", "disk", "rect", "cylinder"] {
        let s = load(&format!("tests/data/luxtest/usd/{name}.usda"));
        let (rays, exact) = same_picture(name, &s, Profile::HdEmbree, 8);
        // (the accelerations apply on the frames they were made for)
        if name != "cylinder" {
            assert!(exact * 2 < rays, "{name}: {exact} vs {rays} shadow rays");
        }
    }
    let s = load("tests/data/luxtest/usd/rect.usda");
    same_picture("rect (path tracing)", &s, Profile::Spec, 8);
}

#[test]
fn clutter_scenes_look_the_same_with_rays_and_exact_visibility() {
    for name in ["clutter_mix_seed1", "clutter_many_seed2"] {
        let s = load(&format!("tests/data/clutter/{name}.usda"));
        same_picture(name, &s, Profile::HdEmbree, 8);
        same_picture(&format!("{name} (path tracing)"), &s, Profile::Spec, 4);
    }
}

#[test]
fn instanced_and_linked_scenes_look_the_same_with_rays_and_exact_visibility() {
    let s = load("tests/data/emissive_instanced/pointinstancer.usda");
    same_picture("point instancer", &s, Profile::Spec, 8);
    // The clutter under its four lights, the first lighting everything but two boxes and its
    // shadows cast by everything but two others.
    let mut s = load("tests/data/clutter/clutter_mix_seed1.usda");
    let rules = |entries: &[(&str, Rule)]| {
        Membership::Rules(entries.iter().map(|(p, r)| ((*p).to_owned(), *r)).collect())
    };
    s.lights[0].linking.light = rules(&[
        ("/", Rule::ExpandPrims),
        ("/clutter/box00", Rule::Exclude),
        ("/clutter/box01", Rule::Exclude),
    ]);
    s.lights[0].linking.shadow = rules(&[
        ("/", Rule::ExpandPrims),
        ("/clutter/box02", Rule::Exclude),
        ("/clutter/box03", Rule::Exclude),
    ]);
    same_picture("linked clutter", &s, Profile::HdEmbree, 8);
}
