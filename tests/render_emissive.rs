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
    let pi = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
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

/// [`scene`]'s quad with `MeshLightAPI` (intensity 3, white) in `mode`, and a UsdPreviewSurface
/// emitting (2, 1, 0.5) when `material`.
fn mesh_light(mode: lux::usd::MaterialSyncMode, material: bool) -> (Scene, f64) {
    let (mut s, corners) = scene(DVec3::new(2.0, 1.0, 0.5));
    s.materials[0].preview = true;
    let q = s.meshes.len() - 1;
    if !material {
        s.meshes[q].material = None;
    }
    let tris: Vec<[DVec3; 3]> = s.meshes[q]
        .triangles
        .iter()
        .map(|t| t.map(|i| s.meshes[q].positions[i as usize]))
        .collect();
    let mut l = lux::usd::Light::with_defaults(
        "/Glow",
        lux::math::LightShape::Mesh { triangles: tris },
        glam::DMat4::IDENTITY,
    );
    l.params.intensity = 3.0;
    l.material_sync_mode = mode;
    s.meshes[q].light = Some(s.lights.len());
    s.lights.push(l);
    let pi = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
    (s, pi / PI)
}

#[test]
fn material_sync_mode_of_a_mesh_light() {
    use lux::usd::MaterialSyncMode as M;
    let floor = |s: &Scene| {
        let mut o = options(Profile::Spec, 4096, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        let r = Renderer::new(s, o).unwrap();
        assert!(
            r.warnings().next().is_none(),
            "{:?}",
            r.warnings().collect::<Vec<_>>()
        );
        r.pixel_value(0, 0)
    };
    // What the camera sees of the quad: its glow, plus the direct light on it (none: the only
    // light is the quad itself). Direct lighting, because a UsdPreviewSurface reflects at
    // grazing angles (Schlick's F90 = 1, MaterialX's graph): path tracing adds the lit floor
    // reflected at grazing, a real ~3e-8 of the glow, which is not what this test is about.
    let seen = |mut s: Scene| {
        s.cameras[0] = common::probe_camera(0.7, 0.1);
        let mut o = options(Profile::Spec, 16, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        Renderer::new(&s, o).unwrap().pixel_value(0, 0)
    };
    // (the floor's light, per unit of the quad's radiance; what the camera sees on the quad)
    for (mode, material, light, glow) in [
        // The material's glow tints the light: 3·(2, 1, 0.5); the camera sees the glow.
        (
            M::MaterialGlowTintsLight,
            true,
            DVec3::new(6.0, 3.0, 1.5),
            DVec3::new(2.0, 1.0, 0.5),
        ),
        // Independent: the light as authored, the camera still sees the material's glow.
        (
            M::Independent,
            true,
            DVec3::splat(3.0),
            DVec3::new(2.0, 1.0, 0.5),
        ),
        // No material response: the light's radiance is what everything sees.
        (
            M::NoMaterialResponse,
            true,
            DVec3::splat(3.0),
            DVec3::splat(3.0),
        ),
        // No bound material: a light shaped by geometry, whatever the mode.
        (
            M::MaterialGlowTintsLight,
            false,
            DVec3::splat(3.0),
            DVec3::splat(3.0),
        ),
    ] {
        let what = format!("{mode:?}, material {material}");
        let (s, factor) = mesh_light(mode, material);
        let v = floor(&s);
        for k in 0..3 {
            close(v[k], light[k] * factor, 1e-3, &format!("floor, {what}"));
        }
        let g = seen(s);
        for k in 0..3 {
            close(g[k], glow[k], 1e-12, &format!("camera, {what}"));
        }
    }
}

#[test]
fn textured_emission_is_found_by_bsdf_rays() {
    // The quad's emissiveColor from a UsdUVTexture (a white PNG scaled by (2, 1, 0.5)): no light
    // samples it, BSDF rays from the floor find it, and the floor converges to the same closed
    // form as the constant emission. Cosine-sampled rays hit the quad with probability
    // p = Π/π, so the relative standard error of N samples is √((1 − p)/(pN)): the bound is
    // 4 of them.
    let (mut s, corners) = scene(DVec3::ZERO);
    s.materials[0].preview = true;
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/textures/white.png");
    s.materials[0].emissive_texture = Some(Box::new(lux::usd::TextureInput {
        shader: "/Looks/Glow/Tex".to_owned(),
        file: Some(lux::usd::AssetRef {
            authored: "white.png".to_owned(),
            resolved: Some(file),
        }),
        st_primvar: "st".to_owned(),
        st_fallback: glam::DVec2::ZERO,
        transform: None,
        scale: glam::DVec4::new(2.0, 1.0, 0.5, 1.0),
        bias: glam::DVec4::ZERO,
        fallback: glam::DVec4::new(0.0, 0.0, 0.0, 1.0),
        fallback_authored: false,
        wrap_s: lux::usd::Wrap::Repeat,
        wrap_t: lux::usd::Wrap::Repeat,
        source_color_space: lux::usd::SourceColorSpace::Auto,
        output: "rgb".to_owned(),
    }));
    let pi = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
    let spp = 1 << 16;
    let mut o = options(Profile::Spec, spp, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    let r = Renderer::new(&s, o).unwrap();
    assert!(
        r.lights().lights.is_empty(),
        "a textured emission is not a light"
    );
    let v = r.pixel_value(0, 0);
    let p = pi / PI;
    let rel = 4.0 * ((1.0 - p) / (p * spp as f64)).sqrt();
    for (c, l) in [(v.x, 2.0), (v.y, 1.0), (v.z, 0.5)] {
        close(c, l * pi / PI, rel, "floor under the textured glow");
    }
    // The camera sees the texture's radiance on the quad.
    s.cameras[0] = common::probe_camera(0.7, 0.1);
    let g = Renderer::new(&s, options(Profile::Spec, 16, [1, 1]))
        .unwrap()
        .pixel_value(0, 0);
    close(g.x, 2.0, 1e-6, "glow, red");
    close(g.z, 0.5, 1e-6, "glow, blue");
}

#[test]
fn a_single_sided_emitter_lights_only_its_front_side() {
    // The quad of `scene` single-sided: wound as it is, its front faces down (towards the
    // floor), which gets the closed form; wound the other way its front faces up, and the
    // floor below sees its back, which emits nothing — to light samples (they check the side)
    // nor to BSDF rays that hit it.
    let (mut s, corners) = scene(DVec3::new(2.0, 1.0, 0.5));
    let q = s.meshes.len() - 1;
    s.meshes[q].double_sided = false;
    let pi = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
    let floor = |s: &Scene| {
        let mut o = options(Profile::Spec, 4096, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        Renderer::new(s, o).unwrap().pixel_value(0, 0)
    };
    let v = floor(&s);
    for (c, l) in [(v.x, 2.0), (v.y, 1.0), (v.z, 0.5)] {
        close(
            c,
            l * pi / PI,
            1e-3,
            "floor under the front of a single-sided emitter",
        );
    }
    s.meshes[q].triangles = s.meshes[q]
        .triangles
        .iter()
        .map(|t| [t[0], t[2], t[1]])
        .collect();
    assert_eq!(floor(&s).truncate(), DVec3::ZERO, "the back emits nothing");
}

#[test]
fn an_emitter_far_from_the_origin_lights_as_near_it() {
    // The whole probe scene moved 20, 100 and 1000 units along x: the floor under the quad
    // still reads the closed form. (Shadow rays once aimed along the light sample's direction
    // from the shading point, not from their offset origin; the offset grows with the
    // coordinates, and the quad shadowed its own samples: 68 % of the light at 20 units,
    // 0.6 % at 100.)
    for shift in [20.0, 100.0, 1000.0] {
        let off = DVec3::new(shift, 0.0, 0.0);
        let (mut s, corners) = scene(DVec3::new(2.0, 1.0, 0.5));
        for m in &mut s.meshes {
            for p in &mut m.positions {
                *p += off;
            }
        }
        s.cameras[0] = common::probe_camera(shift, 0.0);
        let corners: Vec<DVec3> = corners.iter().map(|c| *c + off).collect();
        let pi = lux::irradiance::projected::polygon(off, DVec3::Y, &corners);
        let mut o = options(Profile::Spec, 4096, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        let v = Renderer::new(&s, o).unwrap().pixel_value(0, 0);
        println!("x = {shift}: {} of the closed form", v.x / (2.0 * pi / PI));
        for (c, l) in [(v.x, 2.0), (v.y, 1.0), (v.z, 0.5)] {
            close(
                c,
                l * pi / PI,
                1e-3,
                &format!("floor under the quad at x = {shift}"),
            );
        }
    }
}
