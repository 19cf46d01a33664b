//! Scenes built in code for the renderer tests: a white Lambertian floor (albedo 1, front side
//! +Y) seen by a tiny orthographic camera looking straight down at one floor point, so that a
//! 1 × 1 render reads the reflected radiance `E/π` at that point.

#![allow(dead_code)]

pub mod blocks;
pub mod cli;

use glam::{DMat4, DVec3};
use lux::math::Profile;
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::render::{RenderOptions, Renderer};
use lux::usd::{Camera, Light, Mesh, Projection, Scene};

/// A 200 × 200 single-sided floor at y = 0, front side up.
pub fn floor() -> Mesh {
    Mesh::new(
        "/Floor",
        vec![
            DVec3::new(-100.0, 0.0, -100.0),
            DVec3::new(-100.0, 0.0, 100.0),
            DVec3::new(100.0, 0.0, 100.0),
            DVec3::new(100.0, 0.0, -100.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// An orthographic camera 10 units above `(x, 0, z)` looking down, aperture 10⁻⁴ units.
pub fn probe_camera(x: f64, z: f64) -> Camera {
    let mut c = Camera::with_defaults(
        "/Probe",
        DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, x, 10.0, z, 1.0,
        ]),
    );
    c.projection = Projection::Orthographic;
    c.horizontal_aperture = 1e-3;
    c.vertical_aperture = 1e-3;
    c.clipping_range = glam::DVec2::new(0.0, 1e6);
    c
}

/// The floor, the probe camera at `(x, z)` and the given lights.
pub fn probe_scene(lights: Vec<Light>, x: f64, z: f64) -> Scene {
    let mut s = Scene::empty("code.usda");
    s.meshes.push(floor());
    s.cameras.push(probe_camera(x, z));
    s.lights = lights;
    s
}

/// Render options of `profile` (from the command line), `spp` samples, a `w × h` image.
pub fn options(profile: Profile, spp: u32, resolution: [u32; 2]) -> RenderOptions {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile,
        source: ProfileSource::CommandLine,
    });
    o.spp = spp;
    o.resolution = Some(resolution);
    o
}

/// The red channel of the probed pixel (spec profile, 1 × 1 image).
pub fn probe(scene: &Scene, spp: u32) -> f64 {
    Renderer::new(scene, options(Profile::Spec, spp, [1, 1]))
        .unwrap()
        .pixel_value(0, 0)
        .x
}

/// `|got − want| ≤ rel·|want|`, with a message naming the case.
pub fn close(got: f64, want: f64, rel: f64, what: &str) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: got {got}, want {want} (rel error {:.2e} > {rel:.0e})",
        (got - want).abs() / want.abs()
    );
}
