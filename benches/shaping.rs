//! lux-shaping benchmarks: `Shaping::factor` per call (targets: ≤ 15 ns without IES, ≤ 30 ns
//! with a bilinear IES lookup). Directions are precomputed (uniform on the sphere, or inside the
//! cone for the worst case) and cycled.
//!
//! - `factor/no_ies`: focus 2 + tint + a 60° cone with softness 0.3, uniform directions (3/4
//!   of them leave through the cone test);
//! - `factor/no_ies_in_cone`: the same, directions inside the cone only (every call pays
//!   `powf`, and the ones in the ramp `acos`);
//! - `factor/ies_bilinear`: bega_omni001_1238lm.ies (121 × 73, bilateral), ies:normalize, no
//!   cone, uniform directions;
//! - `factor/ies_bilinear_shaped`: the same with angleScale 0.8, focus, tint and a soft 120°
//!   cone;
//! - `factor/ies_bicubic`: the first with bicubic interpolation;
//! - `bounds/max_factor_in_cone`: the IES light's bound over a 10° query cone;
//! - `factor/identity`: a light without ShapingAPI — the cost of the harness and of the
//!   direction check, for reference.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use lux::ies::{IesFile, Interpolation, PhotometricWeb};
use lux::math::Profile;
use lux::shaping::{Shaping, ShapingOptions, ShapingParams};
use std::hint::black_box;

const N: usize = 4096;
const OMNI: &str = include_str!("../tests/data/ies/luxtest/bega_omni001_1238lm.ies");

fn rng() -> impl FnMut() -> f64 {
    let mut s = 0x9E3779B97F4A7C15u64;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `N` directions uniform on the sphere, or within `max_theta` of the light's −Z.
fn directions(max_theta: f64) -> Vec<DVec3> {
    let mut next = rng();
    let zmin = max_theta.cos();
    (0..N)
        .map(|_| {
            // −z uniform in [cos θmax, 1]: uniform in solid angle on the cap
            let c = zmin + (1.0 - zmin) * next();
            let s = (1.0 - c * c).max(0.0).sqrt();
            let p = next() * std::f64::consts::TAU;
            DVec3::new(s * p.cos(), s * p.sin(), -c)
        })
        .collect()
}

fn omni() -> PhotometricWeb {
    PhotometricWeb::new(&IesFile::parse(OMNI).unwrap(), Profile::Spec).unwrap()
}

fn bench(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    s: &Shaping,
    dirs: &[DVec3],
) {
    g.bench_function(name, |b| {
        let mut i = 0usize;
        b.iter(|| {
            i = (i + 1) & (N - 1);
            s.factor(black_box(dirs[i]))
        })
    });
}

fn factor(c: &mut Criterion) {
    let sphere = directions(std::f64::consts::PI);
    let spot = ShapingParams {
        focus: 2.0,
        focus_tint: DVec3::new(0.2, 0.4, 1.0),
        cone_angle_deg: 60.0,
        cone_softness: 0.3,
        ..ShapingParams::default()
    };
    let no_ies = Shaping::new(&spot, None, ShapingOptions::default()).unwrap();
    let in_cone = directions(60f64.to_radians());
    let normalized = ShapingParams {
        ies_normalize: true,
        ..ShapingParams::NO_SHAPING
    };
    let ies = Shaping::new(&normalized, Some(omni()), ShapingOptions::default()).unwrap();
    let shaped = Shaping::new(
        &ShapingParams {
            focus: 1.5,
            focus_tint: DVec3::new(0.1, 0.2, 0.3),
            cone_angle_deg: 120.0,
            cone_softness: 0.5,
            ies_angle_scale: 0.8,
            ies_normalize: true,
        },
        Some(omni()),
        ShapingOptions::default(),
    )
    .unwrap();
    let bicubic = Shaping::new(
        &normalized,
        Some(omni()),
        ShapingOptions {
            interpolation: Interpolation::Bicubic,
            ..Default::default()
        },
    )
    .unwrap();

    let mut g = c.benchmark_group("factor");
    bench(&mut g, "identity", &Shaping::identity(), &sphere);
    bench(&mut g, "no_ies", &no_ies, &sphere);
    bench(&mut g, "no_ies_in_cone", &no_ies, &in_cone);
    bench(&mut g, "ies_bilinear", &ies, &sphere);
    bench(&mut g, "ies_bilinear_shaped", &shaped, &sphere);
    bench(&mut g, "ies_bicubic", &bicubic, &sphere);
    g.finish();

    let mut g = c.benchmark_group("bounds");
    g.bench_function("max_factor_in_cone", |b| {
        let mut i = 0usize;
        b.iter(|| {
            i = (i + 1) & (N - 1);
            ies.max_factor_in_cone(black_box(sphere[i]), black_box(0.17))
        })
    });
    g.finish();
}

criterion_group!(benches, factor);
criterion_main!(benches);
