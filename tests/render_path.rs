//! The `path` integrator: one lit vertex is the direct integrator bit for bit; a white furnace
//! (albedo-1 surfaces under a uniform dome) converges to the dome's radiance even where the
//! geometry is concave, where direct lighting alone falls well short.

mod common;

use common::{close, options, probe_camera};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::render::Renderer;
use lux::render::settings::IntegratorKind;
use lux::usd::{Light, Mesh, Scene, load_stage};
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
    Renderer::new(scene, o).unwrap().pixel_value(0, 0).y
}

#[test]
fn white_furnace_converges_to_the_dome() {
    // The open floor sees the whole dome: its radiance is the dome's (ρ = 1).
    let dome = read(&furnace(false, 0.0, 0.0), IntegratorKind::Direct, 1, 256);
    assert!(dome > 0.0);
    // Near a corner inside the box the floor sees a fraction of the sky directly and the rest
    // through the white walls.
    let corner = furnace(true, 0.8, 0.8);
    let direct = read(&corner, IntegratorKind::Direct, 1, 1024);
    assert!(
        direct < 0.8 * dome,
        "direct lighting alone: {direct} of {dome}"
    );
    let path = read(&corner, IntegratorKind::Path, 32, 4096);
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
fn one_vertex_is_the_direct_integrator_bit_for_bit() {
    let data =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("crates/lux-render/tests/data/luxtest/usd");
    for (name, frame) in [("sphere", 1.0), ("rect", 25.0), ("dome", 1.0)] {
        let scene = load_stage(data.join(format!("{name}.usda")), frame).unwrap();
        let render = |kind| {
            let mut o = options(Profile::Spec, 4, [48, 48]);
            o.integrator = kind;
            o.max_depth = 1;
            Renderer::new(&scene, o).unwrap().render(&|_| {}).0.pixels
        };
        assert_eq!(
            render(IntegratorKind::Direct),
            render(IntegratorKind::Path),
            "{name} {frame}"
        );
    }
}
