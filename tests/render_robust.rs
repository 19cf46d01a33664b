//! Renderer invariants: no NaN/inf pixel in any luxtest frame (both profiles), identical bits
//! for 1 and 2 threads, the RectLight texture orientation of each profile, and the light
//! selection strategies agreeing with sampling every light.

mod common;

use common::{options, probe_scene};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::image_io::{ImageRgba, write_png};
use lux::render::light::{LightOptions, LightSelection, LightSet};
use lux::render::render::Renderer;
use lux::usd::{AssetRef, Camera, Light, Projection, Scene, load_stage};
use std::path::PathBuf;

fn luxtest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/luxtest/usd")
}

#[test]
fn every_luxtest_frame_renders_finite_pixels_in_both_profiles() {
    let scenes = [
        ("cylinder", 60),
        ("disk", 60),
        ("distant", 35),
        ("dome", 1),
        ("iesDown", 98),
        ("iesLibPreview", 31),
        ("iesTest", 31),
        ("iesUp", 98),
        ("ies_scale", 20),
        ("rect", 60),
        ("sphere", 60),
        ("visibleRect", 1),
    ];
    let mut frames = 0;
    for (name, last) in scenes {
        for frame in 1..=last {
            let scene = load_stage(luxtest().join(format!("{name}.usda")), frame as f64)
                .unwrap_or_else(|e| panic!("{name} {frame}: {e}"));
            for profile in Profile::ALL {
                let r = Renderer::new(&scene, options(profile, 2, [24, 24]))
                    .unwrap_or_else(|e| panic!("{name} {frame} {profile}: {e}"));
                let (img, stats) = r.render(&|_| {});
                assert_eq!(stats.pixels, 24 * 24);
                assert_eq!(
                    stats.non_finite_samples, 0,
                    "{name} frame {frame} {profile}: non-finite radiance samples"
                );
                for (i, p) in img.pixels.iter().enumerate() {
                    assert!(
                        p.iter().all(|c| c.is_finite() && *c >= 0.0),
                        "{name} frame {frame} {profile}: pixel {i} = {p:?}"
                    );
                }
            }
            frames += 1;
        }
    }
    assert_eq!(frames, 60 * 4 + 35 + 98 * 2 + 31 * 2 + 20 + 2);
}

fn render_with_threads(scene: &Scene, threads: usize) -> ImageRgba {
    let r = Renderer::new(scene, options(Profile::HdEmbree, 4, [96, 96])).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| r.render(&|_| {})).0
}

#[test]
fn identical_bits_for_one_and_two_threads() {
    for (name, frame) in [("rect", 27.0), ("sphere", 1.0), ("iesDown", 40.0)] {
        let scene = load_stage(luxtest().join(format!("{name}.usda")), frame).unwrap();
        let a = render_with_threads(&scene, 1);
        let b = render_with_threads(&scene, 2);
        let bits = |img: &ImageRgba| -> Vec<u32> {
            img.pixels.iter().flatten().map(|c| c.to_bits()).collect()
        };
        assert_eq!(bits(&a), bits(&b), "{name} {frame}");
        assert!(
            a.pixels.iter().any(|p| p[0] > 0.0),
            "{name}: a black image proves nothing"
        );
    }
}

/// A 16 × 16 texture in quadrants: top-left red, top-right green, bottom-left dark red,
/// bottom-right dark green (image rows from the top).
fn quadrant_texture() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lux-robust-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("quadrants.png");
    let pixels = (0..256)
        .map(|i| {
            let (x, y) = (i % 16, i / 16);
            let k = if y < 8 { 1.0 } else { 0.2 };
            if x < 8 {
                [k, 0.0, 0.0, 1.0]
            } else {
                [0.0, k, 0.0, 1.0]
            }
        })
        .collect();
    let img = ImageRgba {
        width: 16,
        height: 16,
        pixels,
    };
    write_png(&p, &img, 0.0).unwrap();
    p
}

