//! lux-render benchmarks (issue 7).
//!
//! - `render_luxtest_64spp`: rendering throughput on the luxtest rect and sphere frame 1
//!   (a 64 × 64 window of the 512 × 512 frame around the lit area, 64 spp) with lux and with
//!   hdEmbree's reference sampling; criterion reports samples/s. The full 512² RMSE and
//!   equal-time variance study is `cargo run --release --example render_bench`.
//! - `light_sample_vs_shadow_ray`: the cost of one light sample (lux-sample technique plus
//!   emission: base × shaping × texture) against the shadow ray that tests it, on the same
//!   shading points of the sphere scene. Target: light sample ≤ 1.3 × shadow ray.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::geometry::{Geometry, offset_scale, shadow_tmax};
use lux::render::light::{LightOptions, LightSelection, LightSet};
use lux::render::render::{RenderOptions, Renderer};
use lux::render::settings::{AdaptiveSampling, SamplingMode};
use lux::sample::{Reference, SplitMix64, Strategy};
use lux::usd::{Scene, load_stage};
use std::hint::black_box;
use std::path::PathBuf;

fn luxtest(name: &str) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/luxtest/usd")
        .join(format!("{name}.usda"));
    load_stage(p, 1.0).expect("luxtest scene loads")
}

fn render_luxtest_64spp(c: &mut Criterion) {
    let mut g = c.benchmark_group("render_luxtest_64spp");
    g.sample_size(10);
    for name in ["rect", "sphere"] {
        let scene = luxtest(name);
        for mode in [SamplingMode::Lux, SamplingMode::Reference] {
            let mut o = RenderOptions::new(ResolvedProfile {
                profile: Profile::HdEmbree,
                source: ProfileSource::CommandLine,
            });
            o.spp = 64;
            o.sampling = mode;
            // Per-sample cost: every pixel takes exactly 64 samples.
            o.adaptive = Some(AdaptiveSampling::OFF);
            o.crop = Some([224, 192, 288, 256]);
            let r = Renderer::new(&scene, o).expect("scene prepares");
            g.throughput(Throughput::Elements(64 * 64 * 64));
            g.bench_function(format!("{name}_{mode:?}").to_lowercase(), |b| {
                b.iter(|| black_box(r.render(&|_| {})))
            });
        }
    }
    g.finish();
}

fn light_sample_vs_shadow_ray(c: &mut Criterion) {
    let scene = luxtest("sphere");
    let geometry = Geometry::new(&scene);
    let set = LightSet::new(
        &scene,
        LightOptions {
            cone_clipping: true,
            profile: Profile::HdEmbree,
            selection: LightSelection::All,
            strict: false,
        },
    )
    .expect("lights prepare");
    let light = &set.lights[0];
    // Shading points on the floor around the light, with their light samples.
    let mut rng = SplitMix64::new(7);
    let mut cases = Vec::new();
    while cases.len() < 4096 {
        let [a, b] = rng.next_2d();
        let p = DVec3::new(8.0 * a - 4.0, 0.0, 8.0 * b - 4.0);
        let r = Reference::surface(p, DVec3::Y);
        if let Some(s) = light.sample_li(&r, rng.next_2d(), Strategy::Lux)
            && s.wi.y > 0.0
        {
            cases.push((r, rng.next_2d(), s));
        }
    }
    let mut g = c.benchmark_group("light_sample_vs_shadow_ray");
    let mut i = 0;
    g.bench_function("light_sample_and_emission", |b| {
        b.iter(|| {
            let (r, u, _) = &cases[i & 4095];
            i += 1;
            light
                .sample_li(black_box(r), *u, Strategy::Lux)
                .map(|s| s.l)
        })
    });
    let mut i = 0;
    g.bench_function("shadow_ray", |b| {
        b.iter(|| {
            let (r, _, s) = &cases[i & 4095];
            i += 1;
            let o = r.p + DVec3::Y * offset_scale(r.p);
            geometry.occluded(black_box(o), s.wi, 0.0, shadow_tmax(s.dist, s.point))
        })
    });
    g.finish();
}

criterion_group!(benches, render_luxtest_64spp, light_sample_vs_shadow_ray);
criterion_main!(benches);
