//! The `path` integrator: one lit vertex is the direct integrator bit for bit; a white furnace
//! (albedo-1 surfaces under a uniform dome) converges to the dome's radiance even where the
//! geometry is concave, where direct lighting alone falls well short.

mod common;

use common::{close, options, probe_camera};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::geometry::Geometry;
use lux::render::material::Materials;
use lux::render::render::Renderer;
use lux::render::settings::{AdaptiveSampling, IntegratorKind};
use lux::usd::{Input, Light, Material, Mesh, Scene, load_stage};
use std::path::PathBuf;

fn quad(path: &str, p: [DVec3; 4]) -> Mesh {
    let mut m = Mesh::new(path, p.to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
    m.double_sided = true;
    m
}

/// A white floor and, with `walls`, an open 2 × 2 × 2 box on it (four double-sided walls, no
/// lid), under a uniform dome; the probe camera looks down at (x, z).
fn furnace(walls: bool, x: f64, z: f64) -> Scene {
    let mut s = Scene::empty("furnace.usda");
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    s.meshes.push(quad(
        "/Floor",
        [
            v(-50.0, 0.0, -50.0),
            v(-50.0, 0.0, 50.0),
            v(50.0, 0.0, 50.0),
            v(50.0, 0.0, -50.0),
        ],
    ));
    if walls {
        s.meshes.push(quad(
            "/W0",
            [
                v(-1.0, 0.0, -1.0),
                v(1.0, 0.0, -1.0),
                v(1.0, 2.0, -1.0),
                v(-1.0, 2.0, -1.0),
            ],
        ));
        s.meshes.push(quad(
            "/W1",
            [
                v(-1.0, 0.0, 1.0),
                v(1.0, 0.0, 1.0),
                v(1.0, 2.0, 1.0),
                v(-1.0, 2.0, 1.0),
            ],
        ));
        s.meshes.push(quad(
            "/W2",
            [
                v(-1.0, 0.0, -1.0),
                v(-1.0, 0.0, 1.0),
                v(-1.0, 2.0, 1.0),
                v(-1.0, 2.0, -1.0),
            ],
        ));
        s.meshes.push(quad(
            "/W3",
            [
                v(1.0, 0.0, -1.0),
                v(1.0, 0.0, 1.0),
                v(1.0, 2.0, 1.0),
                v(1.0, 2.0, -1.0),
            ],
        ));
    }
    s.cameras.push(probe_camera(x, z));
    s.lights.push(Light::with_defaults(
        "/Dome",
        LightShape::Dome,
        DMat4::IDENTITY,
    ));
    s
}

fn read(scene: &Scene, integrator: IntegratorKind, depth: u32, spp: u32) -> f64 {
    let mut o = options(Profile::Spec, spp, [1, 1]);
    o.integrator = integrator;
    o.max_depth = depth;
    // One light sample per vertex for both integrators (the direct one takes 4 by default).
    o.light_samples = Some(1);
    Renderer::new(scene, o).unwrap().pixel_value(0, 0).y
}

#[test]
fn white_furnace_converges_to_the_dome() {
    // The dome's radiance: intensity 1, white (UsdLux defaults). The open floor sees the
    // whole dome, so it reflects that radiance (ρ = 1).
    let dome = 1.0;
    let floor = read(&furnace(false, 0.0, 0.0), IntegratorKind::Direct, 1, 1024);
    close(floor, dome, 5e-3, "direct light of the open floor");
    // Near a corner inside the box the floor sees a fraction of the sky directly and the rest
    // through the white walls.
    let corner = furnace(true, 0.8, 0.8);
    let direct = read(&corner, IntegratorKind::Direct, 1, 1024);
    assert!(
        direct < 0.8 * dome,
        "direct lighting alone: {direct} of {dome}"
    );
    // (a path's vertices past the camera's draw independent numbers: the estimate's
    // standard error at 32768 samples is about 1.1e-3, a quarter of the tolerance)
    let path = read(&corner, IntegratorKind::Path, 32, 32768);
    close(
        path,
        dome,
        5e-3,
        "path tracing at depth 32 in the white furnace",
    );
    // Depth 2 adds one bounce: between the two.
    let two = read(&corner, IntegratorKind::Path, 2, 1024);
    assert!(direct < two && two < path, "{direct} < {two} < {path}");
}

#[test]
fn metal_furnace_never_exceeds_the_dome() {
    // Every surface a UsdPreviewSurface metal of F0 = 1 (metallic 1, diffuseColor 1): Schlick's
    // F is 1 and single-scattering GGX loses the light of its inter-reflections, so at every
    // roughness the corner's radiance stays at or below the dome's (within 3σ of its noise),
    // and a smooth metal reflects nearly all of it (at roughness 1, single-scattering GGX
    // keeps only 0.31 of it even on the open floor).
    // The default DomeLight: L = 1.
    let dome = 1.0;
    for roughness in [0.05, 0.3, 0.7, 1.0] {
        let mut s = furnace(true, 0.8, 0.8);
        s.materials.push(Material {
            preview: true,
            diffuse: Input::Value(DVec3::ONE),
            metallic: Input::Value(1.0),
            roughness: Input::Value(roughness),
            ..Material::new("/Looks/Metal")
        });
        for m in &mut s.meshes {
            m.material = Some(0);
        }
        let (spp, runs) = (256, 8);
        let v: Vec<f64> = (0..runs)
            .map(|seed| {
                let mut o = options(Profile::Spec, spp, [1, 1]);
                o.max_depth = 32;
                o.seed = seed;
                Renderer::new(&s, o).unwrap().pixel_value(0, 0).y
            })
            .collect();
        let mean = v.iter().sum::<f64>() / runs as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (runs - 1) as f64;
        let sigma = (var / runs as f64).sqrt();
        assert!(
            mean <= dome + 3.0 * sigma,
            "roughness {roughness}: {mean} ± {sigma} exceeds the dome {dome}"
        );
        if roughness == 0.05 {
            assert!(mean > 0.97 * dome, "a smooth metal: {mean} of {dome}");
        }
    }
}

#[test]
fn back_faces_of_single_sided_walls_reflect_nothing() {
    // The furnace corner with single-sided walls whose fronts face out of the box: from the
    // floor inside, a path meets only their backs, which block the dome and reflect nothing
    // (as camera rays do not see them; Mitsuba's one-sided BSDFs are black from behind). Every
    // path then ends at its first bounce: path tracing gives the direct estimate, bit for bit.
    let mut s = furnace(true, 0.8, 0.8);
    for m in s.meshes.iter_mut().skip(1) {
        m.double_sided = false;
        let c = m.positions.iter().sum::<DVec3>() / m.positions.len() as f64;
        let inward = DVec3::new(0.0, 1.0, 0.0) - c;
        for t in &mut m.triangles {
            let [a, b, d] = t.map(|i| m.positions[i as usize]);
            if (b - a).cross(d - a).dot(inward) > 0.0 {
                t.swap(1, 2);
            }
        }
    }
    let direct = read(&s, IntegratorKind::Direct, 1, 256);
    let path = read(&s, IntegratorKind::Path, 32, 256);
    assert!(direct > 0.1, "{direct}");
    assert_eq!(path, direct);
    // With the fronts facing in, the walls reflect: more light than direct.
    for m in s.meshes.iter_mut().skip(1) {
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
    }
    assert!(read(&s, IntegratorKind::Path, 32, 256) > 1.2 * direct);
}

#[test]
fn glossy_floor_under_the_dome_reflects_its_albedo() {
    // An open UsdPreviewSurface floor (gold-ish metal, and a rough dielectric with clearcoat)
    // under a uniform dome of radiance L seen from straight above: its radiance is
    // L·∫ f(wo, wi) cos θi dωi, the BSDF's albedo at normal view, here by quadrature of the
    // renderer's own BSDF at the floor (the material's MaterialX graph). Light and BSDF samples
    // combine with MIS; the render must find the same integral. The default DomeLight
    // (intensity 1, white, no texture) has L = 1.
    let gold = Material {
        preview: true,
        diffuse: Input::Value(DVec3::new(1.0, 0.8, 0.4)),
        metallic: Input::Value(1.0),
        roughness: Input::Value(0.3),
        ..Material::new("/Looks/Floor")
    };
    let coated = Material {
        preview: true,
        diffuse: Input::Value(DVec3::new(0.2, 0.5, 0.8)),
        roughness: Input::Value(0.7),
        clearcoat: Input::Value(1.0),
        clearcoat_roughness: Input::Value(0.1),
        ..Material::new("/Looks/Floor")
    };
    for material in [gold, coated] {
        let mut s = furnace(false, 0.0, 0.0);
        s.materials.push(material.clone());
        s.meshes[0].material = Some(0);
        let geometry = Geometry::new(&s);
        let down = DVec3::NEG_Y;
        let hit = geometry
            .intersect(&s, DVec3::new(0.0, 1.0, 0.0), down, 0.0, 10.0)
            .unwrap();
        let b = Materials::new(&s).unwrap().at(&s, &hit, down).bsdf;
        // Midpoint rule in (cos θ, φ), fine near the normal where the smooth lobes peak.
        let (nt, np) = (4000, 64);
        let mut albedo = DVec3::ZERO;
        for i in 0..nt {
            let c = 1.0 - ((i as f64 + 0.5) / nt as f64).powi(2);
            let dc = 2.0 * (1.0 - c).sqrt() / nt as f64;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let s = (1.0 - c * c).sqrt();
                let wi = DVec3::new(s * phi.cos(), c, s * phi.sin());
                albedo += b.f(wi) * c * dc * std::f64::consts::TAU / np as f64;
            }
        }
        // Eight independent renders give the estimate's own standard error; the mean must lie
        // within 4 of them (and within 0.5 %) of the quadrature.
        let runs: Vec<DVec3> = (0..8)
            .map(|seed| {
                let mut o = options(Profile::Spec, 4096, [1, 1]);
                o.integrator = IntegratorKind::Direct;
                o.seed = seed;
                Renderer::new(&s, o).unwrap().pixel_value(0, 0).truncate()
            })
            .collect();
        let mean = runs.iter().sum::<DVec3>() / 8.0;
        let var = runs
            .iter()
            .map(|v| (*v - mean) * (*v - mean))
            .sum::<DVec3>()
            / 7.0;
        let sigma = (var / 8.0).powf(0.5);
        let want = albedo;
        for k in 0..3 {
            assert!(
                (mean[k] - want[k]).abs() <= (4.0 * sigma[k]).max(1e-4 * want[k])
                    && (mean[k] - want[k]).abs() <= 5e-3 * want[k],
                "channel {k}: {} ± {} vs {} ({material:?})",
                mean[k],
                sigma[k],
                want[k]
            );
        }
    }
}

#[test]
fn one_vertex_is_the_direct_integrator_bit_for_bit() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/luxtest/usd");
    for (name, frame) in [("sphere", 1.0), ("rect", 25.0), ("dome", 1.0)] {
        let scene = load_stage(data.join(format!("{name}.usda")), frame).unwrap();
        let render = |kind| {
            let mut o = options(Profile::Spec, 4, [48, 48]);
            o.integrator = kind;
            o.max_depth = 1;
            o.light_samples = Some(1);
            // The same samples for both (adaptive sampling is on by default for direct only).
            o.adaptive = Some(AdaptiveSampling::OFF);
            Renderer::new(&scene, o).unwrap().render(&|_| {}).0.pixels
        };
        assert_eq!(
            render(IntegratorKind::Direct),
            render(IntegratorKind::Path),
            "{name} {frame}"
        );
    }
}