/// The lit path (`true`) or the camera path.
fn seen(lit: bool) -> lux::render::light::Seen {
    if lit {
        lux::render::light::Seen::Lit
    } else {
        lux::render::light::Seen::Camera
    }
}

fn textured_rect(profile: Profile) -> lux::render::light::Light {
    let tex = quadrant_texture();
    let mut l = Light::with_defaults(
        "/Rect",
        LightShape::Rect {
            width: 2.0,
            height: 2.0,
        },
        DMat4::IDENTITY,
    );
    l.texture = Some(AssetRef {
        authored: "quadrants.png".into(),
        resolved: Some(tex),
    });
    let mut s = Scene::empty("code.usda");
    s.lights.push(l);
    let set = LightSet::new(
        &s,
        LightOptions {
            cone_clipping: true,
            profile,
            selection: LightSelection::All,
            strict: false,
        },
    )
    .unwrap();
    set.lights.into_iter().next().unwrap()
}

#[test]
fn rect_texture_orientation_per_profile() {
    // Emission towards −Z (the emitting side). An observer on that side looking back along +Z
    // with +Y up has local −X on their right: in the schema orientation image u runs along −X
    // and the top row is at +Y, so local (+0.5, +0.5) — the observer's upper left — is red.
    let e = DVec3::NEG_Z;
    let upper_left = DVec3::new(0.5, 0.5, 0.0);
    let upper_right = DVec3::new(-0.5, 0.5, 0.0);
    let lower_left = DVec3::new(0.5, -0.5, 0.0);
    let spec = textured_rect(Profile::Spec);
    for lit in [false, true] {
        assert_eq!(spec.le(upper_left, e, seen(lit)), DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(
            spec.le(upper_right, e, seen(lit)),
            DVec3::new(0.0, 1.0, 0.0)
        );
        let dark = spec.le(lower_left, e, seen(lit));
        assert!((dark - DVec3::new(0.2, 0.0, 0.0)).length() < 2e-3, "{dark}");
    }
    // hdEmbree: the visible path as in the schema, the lit path mirrored in u.
    let hd = textured_rect(Profile::HdEmbree);
    assert_eq!(hd.le(upper_left, e, seen(false)), DVec3::new(1.0, 0.0, 0.0));
    assert_eq!(hd.le(upper_left, e, seen(true)), DVec3::new(0.0, 1.0, 0.0));
    assert_eq!(hd.le(upper_right, e, seen(true)), DVec3::new(1.0, 0.0, 0.0));
    // The back side emits nothing.
    assert_eq!(spec.le(upper_left, DVec3::Z, seen(true)), DVec3::ZERO);
}

#[test]
fn camera_sees_the_texture_upright_and_unmirrored() {
    // The rect at the origin emits towards −Z; a camera at z = −5 looks back at it along +Z.
    let tex = quadrant_texture();
    let mut l = Light::with_defaults(
        "/Rect",
        LightShape::Rect {
            width: 2.0,
            height: 2.0,
        },
        DMat4::IDENTITY,
    );
    l.visible_to_camera = true;
    l.texture = Some(AssetRef {
        authored: "quadrants.png".into(),
        resolved: Some(tex),
    });
    let mut s = Scene::empty("code.usda");
    s.lights.push(l);
    // Camera looking along +Z (local −Z → world +Z: a 180° turn about Y), orthographic 2 × 2.
    let mut c = Camera::with_defaults(
        "/Cam",
        DMat4::from_rotation_translation(
            glam::DQuat::from_rotation_y(std::f64::consts::PI),
            DVec3::new(0.0, 0.0, -5.0),
        ),
    );
    c.projection = Projection::Orthographic;
    c.horizontal_aperture = 19.0;
    c.vertical_aperture = 19.0;
    s.cameras.push(c);
    let r = Renderer::new(&s, options(Profile::Spec, 4, [8, 8])).unwrap();
    let (img, _) = r.render(&|_| {});
    let px = |x: usize, y: usize| img.pixels[y * 8 + x];
    assert_eq!(px(1, 1)[..3], [1.0, 0.0, 0.0], "upper left is red");
    assert_eq!(px(6, 1)[..3], [0.0, 1.0, 0.0], "upper right is green");
    assert!(
        (px(1, 6)[0] - 0.2).abs() < 2e-3 && px(1, 6)[1] == 0.0,
        "lower left is dark red"
    );
}

#[test]
fn light_selection_strategies_agree_with_sampling_every_light() {
    // 24 small sphere lights of varied power over a floor, probed at one point.
    let mut s = probe_scene(vec![], 0.3, 0.2);
    for i in 0..24 {
        let a = i as f64 * 2.399;
        let rad = 0.5 + 0.25 * i as f64;
        let mut l = Light::with_defaults(
            format!("/L{i}"),
            LightShape::Sphere { radius: 0.1 },
            DMat4::from_translation(DVec3::new(
                rad * a.cos(),
                1.0 + 0.1 * i as f64,
                rad * a.sin(),
            )),
        );
        l.params.intensity = 10.0 + 7.0 * (i % 5) as f64;
        s.lights.push(l);
    }
    let probe = |sel: LightSelection, spp: u32| probe_with(&s, sel, spp);
    let all = probe(LightSelection::All, 4096);
    // Closed form: each sphere fully above the horizon gives L·π·(r/d)²·cos β.
    let p = DVec3::new(0.3, 0.0, 0.2);
    let want: f64 = s
        .lights
        .iter()
        .map(|l| {
            let c = l.light_to_world.transform_point3(DVec3::ZERO) - p;
            let d = c.length();
            l.params.intensity * (0.1 / d).powi(2) * (c.y / d)
        })
        .sum();
    assert!(
        (all - want).abs() < 1e-3 * want,
        "all lights {all} vs {want}"
    );
    for sel in [LightSelection::Power, LightSelection::Bvh] {
        let got = probe(sel, 1 << 16);
        assert!((got - want).abs() < 0.02 * want, "{sel:?}: {got} vs {want}");
    }
}

#[test]
fn light_bvh_with_shaping_cones_agrees_with_sampling_every_light() {
    // 24 downward rect lights whose ShapingAPI cones just reach the probed floor point (the
    // point lies 3° inside each cone): the BVH's emission bounds come from lux-shaping's
    // emission half-angle, and a bound narrower than the cone would make the BVH skip lights
    // that light the point, so its estimate would fall below sampling every light.
    let (px, pz) = (0.3, 0.2);
    let mut s = probe_scene(vec![], px, pz);
    for i in 0..24 {
        let a = i as f64 * 2.399;
        let rho = 0.2 + 0.1 * i as f64;
        let pos = DVec3::new(px + rho * a.cos(), 1.0, pz + rho * a.sin());
        let mut l = Light::with_defaults(
            format!("/R{i}"),
            LightShape::Rect {
                width: 0.05,
                height: 0.05,
            },
            DMat4::from_translation(pos) * DMat4::from_rotation_x(-std::f64::consts::FRAC_PI_2),
        );
        l.params.intensity = 10.0 + 7.0 * (i % 5) as f64;
        l.shaping = Some(lux::usd::ShapingInputs {
            cone_angle_deg: rho.atan().to_degrees() + 3.0,
            cone_softness: 0.2 * (i % 3) as f64,
            ..Default::default()
        });
        s.lights.push(l);
    }
    let probe = |sel: LightSelection, spp: u32| probe_with(&s, sel, spp);
    let all = probe(LightSelection::All, 4096);
    assert!(all > 0.0);
    let got = probe(LightSelection::Bvh, 1 << 16);
    assert!(
        (got - all).abs() < 0.02 * all,
        "BVH {got} vs all lights {all}"
    );
}

/// The red channel of the probed pixel (spec profile, 1 × 1 image) with light selection `sel`.
fn probe_with(s: &Scene, sel: LightSelection, spp: u32) -> f64 {
    let mut o = options(Profile::Spec, spp, [1, 1]);
    o.selection = sel;
    Renderer::new(s, o).unwrap().pixel_value(0, 0).x
}
