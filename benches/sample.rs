//! lux-sample benchmarks: nanoseconds per light sample for every technique (issue 5 targets:
//! ≤ 60 ns spherical rectangle, ≤ 30 ns sphere cone, ≤ 100 ns dome 2048×1024).
//!
//! Run: `cargo bench --bench sample`

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DMat4, DVec3};
use lux_sample::*;
use std::hint::black_box;

const NU: usize = 1024;

fn uniforms() -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(42);
    (0..NU).map(|_| r.next_2d()).collect()
}

fn bench_light(c: &mut Criterion, group: &str, light: &Light, r: Reference) {
    let us = uniforms();
    let mut g = c.benchmark_group(group);
    let mut i = 0usize;
    g.bench_function("sample", |b| {
        b.iter(|| {
            i = (i + 1) & (NU - 1);
            black_box(light.sample(black_box(&r), us[i]))
        })
    });
    let dirs: Vec<DVec3> = us
        .iter()
        .filter_map(|&u| light.sample(&r, u))
        .map(|s| s.wi)
        .collect();
    if !dirs.is_empty() {
        let mut k = 0usize;
        g.bench_function("pdf", |b| {
            b.iter(|| {
                k = (k + 1) % dirs.len();
                black_box(light.pdf(black_box(&r), dirs[k]))
            })
        });
    }
    g.finish();
}

fn up(h: f64) -> LightTransform {
    LightTransform::new(DMat4::from_translation(DVec3::new(0.0, 0.0, h))).unwrap()
}

