//! Emissive geometry is light: a mesh whose UsdPreviewSurface has an `emissiveColor` lights the
//! scene as a `MeshLightAPI` mesh of that radiance does — sampled through the light interface,
//! found by BSDF rays, its glow seen by the camera.

mod common;

use common::{close, options, probe_scene};
use glam::DVec3;
use lux::math::Profile;
use lux::render::render::Renderer;
use lux::render::settings::IntegratorKind;
use lux::usd::{Input, Material, Mesh, Scene};
use std::f64::consts::PI;

/// The probe's floor beside a 1 × 0.6 double-sided quad at height 1.2–1.4, tilted, emitting
/// `emissive` (a black diffuse surface, so that nothing but its emission comes from it).
fn scene(emissive: DVec3) -> (Scene, Vec<DVec3>) {
    let corners = vec![
        DVec3::new(0.2, 1.2, -0.2),
        DVec3::new(1.2, 1.4, -0.2),
        DVec3::new(1.2, 1.4, 0.4),
        DVec3::new(0.2, 1.2, 0.4),
    ];
    let mut s = probe_scene(vec![], 0.0, 0.0);
    let mut quad = Mesh::new("/Glow", corners.clone(), vec![[0, 1, 2], [0, 2, 3]]);
    quad.double_sided = true;
    quad.material = Some(s.materials.len());
    s.materials.push(Material {
        diffuse: Input::Value(DVec3::ZERO),
        emissive,
        ..Material::new("/Looks/Glow")
    });
    s.meshes.push(quad);
    (s, corners)
}

#[test]
fn emissive_quad_lights_the_floor_as_its_closed_form_says() {
    let (s, corners) = scene(DVec3::new(2.0, 1.0, 0.5));
    let pi = lux::sample::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
    let mut o = options(Profile::Spec, 4096, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    let r = Renderer::new(&s, o).unwrap();
    let warnings: Vec<&String> = r.warnings().collect();
    assert!(warnings.is_empty(), "{warnings:?}");
    let v = r.pixel_value(0, 0);
    for (c, l) in [(v.x, 2.0), (v.y, 1.0), (v.z, 0.5)] {
        close(c, l * pi / PI, 1e-3, "floor under the emissive quad");
    }
    // Without emission the quad is black and the floor unlit.
    let (dark, _) = scene(DVec3::ZERO);
    let mut o = options(Profile::Spec, 64, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    assert_eq!(Renderer::new(&dark, o).unwrap().pixel_value(0, 0).x, 0.0);
}

#[test]
fn the_camera_sees_the_glow() {
    // The probe camera above x = 0.7 looks down at the quad: it sees its top side's
    // radiance, the emission (its surface is black).
    let (mut s, _) = scene(DVec3::new(2.0, 1.0, 0.5));
    s.cameras[0] = common::probe_camera(0.7, 0.1);
    let v = Renderer::new(&s, options(Profile::Spec, 16, [1, 1]))
        .unwrap()
        .pixel_value(0, 0);
    close(v.x, 2.0, 1e-12, "glow, red");
    close(v.z, 0.5, 1e-12, "glow, blue");
}
