//! Every UsdPreviewSurface input of `preview_surface.usda`: values (through interface
//! inputs), textures with their channel, a `UsdTransform2d`, a normal map, opacity and
//! cut-outs, and invalid values replaced by the defaults with warnings. The expected values are
//! what usd-core reports for the file (`UsdShade.Input.GetValueProducingAttributes`).

use glam::{DVec2, DVec3, DVec4};
use lux_usd::{Input, Material, Scene, SourceColorSpace, Transform2d, Wrap, load_stage};
use std::path::PathBuf;

fn scene() -> Scene {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/preview_surface.usda");
    load_stage(p, 1.0).unwrap()
}

fn material<'a>(s: &'a Scene, mesh: &str) -> &'a Material {
    let m = s.meshes.iter().find(|m| m.path == mesh).unwrap();
    &s.materials[m.material.unwrap()]
}

fn f(x: f32) -> f64 {
    x.into()
}

#[test]
fn values_through_interface_inputs() {
    let s = scene();
    let m = material(&s, "/World/Chrome");
    assert!(m.preview);
    assert_eq!(m.diffuse, Input::Value(DVec3::new(f(0.9), f(0.8), f(0.7))));
    assert_eq!(m.metallic, Input::Value(1.0));
    assert_eq!(
        m.roughness,
        Input::Value(0.125),
        "through the Material's inputs:rough"
    );
    assert_eq!(m.ior, Input::Value(2.5));
    assert!(!m.use_specular_workflow);
    // Unauthored inputs keep the schema defaults.
    assert_eq!(m.specular, Input::Value(DVec3::ZERO));
    assert_eq!(m.clearcoat, Input::Value(0.0));
    assert_eq!(m.clearcoat_roughness, Input::Value(0.01));
    assert_eq!(m.opacity, Input::Value(1.0));
    assert_eq!(m.opacity_threshold, 0.0);
    assert!(m.normal.is_none() && !m.uses_opacity && m.emissive_texture.is_none());
    assert_eq!(m.other_inputs, ["inputs:occlusion"]);
    assert_eq!(m.st_primvar(), None);
}

#[test]
fn textures_channels_transform_and_normal_map() {
    let s = scene();
    let m = material(&s, "/World/Leaf");
    assert!(m.use_specular_workflow);
    assert_eq!(m.specular, Input::Value(DVec3::new(0.25, 0.5, 0.75)));
    let Input::Texture(albedo) = &m.diffuse else {
        panic!("{:?}", m.diffuse)
    };
    assert_eq!(albedo.shader, "/World/Looks/Leaf/Albedo");
    assert_eq!(albedo.output, "rgb");
    assert_eq!(albedo.st_primvar, "uv", "read through the UsdTransform2d");
    assert_eq!(albedo.wrap_s, Wrap::Mirror);
    let t = albedo.transform.expect("UsdTransform2d");
    assert_eq!(
        t,
        Transform2d {
            rotation: 90.0,
            scale: DVec2::new(2.0, 4.0),
            translation: DVec2::new(0.5, -1.0),
        }
    );
    // R(90°)·((1, 1)∘(2, 4)) + (0.5, −1) = (−4, 2) + (0.5, −1).
    let st = t.apply(DVec2::ONE);
    assert!((st - DVec2::new(-3.5, 1.0)).length() < 1e-12, "{st}");
    assert!(albedo.file.as_ref().unwrap().resolved.is_some());
    // The same texture's alpha is the opacity, a cut-out at 0.5.
    let Input::Texture(alpha) = &m.opacity else {
        panic!("{:?}", m.opacity)
    };
    assert_eq!(
        (alpha.shader.as_str(), alpha.output.as_str()),
        (albedo.shader.as_str(), "a")
    );
    assert_eq!(m.opacity_threshold, 0.5);
    assert!(m.uses_opacity);
    let Input::Texture(rough) = &m.roughness else {
        panic!("{:?}", m.roughness)
    };
    assert_eq!(rough.output, "g");
    assert_eq!(rough.source_color_space, SourceColorSpace::Raw);
    assert!(rough.transform.is_none());
    let n = m.normal.as_deref().expect("normal map");
    assert_eq!(n.shader, "/World/Looks/Leaf/Normal");
    assert_eq!(
        (n.scale, n.bias),
        (
            DVec4::new(2.0, 2.0, 2.0, 1.0),
            DVec4::new(-1.0, -1.0, -1.0, 0.0)
        )
    );
    // A texture-driven emission: no constant emission.
    let e = m.emissive_texture.as_deref().expect("emissive texture");
    assert_eq!(
        (e.shader.as_str(), e.output.as_str()),
        (albedo.shader.as_str(), "rgb")
    );
    assert_eq!(m.emissive, DVec3::ZERO);
    assert_eq!(m.textures().len(), 5);
    assert_eq!(m.st_primvar(), Some("uv"));
    // The mesh read the primvar the material asks for.
    let leaf = s.meshes.iter().find(|m| m.path == "/World/Leaf").unwrap();
    assert!(leaf.uvs.is_some());
}

#[test]
fn invalid_values_are_defaults_with_warnings() {
    let s = scene();
    let m = material(&s, "/World/Coat");
    assert_eq!(m.clearcoat, Input::Value(0.75));
    assert_eq!(m.clearcoat_roughness, Input::Value(f(0.2)));
    assert_eq!(m.opacity, Input::Value(0.25));
    assert!(m.uses_opacity);
    // metallic = 7 is outside [0, 1]: the default 0, and a warning naming the material.
    assert_eq!(m.metallic, Input::Value(0.0));
    let w: Vec<_> = s
        .warnings
        .iter()
        .filter(|w| w.prim == "/World/Looks/Coat")
        .collect();
    assert_eq!(w.len(), 1, "{:?}", s.warnings);
    assert!(
        w[0].message.contains("inputs:metallic = 7.0"),
        "{}",
        w[0].message
    );
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
}
