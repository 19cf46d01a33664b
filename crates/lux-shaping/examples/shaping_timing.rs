//! CPU time per `Shaping::factor` call for the cases of `benches/shaping.rs`, and per
//! `PhotometricWeb::intensity_with` call in the loop of `benches/ies.rs`, measured with the
//! thread's on-CPU time (`/proc/thread-self/schedstat`), which unlike a wall-clock benchmark is
//! not inflated when the machine is shared. Linux only; falls back to wall-clock time elsewhere.
//!
//! Run: `cargo run -p lux-shaping --release --example shaping_timing`

use glam::DVec3;
use lux_ies::{IesFile, Interpolation, PhotometricWeb};
use lux_math::Profile;
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
use std::hint::black_box;
use std::time::Instant;

const N: usize = 4096;
const OMNI: &str = include_str!("../tests/data/ies/luxtest/bega_omni001_1238lm.ies");

fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Prints the best of 5 runs of `run` (which makes `n` calls) as on-CPU and wall-clock
/// nanoseconds per call.
fn report(name: &str, n: usize, mut run: impl FnMut()) {
    let mut best = (f64::INFINITY, f64::INFINITY);
    for _ in 0..5 {
        let (c0, t0) = (cpu_ns(), Instant::now());
        run();
        let wall = t0.elapsed().as_nanos() as f64 / n as f64;
        let cpu = match (c0, cpu_ns()) {
            (Some(a), Some(b)) => (b - a) as f64 / n as f64,
            _ => wall,
        };
        best = (best.0.min(cpu), best.1.min(wall));
    }
    println!(
        "{name:<40} {:>7.1} ns/call CPU  ({:>7.1} wall)",
        best.0, best.1
    );
}

/// 2²² calls, cycling through `dirs`.
fn measure(name: &str, dirs: &[DVec3], f: impl Fn(DVec3) -> DVec3) {
    let n = 1usize << 22;
    report(name, n, || {
        let mut acc = 0.0;
        for i in 0..n {
            acc += f(black_box(dirs[i & (N - 1)]))[0];
        }
        black_box(acc);
    });
}

/// 2¹⁰ passes over `pairs`, as `benches/ies.rs` does: the sum of `f(θ, φ)`.
fn measure_lookup(name: &str, pairs: &[(f64, f64)], f: impl Fn(f64, f64) -> f64) {
    let passes = 1usize << 10;
    report(name, passes * pairs.len(), || {
        let mut acc = 0.0;
        for _ in 0..passes {
            for &(t, p) in pairs {
                acc += f(black_box(t), black_box(p));
            }
        }
        black_box(acc);
    });
}

/// `N` directions uniform on the sphere, or within `max_theta` of the light's −Z.
fn directions(max_theta: f64) -> Vec<DVec3> {
    let mut s = 0x9E3779B97F4A7C15u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let zmin = max_theta.cos();
    (0..N)
        .map(|_| {
            let c = zmin + (1.0 - zmin) * next();
            let s = (1.0 - c * c).max(0.0).sqrt();
            let p = next() * std::f64::consts::TAU;
            DVec3::new(s * p.cos(), s * p.sin(), -c)
        })
        .collect()
}

fn main() {
    let sphere = directions(std::f64::consts::PI);
    let in_cone = directions(60f64.to_radians());
    let web = PhotometricWeb::new(&IesFile::parse(OMNI).unwrap(), Profile::Spec).unwrap();
    let mk = |p: ShapingParams, w: Option<PhotometricWeb>, o: ShapingOptions| {
        Shaping::new(&p, w, o).unwrap()
    };
    let o = ShapingOptions::default();

    measure("calibration: harness (|d|²)", &sphere, |d| {
        DVec3::splat(d.length_squared())
    });
    measure("calibration: light_polar", &sphere, |d| {
        let (t, p) = lux_math::light_polar(d).unwrap();
        DVec3::splat(t + p)
    });
    measure("calibration: intensity(light_polar)", &sphere, |d| {
        let (t, p) = lux_math::light_polar(d).unwrap();
        DVec3::splat(web.intensity(t, p))
    });
    // the loop of benches/ies.rs: (θ, φ) uniform on the sphere, summed
    let pairs: Vec<(f64, f64)> = sphere
        .iter()
        .map(|&d| lux_math::light_polar(d).unwrap())
        .collect();
    measure_lookup("lux-ies lookup, bilinear", &pairs, |t, p| {
        web.intensity_with(t, p, Interpolation::Bilinear)
    });
    measure_lookup("lux-ies lookup, bicubic", &pairs, |t, p| {
        web.intensity_with(t, p, Interpolation::Bicubic)
    });
    let id = Shaping::identity();
    measure("identity", &sphere, |d| id.factor(d));
    let s = mk(
        ShapingParams {
            cone_angle_deg: 60.0,
            ..Default::default()
        },
        None,
        o,
    );
    measure("hard 60° cone", &sphere, |d| s.factor(d));
    let spot = ShapingParams {
        focus: 2.0,
        focus_tint: DVec3::new(0.2, 0.4, 1.0),
        cone_angle_deg: 60.0,
        cone_softness: 0.3,
        ..ShapingParams::default()
    };
    let s = mk(spot, None, o);
    measure("no_ies (focus 2, tint, soft cone)", &sphere, |d| {
        s.factor(d)
    });
    measure("no_ies_in_cone", &in_cone, |d| s.factor(d));
    let s = mk(ShapingParams { focus: 2.5, ..spot }, None, o);
    measure("no_ies_in_cone, focus 2.5 (powf)", &in_cone, |d| {
        s.factor(d)
    });
    let normalized = ShapingParams {
        ies_normalize: true,
        ..ShapingParams::NO_SHAPING
    };
    let s = mk(normalized, Some(web.clone()), o);
    measure("ies_bilinear", &sphere, |d| s.factor(d));
    let s = mk(
        ShapingParams {
            focus: 1.5,
            focus_tint: DVec3::new(0.1, 0.2, 0.3),
            cone_angle_deg: 120.0,
            cone_softness: 0.5,
            ies_angle_scale: 0.8,
            ies_normalize: true,
        },
        Some(web.clone()),
        o,
    );
    measure("ies_bilinear_shaped", &sphere, |d| s.factor(d));
    let s = mk(
        normalized,
        Some(web.clone()),
        ShapingOptions {
            interpolation: Interpolation::Bicubic,
            ..o
        },
    );
    measure("ies_bicubic", &sphere, |d| s.factor(d));
    let s = mk(normalized, Some(web.clone()), o);
    measure("max_factor_in_cone (10°)", &sphere, |d| {
        DVec3::splat(s.max_factor_in_cone(d, 0.17))
    });
    let t = Instant::now();
    let i = s.integral_sphere();
    println!(
        "integral_sphere (bega_omni001): {:?}  {:.6}",
        t.elapsed(),
        i[0] / (4.0 * std::f64::consts::PI)
    );
}
