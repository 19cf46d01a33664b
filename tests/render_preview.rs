//! UsdPreviewSurface in the renderer: opacity (shadow rays carry ∏(1 − o) exactly, camera rays
//! stop with probability o), `opacityThreshold` cut-outs, and normal maps in the tangent frame
//! of the texture coordinates. The floor is the white Lambertian of `common` (no material).

mod common;

use common::{close, options, probe_scene};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::geometry::Geometry;
use lux::render::material::Materials;
use lux::render::render::Renderer;
use lux::render::settings::IntegratorKind;
use lux::usd::{Input, Light, Material, Membership, Mesh, Rule, Scene};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// A distant light of irradiance 2.5 arriving at 45° from +x (travelling along (−1, −1, 0)/√2).
fn sun() -> Light {
    let dir = DVec3::new(-1.0, -1.0, 0.0).normalize();
    // The light emits along its −Z axis: a frame whose −Z is `dir`.
    let z = -dir;
    let x = DVec3::Z.cross(z).normalize();
    let y = z.cross(x);
    let m = DMat4::from_cols_array(&[
        x.x, x.y, x.z, 0.0, y.x, y.y, y.z, 0.0, z.x, z.y, z.z, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    let mut l = Light::with_defaults("/Sun", LightShape::Distant { angle_deg: 0.0 }, m);
    l.params.intensity = 2.5;
    l
}

/// The probe scene (camera above the origin) with a 1 × 1 double-sided quad at height 1 over
/// x ∈ [0.5, 1.5] — on the shadow ray from the origin towards the sun, out of the camera's
/// view — whose material has `opacity` and `opacityThreshold`.
fn scene(opacity: f64, threshold: f64) -> Scene {
    let mut s = probe_scene(vec![sun()], 0.0, 0.0);
    let mut quad = Mesh::new(
        "/Veil",
        vec![
            DVec3::new(0.5, 1.0, -0.5),
            DVec3::new(1.5, 1.0, -0.5),
            DVec3::new(1.5, 1.0, 0.5),
            DVec3::new(0.5, 1.0, 0.5),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    quad.double_sided = true;
    quad.material = Some(0);
    s.materials.push(Material {
        preview: true,
        opacity: Input::Value(opacity),
        opacity_threshold: threshold,
        ..Material::new("/Looks/Veil")
    });
    s.meshes.push(quad);
    s
}

fn floor_radiance(s: &Scene, integrator: IntegratorKind) -> f64 {
    let mut o = options(Profile::Spec, 16, [1, 1]);
    o.integrator = integrator;
    Renderer::new(s, o).unwrap().pixel_value(0, 0).x
}

#[test]
fn shadow_rays_carry_one_minus_opacity() {
    // E = 2.5·cos 45° on the floor, radiance E/π, through a veil of opacity o: (1 − o)·E/π.
    // Direct lighting only: a path tracer also finds the light the veil's underside reflects
    // onto the floor — except when the veil is fully transparent, where both give `open`.
    let open = 2.5 * FRAC_1_SQRT_2 / PI;
    for (o, threshold) in [(0.0, 0.0), (0.4, 0.5)] {
        close(
            floor_radiance(&scene(o, threshold), IntegratorKind::Path),
            open,
            1e-12,
            &format!("path through a transparent veil (opacity {o}, threshold {threshold})"),
        );
    }
    {
        let integrator = IntegratorKind::Direct;
        for (o, threshold, want) in [
            (1.0, 0.0, 0.0),
            (0.25, 0.0, 0.75 * open),
            (0.0, 0.0, open),
            // Cut-outs: below the threshold fully transparent, at or above it opaque.
            (0.4, 0.5, open),
            (0.6, 0.5, 0.0),
            (0.5, 0.5, 0.0),
        ] {
            let got = floor_radiance(&scene(o, threshold), integrator);
            let what = format!("opacity {o}, threshold {threshold}, {integrator:?}");
            if want == 0.0 {
                assert_eq!(got, 0.0, "{what}");
            } else {
                close(got, want, 1e-12, &what);
            }
        }
    }
}

#[test]
fn a_veil_outside_the_shadow_link_casts_no_shadow() {
    // Opacity and shadow linking together: the sun's shadowLink excludes the veil, so its
    // shadow rays pass it whatever its opacity; with the veil included they carry 1 − o.
    let open = 2.5 * FRAC_1_SQRT_2 / PI;
    for (exclude, want) in [(true, open), (false, 0.75 * open)] {
        let mut s = scene(0.25, 0.0);
        let mut rules = vec![("/".to_owned(), Rule::ExpandPrims)];
        if exclude {
            rules.push(("/Veil".to_owned(), Rule::Exclude));
        }
        s.lights[0].linking.shadow = Membership::Rules(rules.into_iter().collect());
        close(
            floor_radiance(&s, IntegratorKind::Direct),
            want,
            1e-12,
            &format!("veil excluded from the shadow link: {exclude}"),
        );
    }
    // A ShadowAPI colour (0.2, 0.4, 0.6) at full strength: where the veil stops light the
    // shadow lets that colour through, so the floor gets T + (1 − T)·colour, T = 0.75.
    let mut s = scene(0.25, 0.0);
    s.lights[0].shadow.applied = true;
    s.lights[0].shadow.color = DVec3::new(0.2, 0.4, 0.6);
    let mut o = options(Profile::Spec, 16, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    let v = Renderer::new(&s, o).unwrap().pixel_value(0, 0);
    for (k, c) in [0.2, 0.4, 0.6].into_iter().enumerate() {
        close(
            v[k],
            (0.75 + 0.25 * c) * open,
            1e-12,
            "coloured shadow of a veil",
        );
    }
}

#[test]
fn camera_rays_stop_with_probability_opacity() {
    // The camera looks straight down through a black veil (black diffuse, no specular) of
    // opacity 0.25 at height 1 over the probe point, the sun straight above: a quarter of the
    // rays stop at the veil (radiance 0), the rest see the floor in its 0.75 shadow. Mean
    // 0.75 · 0.75 · E/π; the 4096 camera samples give a binomial error of
    // √(0.25·0.75/4096) = 0.68 % of the stopping fraction, so 3 % is 4.4 σ.
    let mut s = scene(0.25, 0.0);
    let mut l = Light::with_defaults("/Sun", LightShape::Distant { angle_deg: 0.0 }, {
        // Emitting along −Y: the light's −Z axis is −Y.
        DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ])
    });
    l.params.intensity = 2.5;
    s.lights = vec![l];
    for p in &mut s.meshes[1].positions {
        p.x -= 1.0;
    }
    s.materials[0].diffuse = Input::Value(DVec3::ZERO);
    s.materials[0].use_specular_workflow = true;
    let mut o = options(Profile::Spec, 4096, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    let got = Renderer::new(&s, o).unwrap().pixel_value(0, 0).x;
    close(
        got,
        0.75 * 0.75 * 2.5 / PI,
        0.03,
        "floor seen through the veil",
    );
}

#[test]
fn normal_map_tilts_the_shading_normal() {
    // preview_surface.usda's /World/Leaf: a unit quad at z = 1 facing +z with st = (x, y), and a
    // normal map of texels (204, 128, 230) read raw with scale 2 and bias −1: the tangent-space
    // normal (0.6, 0.0039, 0.8). Tangent ∂p/∂s = +x, bitangent +y: the shading normal is
    // normalize(0.6, 0.0039, 0.8) in the world.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/scenes/preview_surface.usda");
    let s = lux::usd::load_stage(&path, 1.0).unwrap();
    let g = Geometry::new(&s);
    let m = Materials::new(&s).unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let hit = g
        .intersect(&s, DVec3::new(0.25, 0.5, 5.0), DVec3::NEG_Z, 0.0, 10.0)
        .unwrap();
    assert_eq!(s.meshes[hit.mesh].path, "/World/Leaf");
    let sp = m.at(&s, &hit, DVec3::NEG_Z);
    let texel = |v: f64| (v / 255.0) * 2.0 - 1.0;
    let want = DVec3::new(texel(204.0), texel(128.0), texel(230.0)).normalize();
    assert!((sp.ns - want).length() < 2e-3, "{} vs {want}", sp.ns);
    assert_eq!(sp.ng, DVec3::Z);
    // The leaf's alpha is 1 in its left texel column and 0 in its right, a cut-out at 0.5.
    // Through the UsdTransform2d, st = (x, y) ↦ R(90°)·(2x, 4y) + (0.5, −1) = (0.5 − 4y, 2x − 1),
    // and wrapS = mirror folds s: y = 0.1875 gives s = −0.25 → 0.25 (the left column's centre),
    // y = 0.3125 gives s = −0.75 → 0.75 (the right column's).
    // (x = 0.1 keeps the ray off /World/Coat above, the triangle x ≥ y.)
    for (y, want) in [(0.1875, 1.0), (0.3125, 0.0)] {
        let hit = g
            .intersect(&s, DVec3::new(0.1, y, 5.0), DVec3::NEG_Z, 0.0, 10.0)
            .unwrap();
        assert_eq!(s.meshes[hit.mesh].path, "/World/Leaf");
        assert_eq!(m.opacity(&s, &hit), want, "y = {y}");
    }
}

/// The floor of `common` with a UsdPreviewSurface (a rough dielectric with clearcoat), lit by a
/// sphere light with the given `inputs:diffuse` and `inputs:specular`.
fn lobes_scene(diffuse: f64, specular: f64) -> Scene {
    let mut sph = Light::with_defaults(
        "/Sphere",
        LightShape::Sphere { radius: 0.3 },
        DMat4::from_translation(DVec3::new(0.6, 1.2, -0.3)),
    );
    sph.params.intensity = 3.0;
    sph.diffuse = diffuse;
    sph.specular = specular;
    let mut s = probe_scene(vec![sph], 0.0, 0.0);
    s.materials.push(Material {
        preview: true,
        diffuse: Input::Value(DVec3::new(0.6, 0.4, 0.2)),
        roughness: Input::Value(0.4),
        clearcoat: Input::Value(0.5),
        ..Material::new("/Looks/Floor")
    });
    s.meshes[0].material = Some(0);
    s
}

#[test]
fn light_diffuse_and_specular_scale_their_lobes() {
    // LightAPI inputs:diffuse and inputs:specular scale the diffuse and the specular (GGX,
    // clearcoat) parts of f. The estimate is linear in each, with the same random numbers:
    // (1, 0) + (0, 1) = (1, 1), and (2, 3) = 2·(1, 0) + 3·(0, 1), to rounding.
    let read = |kd: f64, ks: f64| {
        let mut o = options(Profile::Spec, 64, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        Renderer::new(&lobes_scene(kd, ks), o)
            .unwrap()
            .pixel_value(0, 0)
            .truncate()
    };
    let (d, s, both) = (read(1.0, 0.0), read(0.0, 1.0), read(1.0, 1.0));
    assert!(d.min_element() > 0.0 && s.min_element() > 0.0, "{d} {s}");
    // Both parts matter here: the specular part is a few per cent of the total at least.
    assert!(s.x > 0.02 * both.x, "{s} of {both}");
    for k in 0..3 {
        close(d[k] + s[k], both[k], 1e-9, "diffuse + specular");
        close(
            2.0 * d[k] + 3.0 * s[k],
            read(2.0, 3.0)[k],
            1e-9,
            "2·diffuse + 3·specular",
        );
    }
    assert_eq!(read(0.0, 0.0), DVec3::ZERO);
}

/// A direct render decodes a `UsdUVTexture` file when a lookup first reads it
/// (`TextureDecoding::OnFirstUse`; `strict` decodes every file up front instead): the same
/// bits, on pools of 1, 2 and 3 threads whose workers meet the undecoded texture at once, and
/// no late warning for files that decode.
#[test]
fn textures_decoded_on_first_use_render_the_bits_of_textures_decoded_up_front() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/scenes/preview_surface.usda");
    let mut s = lux::usd::load_stage(&path, 1.0).unwrap();
    // Looking down −z at the unit quads from above their middle, 1.2 units across, lit by a
    // distant light straight down the −z axis (a light's identity frame).
    let mut c = lux::usd::Camera::with_defaults(
        "/Above",
        DMat4::from_translation(DVec3::new(0.5, 0.5, 5.0)),
    );
    c.projection = lux::usd::Projection::Orthographic;
    (c.horizontal_aperture, c.vertical_aperture) = (12.0, 12.0);
    s.cameras.push(c);
    let mut sun = Light::with_defaults(
        "/Down",
        LightShape::Distant { angle_deg: 0.0 },
        DMat4::IDENTITY,
    );
    sun.params.intensity = 2.0;
    s.lights.push(sun);
    let mut o = options(Profile::Spec, 2, [48, 48]);
    o.integrator = IntegratorKind::Direct;
    o.surfaces = lux::render::material::SurfaceModel::Lambert;
    let image = |strict: bool, threads: usize| {
        let mut o = o.clone();
        o.strict = strict;
        let r = Renderer::new(&s, o).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let pixels = pool.install(|| r.render(&|_| {})).0.pixels;
        assert_eq!(r.late_warnings().count(), 0);
        pixels
    };
    let want = image(true, 2);
    // The leaf's texture is in the picture: its texels are not all one colour.
    let lit: Vec<_> = want.iter().filter(|p| p[3] > 0.0).collect();
    assert!(lit.iter().any(|p| p[0] != lit[0][0]), "a flat picture");
    for threads in [1, 2, 3] {
        assert!(image(false, threads) == want, "{threads} threads");
    }
}