fn benches(c: &mut Criterion) {
    let r = Reference::surface(DVec3::new(0.1, 0.2, 0.0), DVec3::Z);
    let rect = |t| Light::Rect(RectLight::new(1.0, 1.0, up(0.25), t).unwrap());
    bench_light(
        c,
        "spherical_rectangle",
        &rect(RectTechnique::SphericalRectangle),
        r,
    );
    bench_light(
        c,
        "spherical_rectangle_cosine",
        &rect(RectTechnique::SphericalRectangleCosine),
        r,
    );
    bench_light(c, "rect_area", &rect(RectTechnique::Area), r);
    // The technique itself in the light's frame (the rect light above: 1 × 1 at height 0.25,
    // seen from (0.1, 0.2, 0)): the set-up per reference point, and one more sample from a
    // prepared set-up (what each further sample at the same point costs).
    {
        let o = DVec3::new(0.1, 0.2, -0.25);
        let us = uniforms();
        let mut g = c.benchmark_group("spherical_rectangle_parts");
        g.bench_function("setup", |b| {
            b.iter(|| {
                black_box(spherical::SphericalRectangle::centred(
                    black_box(o),
                    0.5,
                    0.5,
                ))
            })
        });
        let sr = spherical::SphericalRectangle::centred(o, 0.5, 0.5);
        let mut i = 0usize;
        g.bench_function("sample_prepared", |b| {
            b.iter(|| {
                i = (i + 1) & (NU - 1);
                black_box(black_box(&sr).sample(us[i]))
            })
        });
        g.finish();
    }

    let sphere = |t| Light::Sphere(SphereLight::new(0.5, up(1.5), t).unwrap());
    bench_light(c, "sphere_cone", &sphere(SphereTechnique::Cone), r);
    bench_light(c, "sphere_area", &sphere(SphereTechnique::Area), r);
    let skew = DMat4::from_translation(DVec3::new(0.0, 0.0, 1.5))
        * DMat4::from_cols_array(&[
            1.3, 0.0, 0.0, 0.0, 0.4, 0.8, 0.0, 0.0, 0.0, 0.2, 1.1, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
    let ellipsoid = SphereLight::new(
        0.5,
        LightTransform::new(skew).unwrap(),
        SphereTechnique::Cone,
    )
    .unwrap();
    bench_light(c, "sphere_cone_sheared", &Light::Sphere(ellipsoid), r);
    let disk = |t| Light::Disk(DiskLight::new(0.5, up(0.5), t).unwrap());
    bench_light(
        c,
        "disk_elliptic_cone",
        &disk(DiskTechnique::EllipticCone),
        r,
    );
    bench_light(c, "disk_polar_chord", &disk(DiskTechnique::PolarChord), r);
    bench_light(c, "disk_area", &disk(DiskTechnique::Area), r);
    let cyl = |t| Light::Cylinder(CylinderLight::new(0.5, 1.0, up(1.0), t).unwrap());
    bench_light(
        c,
        "cylinder_solid_angle",
        &cyl(CylinderTechnique::SolidAngle),
        r,
    );
    bench_light(
        c,
        "cylinder_visible_area",
        &cyl(CylinderTechnique::VisibleArea),
        r,
    );
    bench_light(c, "cylinder_area", &cyl(CylinderTechnique::Area), r);

    // A 32×32-quad grid (2048 triangles) facing down at height 1.
    let n = 32;
    let mut pts = Vec::new();
    for y in 0..=n {
        for x in 0..=n {
            pts.push(DVec3::new(
                x as f64 / n as f64 - 0.5,
                y as f64 / n as f64 - 0.5,
                1.0,
            ));
        }
    }
    let mut idx = Vec::new();
    for y in 0..n as u32 {
        for x in 0..n as u32 {
            let i = y * (n as u32 + 1) + x;
            idx.push([i, i + n as u32 + 2, i + 1]);
            idx.push([i, i + n as u32 + 1, i + n as u32 + 2]);
        }
    }
    for (name, t) in [
        ("mesh_spherical_triangle", MeshTechnique::SphericalTriangle),
        ("mesh_area", MeshTechnique::Area),
    ] {
        let mesh = MeshLight::new(&pts, &idx, None, false, t).unwrap();
        let us = uniforms();
        let mut g = c.benchmark_group(name);
        let mut i = 0usize;
        g.bench_function("sample", |b| {
            b.iter(|| {
                i = (i + 1) & (NU - 1);
                black_box(mesh.sample_with_index(black_box(&r), us[i]))
            })
        });
        g.finish();
    }

    let distant = DistantLight::new(0.53, &LightTransform::IDENTITY).unwrap();
    bench_light(c, "distant_cone", &Light::Distant(distant), r);

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
    let dome = DomeLight::new(&map, LightTransform::IDENTITY, DomeTechnique::Texture).unwrap();
    bench_light(c, "dome_2048x1024", &Light::Dome(dome), r);
    let dome_mis = DomeLight::new(
        &map,
        LightTransform::IDENTITY,
        DomeTechnique::MisCompensated,
    )
    .unwrap();
    bench_light(
        c,
        "dome_mis_compensated_2048x1024",
        &Light::Dome(dome_mis),
        r,
    );
    bench_light(
        c,
        "dome_uniform",
        &Light::Dome(DomeLight::uniform(LightTransform::IDENTITY)),
        r,
    );

    // Light selection over 4096 small lights scattered in a box.
    let mut rng = SplitMix64::new(7);
    let bounds: Vec<Option<LightBounds>> = (0..4096)
        .map(|_| {
            let c = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 10.0;
            let cone = EmissionCone::new(DVec3::NEG_Z, 0.0, std::f64::consts::FRAC_PI_2).unwrap();
            Some(LightBounds::new(c - 0.05, c + 0.05, 0.5 + rng.next_f64(), cone, false).unwrap())
        })
        .collect();
    let power: Vec<f64> = bounds.iter().map(|b| b.unwrap().phi).collect();
    let selectors = [
        ("select_uniform", LightSelector::uniform(4096).unwrap()),
        ("select_power", LightSelector::power(&power).unwrap()),
        (
            "select_bvh",
            LightSelector::Bvh(LightBvh::new(&bounds).unwrap()),
        ),
    ];
    let rs = Reference::surface(DVec3::new(5.0, 5.0, -1.0), DVec3::Z);
    for (name, sel) in &selectors {
        let us = uniforms();
        let mut g = c.benchmark_group(*name);
        let mut i = 0usize;
        g.bench_function("sample", |b| {
            b.iter(|| {
                i = (i + 1) & (NU - 1);
                black_box(sel.sample(black_box(&rs), us[i][0]))
            })
        });
        g.finish();
    }
}

criterion_group! {
    name = sample;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_millis(800));
    targets = benches
}
criterion_main!(sample);
