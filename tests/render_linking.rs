//! Light and shadow linking (UsdLux `collection:lightLink` / `collection:shadowLink`) in
//! both integrators: an unlinked surface gets nothing from the light (by light sampling or by
//! a BSDF ray finding it), an occluder outside the shadowLink lets the light through, and a
//! scene without linking takes the old code paths.

mod common;

use common::{options, probe_camera};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::image_io::ImageRgba;
use lux::render::light::{LightLinks, LightSelection};
use lux::render::render::Renderer;
use lux::render::settings::IntegratorKind;
use lux::usd::{Input, Light, Material, Membership, Mesh, Rule, Scene};

/// A horizontal quad `[x0, x1] × [z0, z1]` at height `y`, front side up.
fn quad(path: &str, x: [f64; 2], z: [f64; 2], y: f64) -> Mesh {
    Mesh::new(
        path,
        vec![
            DVec3::new(x[0], y, z[0]),
            DVec3::new(x[0], y, z[1]),
            DVec3::new(x[1], y, z[1]),
            DVec3::new(x[1], y, z[0]),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// A rect light `w × w` at height `h` above the origin, emitting downwards.
fn rect_light(w: f64, h: f64) -> Light {
    let q = glam::DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::NEG_Y);
    Light::with_defaults(
        "/World/Key",
        LightShape::Rect {
            width: w,
            height: w,
        },
        DMat4::from_rotation_translation(q, DVec3::new(0.0, h, 0.0)),
    )
}

/// An orthographic camera looking down at the origin, `w × h` units (aperture in tenths).
fn top_camera(w: f64, h: f64) -> lux::usd::Camera {
    let mut c = probe_camera(0.0, 0.0);
    c.horizontal_aperture = 10.0 * w;
    c.vertical_aperture = 10.0 * h;
    c
}

fn rules(entries: &[(&str, Rule)]) -> Membership {
    Membership::Rules(entries.iter().map(|(p, r)| ((*p).to_owned(), *r)).collect())
}

fn render(s: &Scene, kind: IntegratorKind, selection: LightSelection, res: [u32; 2]) -> ImageRgba {
    let mut o = options(Profile::Spec, 16, res);
    o.integrator = kind;
    o.selection = selection;
    if kind == IntegratorKind::Path {
        // Fixed counts: by the path's linear noise measure a pixel's count reads the frame's
        // mean, which a link elsewhere in the frame changes (the pixels stay unbiased, not
        // the same bits).
        o.adaptive = Some(lux::render::settings::AdaptiveSampling::OFF);
    }
    let r = Renderer::new(s, o).unwrap();
    let w: Vec<&String> = r.warnings().collect();
    assert!(w.is_empty(), "{w:?}");
    r.render(&|_| {}).0
}

/// The pixels (r, g, b) whose centre lies in the world rectangle `x × z` of a `top_camera`
/// image covering `[-w/2, w/2] × [-h/2, h/2]` (image right = +x, image up = −z).
fn region(img: &ImageRgba, w: f64, h: f64, x: [f64; 2], z: [f64; 2]) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for row in 0..img.height {
        for col in 0..img.width {
            let px = -w / 2.0 + (col as f64 + 0.5) * w / img.width as f64;
            let pz = -h / 2.0 + (row as f64 + 0.5) * h / img.height as f64;
            if px > x[0] && px < x[1] && pz > z[0] && pz < z[1] {
                let p = img.pixels[row * img.width + col];
                out.push([p[0], p[1], p[2]]);
            }
        }
    }
    assert!(!out.is_empty());
    out
}

fn mean(px: &[[f32; 3]]) -> f64 {
    px.iter().map(|p| p[0] as f64).sum::<f64>() / px.len() as f64
}

/// Two quads side by side under a rect light: Q1 at x ∈ [−2, −0.5], Q2 at x ∈ [0.5, 2].
fn two_quads() -> Scene {
    let mut s = Scene::empty("code.usda");
    s.meshes
        .push(quad("/World/Q1", [-2.0, -0.5], [-1.0, 1.0], 0.0));
    s.meshes
        .push(quad("/World/Q2", [0.5, 2.0], [-1.0, 1.0], 0.0));
    s.cameras.push(top_camera(5.0, 2.5));
    s.lights.push(rect_light(3.0, 2.0));
    s
}

const INTEGRATORS: [IntegratorKind; 2] = [IntegratorKind::Direct, IntegratorKind::Path];

#[test]
fn light_link_excluding_a_quad_leaves_it_black_and_the_other_as_before() {
    let base = two_quads();
    let mut linked = two_quads();
    // includeRoot, excludes /World/Q1
    linked.lights[0].linking.light =
        rules(&[("/", Rule::ExpandPrims), ("/World/Q1", Rule::Exclude)]);
    let (q1, q2) = (([-1.9, -0.6], [-0.9, 0.9]), ([0.6, 1.9], [-0.9, 0.9]));
    // Power selection makes the direct estimate use BSDF sampling (MIS) too, whose hits of
    // the unlinked light must add nothing.
    for kind in INTEGRATORS {
        for selection in [LightSelection::All, LightSelection::Power] {
            let what = format!("{kind:?}, {selection:?}");
            let a = render(&base, kind, selection, [50, 25]);
            let b = render(&linked, kind, selection, [50, 25]);
            let lit = region(&a, 5.0, 2.5, q1.0, q1.1);
            eprintln!(
                "{what}: Q1 mean {:.5} unlinked, {:.5} excluded; Q2 mean {:.5}",
                mean(&lit),
                mean(&region(&b, 5.0, 2.5, q1.0, q1.1)),
                mean(&region(&b, 5.0, 2.5, q2.0, q2.1))
            );
            assert!(
                mean(&lit) > 0.1,
                "{what}: Q1 unlinked is lit, {}",
                mean(&lit)
            );
            assert!(
                region(&b, 5.0, 2.5, q1.0, q1.1)
                    .iter()
                    .all(|p| *p == [0.0; 3]),
                "{what}: Q1 excluded from lightLink must be black"
            );
            assert_eq!(
                region(&a, 5.0, 2.5, q2.0, q2.1),
                region(&b, 5.0, 2.5, q2.0, q2.1),
                "{what}: Q2 as without linking"
            );
        }
    }
    // The same exclusion through an explicitOnly include of Q2 alone.
    let mut only_q2 = two_quads();
    only_q2.lights[0].linking.light = rules(&[("/World/Q2", Rule::ExplicitOnly)]);
    let b = render(
        &only_q2,
        IntegratorKind::Path,
        LightSelection::All,
        [50, 25],
    );
    assert!(mean(&region(&b, 5.0, 2.5, q1.0, q1.1)) == 0.0);
    assert!(mean(&region(&b, 5.0, 2.5, q2.0, q2.1)) > 0.1);
}

/// A floor, a 2 × 2 black occluder at height 1 and a 1 × 1 rect light at height 3: the floor
/// under the occluder (|x|, |z| < 1.25) is in its umbra.
fn occluded_floor(with_occluder: bool) -> Scene {
    let mut s = Scene::empty("code.usda");
    s.meshes
        .push(quad("/World/Floor", [-3.0, 3.0], [-3.0, 3.0], 0.0));
    if with_occluder {
        let mut occ = quad("/World/Occ", [-1.0, 1.0], [-1.0, 1.0], 1.0);
        occ.double_sided = true;
        occ.material = Some(0);
        s.materials.push(Material {
            diffuse: Input::Value(DVec3::ZERO),
            ..Material::new("/Looks/Black")
        });
        s.meshes.push(occ);
    }
    let mut cam = top_camera(4.0, 4.0);
    // Below the occluder: the camera sees the floor.
    cam.camera_to_world.w_axis.y = 0.5;
    s.cameras.push(cam);
    s.lights.push(rect_light(1.0, 3.0));
    s
}

#[test]
fn shadow_link_excluding_the_occluder_lights_the_floor_as_without_it() {
    let open = occluded_floor(false);
    let shadowed = occluded_floor(true);
    let mut passed = occluded_floor(true);
    passed.lights[0].linking.shadow =
        rules(&[("/", Rule::ExpandPrims), ("/World/Occ", Rule::Exclude)]);
    let mut kept = occluded_floor(true);
    kept.lights[0].linking.shadow = rules(&[("/World/Occ", Rule::ExpandPrims)]);
    let under = ([-0.9, 0.9], [-0.9, 0.9]);
    for kind in INTEGRATORS {
        let what = format!("{kind:?}");
        let img = |s: &Scene| render(s, kind, LightSelection::All, [40, 40]);
        let (o, sh, p, k) = (img(&open), img(&shadowed), img(&passed), img(&kept));
        let r = |i: &ImageRgba| region(i, 4.0, 4.0, under.0, under.1);
        // Floor straight under a unit-radiance 1 × 1 rect at height 3: E/π ≈ 1/(π·9)·… > 0.
        let m = mean(&r(&o));
        eprintln!(
            "{what}: floor under the occluder: open {m:.5}, shadowed {:.5}, shadowLink \
             excluding it {:.5}, including it {:.5}",
            mean(&r(&sh)),
            mean(&r(&p)),
            mean(&r(&k))
        );
        assert!(m > 0.02 && m < 0.04, "{what}: open floor {m}");
        assert_eq!(mean(&r(&sh)), 0.0, "{what}: the umbra is black");
        // Excluded from shadowLink: the occluder casts nothing, pixel for pixel as without it.
        assert_eq!(r(&p), r(&o), "{what}: shadowLink excluding the occluder");
        // The whole image: the occluder is black and seen from below only where the camera
        // looks through it; everywhere else the floor matches the open render.
        assert_eq!(p.pixels, o.pixels, "{what}: whole image");
        // A shadowLink that holds the occluder: as without linking.
        assert_eq!(
            k.pixels, sh.pixels,
            "{what}: shadowLink including the occluder"
        );
    }
}

#[test]
fn without_linking_no_light_has_links() {
    // No set is built: the integrators take the code paths of a scene without linking (the
    // renders of the other tests' unlinked scenes are those of before).
    for s in [two_quads(), occluded_floor(true)] {
        let r = Renderer::new(&s, options(Profile::Spec, 1, [4, 4])).unwrap();
        assert!(
            r.lights()
                .lights
                .iter()
                .all(|l| l.base().links == LightLinks::default() && l.base().plain_shadows())
        );
    }
}

#[test]
fn linking_from_a_stage_reaches_the_renderer() {
    let s = lux::usd::load_usda_str(
        r#"#usda 1.0
(
    upAxis = "Y"
)
def Xform "World" {
    def Mesh "Q1" {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-2, 0, -1), (-2, 0, 1), (-0.5, 0, 1), (-0.5, 0, -1)]
    }
    def Mesh "Q2" {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(0.5, 0, -1), (0.5, 0, 1), (2, 0, 1), (2, 0, -1)]
    }
    def RectLight "Key" {
        float inputs:width = 3
        float inputs:height = 3
        rel collection:lightLink:excludes = </World/Q1>
        double3 xformOp:translate = (0, 2, 0)
        float xformOp:rotateX = -90
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
    }
}
"#,
        1.0,
        &lux::usd::LoadOptions::default(),
    )
    .unwrap();
    let mut s = s;
    s.cameras.push(top_camera(5.0, 2.5));
    let img = render(&s, IntegratorKind::Path, LightSelection::All, [50, 25]);
    assert_eq!(
        mean(&region(&img, 5.0, 2.5, [-1.9, -0.6], [-0.9, 0.9])),
        0.0
    );
    assert!(mean(&region(&img, 5.0, 2.5, [0.6, 1.9], [-0.9, 0.9])) > 0.1);
}
