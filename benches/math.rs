//! lux-math benchmarks (issue 2 targets): sizeFactor per light kind (group `size_factor`: one
//! bench per kind and profile; ≤ 200 ns for the ellipsoid `sphere_ellipsoid_exact`, ≤ 20 ns for
//! the rest) and the blackbody colour (group `blackbody`, ≤ 20 ns).

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DMat4, DQuat, DVec3};
use lux::math::{
    LightShape, Profile, hdembree_blackbody_rgb, size_factor, spec_blackbody_rgb,
    usdlux_blackbody_rgb,
};
use std::hint::black_box;

fn transform() -> DMat4 {
    // Rotation, non-uniform scale and a shear: the general case.
    let shear = DMat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.1, -0.2, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    DMat4::from_rotation_translation(
        DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.4),
        DVec3::new(1.0, 2.0, 3.0),
    ) * DMat4::from_scale(DVec3::new(2.0, 0.7, 1.3))
        * shear
}

fn size_factors(c: &mut Criterion) {
    let m = transform();
    let mut g = c.benchmark_group("size_factor");
    let shapes = [
        (
            "sphere_ellipsoid_exact",
            LightShape::Sphere { radius: 0.5 },
            Profile::Spec,
        ),
        (
            "sphere_thomsen",
            LightShape::Sphere { radius: 0.5 },
            Profile::HdEmbree,
        ),
        (
            "cylinder_exact",
            LightShape::Cylinder {
                radius: 0.5,
                length: 1.0,
            },
            Profile::Spec,
        ),
        (
            "cylinder_ramanujan",
            LightShape::Cylinder {
                radius: 0.5,
                length: 1.0,
            },
            Profile::HdEmbree,
        ),
        (
            "disk_exact",
            LightShape::Disk { radius: 0.5 },
            Profile::Spec,
        ),
        (
            "disk_reference",
            LightShape::Disk { radius: 0.5 },
            Profile::HdEmbree,
        ),
        (
            "portal",
            LightShape::Portal {
                width: 1.0,
                height: 1.0,
            },
            Profile::Spec,
        ),
        (
            // A MeshLightAPI quad: two triangles.
            "mesh_2_triangles",
            LightShape::Mesh {
                triangles: vec![
                    [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)],
                    [DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
                ],
            },
            Profile::Spec,
        ),
        (
            "rect",
            LightShape::Rect {
                width: 1.0,
                height: 2.0,
            },
            Profile::Spec,
        ),
        (
            "distant",
            LightShape::Distant { angle_deg: 0.53 },
            Profile::Spec,
        ),
        ("dome", LightShape::Dome, Profile::Spec),
    ];
    for (name, shape, profile) in shapes {
        g.bench_function(name, |b| {
            b.iter(|| size_factor(black_box(&shape), black_box(&m), profile))
        });
    }
    let uniform = DMat4::from_scale(DVec3::splat(2.0));
    let sphere = LightShape::Sphere { radius: 0.5 };
    g.bench_function("sphere_uniform_scale", |b| {
        b.iter(|| size_factor(black_box(&sphere), black_box(&uniform), Profile::Spec))
    });
    // Not a size factor: the machine's latency floor for comparison, one dependent chain of
    // square root → square root → division (what any exact elliptic perimeter needs at least
    // after its projection), each step feeding the next iteration.
    g.bench_function("floor_sqrt_sqrt_div_chain", |b| {
        let mut x = 1.5f64;
        b.iter(|| {
            x = 1.0 / ((black_box(x) + 0.5).sqrt() + 1.0).sqrt() + 1.0;
            x
        })
    });
    g.finish();
}

fn blackbody(c: &mut Criterion) {
    let mut g = c.benchmark_group("blackbody");
    g.bench_function("usdlux", |b| {
        b.iter(|| usdlux_blackbody_rgb(black_box(3700.0)))
    });
    g.bench_function("spec", |b| b.iter(|| spec_blackbody_rgb(black_box(3700.0))));
    g.bench_function("hdembree", |b| {
        b.iter(|| hdembree_blackbody_rgb(black_box(3700.0)))
    });
    g.finish();
}

/// Latency floors used in the issue notes (not targets): one dependent chain through libm's
/// `atan2` and one through its `sin_cos`, each step feeding the next.
fn latency(c: &mut Criterion) {
    let mut g = c.benchmark_group("latency");
    g.bench_function("atan2_chain", |b| {
        let mut x = 0.3f64;
        b.iter(|| {
            x = black_box(x).atan2(1.7) + 0.25;
            x
        })
    });
    g.bench_function("sin_cos_chain", |b| {
        let mut x = 0.3f64;
        b.iter(|| {
            let (s, c) = black_box(x).sin_cos();
            x = s * 0.5 + c * 0.25 + 0.5;
            x
        })
    });
    g.finish();
}

criterion_group!(benches, size_factors, blackbody, latency);
criterion_main!(benches);
