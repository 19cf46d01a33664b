//! CPU time per light sample for every technique, measured with the thread's on-CPU time
//! (`/proc/thread-self/schedstat`), which unlike wall-clock benchmarks is not inflated when the
//! machine is shared. Linux only; falls back to wall-clock time elsewhere.
//!
//! Run: `cargo run -p lux-sample --release --example sample_timing`

use glam::{DMat4, DVec3};
use lux_sample::*;
use std::hint::black_box;
use std::time::Instant;

fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn measure(name: &str, mut f: impl FnMut(usize) -> bool) {
    let n = 4_000_000;
    let (c0, t0) = (cpu_ns(), Instant::now());
    let mut ok = 0usize;
    for i in 0..n {
        ok += black_box(f(i)) as usize;
    }
    let wall = t0.elapsed().as_nanos() as f64 / n as f64;
    let cpu = match (c0, cpu_ns()) {
        (Some(a), Some(b)) => (b - a) as f64 / n as f64,
        _ => wall,
    };
    println!(
        "{name:<36} {cpu:>8.1} ns/sample CPU  ({wall:>7.1} wall, {:.0} % ok)",
        100.0 * ok as f64 / n as f64
    );
}

fn main() {
    // Calibration: a dependent chain of one multiply-add and one sqrt (≈ 20–25 cycles latency,
    // i.e. ≈ 6 ns at 4 GHz on an idle modern core).
    let mut x = 1.0f64;
    measure("calibration: dependent fma+sqrt", |_| {
        x = (x * 1.000_000_1 + 0.5).sqrt();
        x > 0.0
    });
    let mut rng = SplitMix64::new(42);
    let us: Vec<[f64; 2]> = (0..4096).map(|_| rng.next_2d()).collect();
    let r = Reference::surface(DVec3::new(0.1, 0.2, 0.0), DVec3::Z);
    let up =
        |h: f64| LightTransform::new(DMat4::from_translation(DVec3::new(0.0, 0.0, h))).unwrap();
    let skew = DMat4::from_translation(DVec3::new(0.0, 0.0, 1.5))
        * DMat4::from_cols_array(&[
            1.3, 0.0, 0.0, 0.0, 0.4, 0.8, 0.0, 0.0, 0.0, 0.2, 1.1, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
    let skew = LightTransform::new(skew).unwrap();
    let (w, h) = (2048usize, 1024usize);
    let tex: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
            let sun = if (x - 0.3).abs() < 0.004 && (y - 0.3).abs() < 0.004 {
                5e4
            } else {
                0.0
            };
            0.5 + (1.0 - y) + 0.3 * (40.0 * x).sin() + sun
        })
        .collect();
    let map = LatLongMap::new(w, h, tex).unwrap();
    let lights: Vec<(&str, Light)> = vec![
        (
            "spherical_rectangle",
            Light::Rect(
                RectLight::new(1.0, 1.0, up(0.25), RectTechnique::SphericalRectangle).unwrap(),
            ),
        ),
        (
            "spherical_rectangle_cosine",
            Light::Rect(
                RectLight::new(1.0, 1.0, up(0.25), RectTechnique::SphericalRectangleCosine)
                    .unwrap(),
            ),
        ),
        (
            "rect_area",
            Light::Rect(RectLight::new(1.0, 1.0, up(0.25), RectTechnique::Area).unwrap()),
        ),
        (
            "sphere_cone",
            Light::Sphere(SphereLight::new(0.5, up(1.5), SphereTechnique::Cone).unwrap()),
        ),
        (
            "sphere_cone_sheared",
            Light::Sphere(SphereLight::new(0.5, skew, SphereTechnique::Cone).unwrap()),
        ),
        (
            "sphere_area",
            Light::Sphere(SphereLight::new(0.5, up(1.5), SphereTechnique::Area).unwrap()),
        ),
        (
            "disk_elliptic_cone",
            Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::EllipticCone).unwrap()),
        ),
        (
            "disk_polar_chord",
            Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::PolarChord).unwrap()),
        ),
        (
            "disk_area",
            Light::Disk(DiskLight::new(0.5, up(0.5), DiskTechnique::Area).unwrap()),
        ),
        (
            "cylinder_solid_angle",
            Light::Cylinder(
                CylinderLight::new(0.5, 1.0, up(1.0), CylinderTechnique::SolidAngle).unwrap(),
            ),
        ),
        (
            "cylinder_visible_area",
            Light::Cylinder(
                CylinderLight::new(0.5, 1.0, up(1.0), CylinderTechnique::VisibleArea).unwrap(),
            ),
        ),
        (
            "cylinder_area",
            Light::Cylinder(
                CylinderLight::new(0.5, 1.0, up(1.0), CylinderTechnique::Area).unwrap(),
            ),
        ),
        (
            "distant_cone",
            Light::Distant(DistantLight::new(0.53, &LightTransform::IDENTITY).unwrap()),
        ),
        (
            "dome_2048x1024",
            Light::Dome(
                DomeLight::new(&map, LightTransform::IDENTITY, DomeTechnique::Texture).unwrap(),
            ),
        ),
        (
            "dome_mis_compensated_2048x1024",
            Light::Dome(
                DomeLight::new(
                    &map,
                    LightTransform::IDENTITY,
                    DomeTechnique::MisCompensated,
                )
                .unwrap(),
            ),
        ),
        (
            "dome_uniform",
            Light::Dome(DomeLight::uniform(LightTransform::IDENTITY)),
        ),
    ];
    for (name, light) in &lights {
        measure(&format!("{name}/sample"), |i| {
            light.sample(&r, us[i & 4095]).is_some()
        });
        let dirs: Vec<DVec3> = us
            .iter()
            .filter_map(|&u| light.sample(&r, u))
            .map(|s| s.wi)
            .collect();
        measure(&format!("{name}/pdf"), |i| {
            light.pdf(&r, dirs[i % dirs.len()]) > 0.0
        });
    }
}
