//! The direct integrator's light-only estimation of rect, disk and sphere lights of uniform
//! radiance on Lambertian surfaces: a sphere wholly above the horizon is sampled in proportion
//! to the cosine-weighted solid angle (its projected cap), so the estimate is exact at any
//! sample count where it is unoccluded; occluded, light-only estimation converges to the exact
//! shadowed irradiance and to hdEmbree's estimator (uniform area samples); lights chosen by a
//! light BVH go alone too and agree with every light sampled. Expected values are closed forms
//! (`lux_irradiance::projected`, Snyder's formula).
//!
//! Scenes are built in code (`common`): a white Lambertian floor probed at one point.

mod common;

use common::{close, options, probe_scene};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::light::LightSelection;
use lux::render::render::Renderer;
use lux::render::settings::{IntegratorKind, SamplingMode};
use lux::usd::{Instance, Light, Mesh, Prototype, Scene};
use std::f64::consts::PI;

/// A light at `pos` whose emitting −Z axis points along `dir`.
fn aimed(pos: DVec3, dir: DVec3) -> DMat4 {
    let q = glam::DQuat::from_rotation_arc(DVec3::NEG_Z, dir.normalize());
    DMat4::from_rotation_translation(q, pos)
}

/// The probed radiance by direct lighting (what these closed forms describe).
fn read(scene: &Scene, spp: u32, selection: LightSelection, seed: u64) -> f64 {
    let mut o = options(Profile::Spec, spp, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    o.selection = selection;
    o.seed = seed;
    Renderer::new(scene, o).unwrap().pixel_value(0, 0).x
}

#[test]
fn unoccluded_spheres_are_exact_at_a_few_samples() {
    // A sphere wholly above the floor's horizon, off to the side: E = L·π sin²α cos β.
    let (rad, c) = (0.3, DVec3::new(0.8, 1.1, -0.4));
    let mut sph = Light::with_defaults(
        "/Sphere",
        LightShape::Sphere { radius: rad },
        DMat4::from_translation(c),
    );
    sph.params.intensity = 3.0;
    let sin2 = rad * rad / c.length_squared();
    let want = 3.0 * sin2 * (c.y / c.length());
    let s = probe_scene(vec![sph.clone()], 0.0, 0.0);
    for seed in 0..3 {
        // (the pixel footprint's variation of E, far below the noise of 4 samples otherwise)
        close(
            read(&s, 4, LightSelection::All, seed),
            want,
            1e-5,
            "sphere, 4 spp",
        );
    }
    // A light chosen by a selector (here by power, one light sample per camera sample) goes
    // alone too: its projected-cap samples are as exact.
    let mut o = options(Profile::Spec, 4, [1, 1]);
    o.integrator = IntegratorKind::Direct;
    o.selection = LightSelection::Power;
    o.light_samples = Some(1);
    let chosen = Renderer::new(&s, o.clone()).unwrap().pixel_value(0, 0).x;
    close(chosen, want, 1e-5, "sphere chosen by power, 4 spp");
    // hdEmbree's estimator (uniform area samples) with 4 spp is not exact.
    o.sampling = lux::render::settings::SamplingMode::Reference;
    let area = Renderer::new(&s, o).unwrap().pixel_value(0, 0).x;
    let far = (area - want).abs() / want;
    assert!(far > 1e-3, "area samples with 4 spp are noisy ({far:.1e})");

    // Cut by the horizon (centre 0.2 above the floor, radius 0.4): the cone fallback
    // converges to Snyder's closed form.
    let (rad, c) = (0.4, DVec3::new(1.0, 0.2, 0.0));
    sph.shape = LightShape::Sphere { radius: rad };
    sph.light_to_world = DMat4::from_translation(c);
    let sin2 = rad * rad / c.length_squared();
    let cos_t = c.y / c.length();
    let sin_t = (1.0 - cos_t * cos_t).sqrt();
    let x = (1.0 / sin2 - 1.0).sqrt();
    let y = -x * cos_t / sin_t;
    let st_y = sin_t * (1.0 - y * y).sqrt();
    let pi_proj = (cos_t * y.acos() - x * st_y) * sin2 + (st_y / x).atan();
    close(
        pi_proj,
        lux::irradiance::projected::sphere(DVec3::ZERO, DVec3::Y, c, rad).unwrap(),
        1e-12,
        "projected::sphere vs Snyder",
    );
    let s = probe_scene(vec![sph], 0.0, 0.0);
    // (uniform cone samples, about half below the horizon: a relative standard error near
    // 0.1 % at 2¹⁸ samples)
    close(
        read(&s, 1 << 18, LightSelection::All, 7),
        3.0 * pi_proj / PI,
        4e-3,
        "clipped sphere",
    );
}

/// Where nothing can block a rect, disk or sphere light of uniform radiance (no geometry in the
/// cone from the shading point to a sphere holding it: `visibility/cone.rs`), its light-only
/// estimate is its closed form `L·Π`, drawn without a sample or a shadow ray; with a blocker in
/// that cone it is sampled, and agrees with MIS.
#[test]
fn lights_nothing_can_block_take_their_closed_form_without_shadow_rays() {
    let render = |s: &Scene, spp: u32, selection: LightSelection| {
        let mut o = options(Profile::Spec, spp, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        o.selection = selection;
        o.adaptive = Some(lux::render::settings::AdaptiveSampling::OFF);
        Renderer::new(s, o).unwrap().render(&|_| {})
    };
    // Lights of intensity 3 with their Π at the point: a rect's from its world corners, a
    // disk's from its centre and its emitting −Z axis.
    let lit = |path: &str, shape: LightShape, xf: DMat4| {
        let mut l = Light::with_defaults(path, shape, xf);
        l.params.intensity = 3.0;
        l
    };
    let rect = |path: &str, xf: DMat4, (w, h): (f64, f64)| {
        let corners: Vec<DVec3> = [(-w, -h), (w, -h), (w, h), (-w, h)]
            .iter()
            .map(|&(x, y)| xf.transform_point3(DVec3::new(x / 2.0, y / 2.0, 0.0)))
            .collect();
        let shape = LightShape::Rect {
            width: w,
            height: h,
        };
        let pi = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &corners);
        (lit(path, shape, xf), pi)
    };
    let disk = |path: &str, xf: DMat4, radius: f64| {
        let (centre, axis) = (
            xf.transform_point3(DVec3::ZERO),
            xf.transform_vector3(DVec3::NEG_Z),
        );
        let pi = lux::irradiance::projected::disk(DVec3::ZERO, DVec3::Y, centre, axis, radius);
        (lit(path, LightShape::Disk { radius }, xf), pi.unwrap())
    };
    let c = DVec3::new(0.8, 1.1, -0.4);
    let sphere = lit(
        "/Sphere",
        LightShape::Sphere { radius: 0.3 },
        DMat4::from_translation(c),
    );
    let sphere_pi = PI * 0.09 / c.length_squared() * (c.y / c.length());
    // A rect and a disk facing the point from above and aside (tilted, one-sided).
    let toward = aimed(c, -c);
    // A wide, low rect (3 × 2, 0.4 above the point, facing down): the ball around it reaches
    // the floor, its pyramid does not (visibility/pyramid.rs); and a wide, low disk (radius
    // 1.2): no ball cone either, the pyramid over the square around it holds its rays.
    let low = DVec3::new(0.2, 0.4, -0.1);
    let down = aimed(low, -DVec3::Y);
    for ((light, pi), at) in [
        ((sphere, sphere_pi), c),
        (rect("/Rect", toward, (0.5, 0.3)), c),
        (disk("/Disk", toward, 0.25), c),
        (rect("/Wide", down, (3.0, 2.0)), low),
        (disk("/WideDisk", down, 1.2), low),
    ] {
        let what = light.path.clone();
        // (the light's radiance: intensity 3 on a white Lambertian floor, ρ/π · L · Π)
        let want = 3.0 * pi / PI;
        // The closed form, without a light sample or a shadow ray (to the pixel footprint's
        // variation of E).
        let closed_form = |s: &Scene, case: &str| {
            let (img, stats) = render(s, 4, LightSelection::All);
            assert_eq!(stats.shadow_rays, 0, "{what}, {case}: no shadow ray");
            assert_eq!(stats.light_samples, 0, "{what}, {case}");
            close(
                img.pixels[0][0] as f64,
                want,
                1e-5,
                &format!("{what}, {case}"),
            );
        };
        let clear = probe_scene(vec![light], 0.0, 0.0);
        closed_form(&clear, "nothing can block");

        // A small square halfway to the light, in its cone or pyramid: shadowed, and what
        // MIS (one light chosen by power, light and BSDF samples: no closed form) converges
        // to: exact without a shadow ray (visibility/penumbra.rs: the sphere's cap, the rect
        // or the disk less what the square's two triangles hide of it), the same at 4 samples
        // as at 2¹⁴.
        let mut blocked = clear;
        let m = at * 0.5;
        blocked.meshes.push(Mesh::new(
            "/Blocker",
            vec![
                m + DVec3::new(-0.06, 0.0, -0.06),
                m + DVec3::new(-0.06, 0.0, 0.06),
                m + DVec3::new(0.06, 0.0, 0.06),
                m + DVec3::new(0.06, 0.0, -0.06),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        ));
        let (img, stats) = render(&blocked, 1 << 14, LightSelection::All);
        let alone = img.pixels[0][0] as f64;
        assert_eq!(stats.shadow_rays, 0, "{what}: an exact penumbra");
        let (few, _) = render(&blocked, 4, LightSelection::All);
        close(
            few.pixels[0][0] as f64,
            alone,
            1e-5,
            &format!("{what}, 4 spp"),
        );
        assert!(
            alone < 0.97 * want && alone > 0.2 * want,
            "{what}: partly shadowed: {alone} of {want}"
        );
        let mis = read(&blocked, 1 << 16, LightSelection::Power, 2);
        close(
            alone,
            mis,
            3e-3,
            &format!("{what}: light sampling alone vs MIS"),
        );

        // The same square as an instance (geometry/instances.rs: its world box is what the
        // search sees): far to the side, the closed form still holds without a shadow ray;
        // halfway, the light is sampled and shadowed as by the world square.
        let square = blocked.meshes.pop().unwrap();
        let instanced = |at: DVec3| {
            let mut s = blocked.clone();
            let proto = s.meshes.len();
            s.meshes.push(Mesh {
                prototype: Some(0),
                positions: square.positions.iter().map(|&p| p - m).collect(),
                ..square.clone()
            });
            s.prototypes.push(Prototype {
                path: "/Proto".into(),
                meshes: vec![proto],
            });
            s.instances.push(Instance {
                path: "/Blocker".into(),
                prototype: 0,
                to_world: DMat4::from_translation(at),
                material: None,
            });
            s
        };
        closed_form(
            &instanced(DVec3::new(-3.0, 0.2, 2.5)),
            "an instance far away",
        );
        let (img, stats) = render(&instanced(m), 1 << 14, LightSelection::All);
        assert!(stats.shadow_rays > 0, "{what}: an instance halfway");
        close(
            img.pixels[0][0] as f64,
            mis,
            3e-3,
            &format!("{what}: instanced square vs MIS"),
        );
    }
}

/// A 1 × 0.6 rect light above and beside the probed point, partly hidden from it by a small
/// opaque square between them (beside the camera's view of the point).
fn occluded_rect() -> Scene {
    let mut l = Light::with_defaults(
        "/Rect",
        LightShape::Rect {
            width: 1.0,
            height: 0.6,
        },
        aimed(DVec3::new(0.2, 1.5, 0.0), DVec3::new(-0.1, -1.0, 0.05)),
    );
    l.params.intensity = 4.0;
    let mut s = probe_scene(vec![l], 0.0, 0.0);
    s.meshes.push(Mesh::new(
        "/Blocker",
        vec![
            DVec3::new(0.05, 0.7, -0.3),
            DVec3::new(0.05, 0.7, 0.3),
            DVec3::new(0.6, 0.7, 0.3),
            DVec3::new(0.6, 0.7, -0.3),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    ));
    s
}

#[test]
fn occluded_lights_converge_to_the_exact_shadowed_irradiance() {
    // A rect light partly hidden from the probed point by a small opaque square between them
    // (beside the camera's view of the point):
    // light sampling alone and MIS both converge to the exact value.
    let s = occluded_rect();
    let spp = 1 << 16;
    let alone = read(&s, spp, LightSelection::All, 1);
    let mis = read(&s, spp, LightSelection::Power, 2);
    let unshadowed = read(
        &probe_scene(vec![s.lights[0].clone()], 0.0, 0.0),
        4,
        LightSelection::All,
        0,
    );
    assert!(
        alone < 0.9 * unshadowed && alone > 0.1 * unshadowed,
        "partly shadowed: {alone} of {unshadowed}"
    );
    // The exact value: the rect's Π minus that of the blocker's shadow on it (the blocker
    // projected from the point onto the rect's plane, clipped to the rect).
    let m = aimed(DVec3::new(0.2, 1.5, 0.0), DVec3::new(-0.1, -1.0, 0.05));
    let corners: Vec<DVec3> = [(-0.5, -0.3), (0.5, -0.3), (0.5, 0.3), (-0.5, 0.3)]
        .iter()
        .map(|&(x, y)| m.transform_point3(DVec3::new(x, y, 0.0)))
        .collect();
    let nr = (corners[1] - corners[0])
        .cross(corners[3] - corners[0])
        .normalize();
    let mut shadow: Vec<DVec3> = s.meshes[1]
        .positions
        .iter()
        .map(|&b| b * (nr.dot(corners[0]) / nr.dot(b)))
        .collect();
    for i in 0..4 {
        let (a, b) = (corners[i], corners[(i + 1) % 4]);
        let inward = nr.cross(b - a); // towards the rect's inside for this winding
        let inward = if inward.dot(corners[(i + 2) % 4] - a) > 0.0 {
            inward
        } else {
            -inward
        };
        let mut out = Vec::new();
        for j in 0..shadow.len() {
            let (x, y) = (shadow[j], shadow[(j + 1) % shadow.len()]);
            let (hx, hy) = (inward.dot(x - a), inward.dot(y - a));
            if hx >= 0.0 {
                out.push(x);
            }
            if (hx >= 0.0) != (hy >= 0.0) {
                out.push(x + (y - x) * (hx / (hx - hy)));
            }
        }
        shadow = out;
    }
    let proj = |v: &[DVec3]| lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, v);
    let exact = 4.0 * (proj(&corners) - proj(&shadow)) / PI;
    close(alone, exact, 2e-3, "light sampling alone");
    close(mis, exact, 2e-3, "MIS");
}

#[test]
fn penumbra_pass_is_unbiased_and_quieter() {
    // The occluded rect, probed in its penumbra and sampled (rays visibility: with the exact one its
    // penumbra is exact): 64-spp estimates over 40 seeds, without and with the penumbra pass
    // (8 light samples where the pilot saw a blocked shadow ray). Both means agree with the
    // exact value within their noise; the pass lowers the spread.
    let s = occluded_rect();
    let exact = read(&s, 1 << 16, LightSelection::All, 1);
    let stats = |pen: u32| {
        let v: Vec<f64> = (0..40u64)
            .map(|seed| {
                let mut o = options(Profile::Spec, 64, [1, 1]);
                o.integrator = IntegratorKind::Direct;
                o.visibility = lux::render::settings::VisibilityMode::Rays;
                o.penumbra_samples = pen;
                o.seed = 100 + seed;
                Renderer::new(&s, o).unwrap().pixel_value(0, 0).x
            })
            .collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (v.len() - 1) as f64;
        (mean, var)
    };
    let (m1, v1) = stats(1);
    let (m8, v8) = stats(8);
    for (mean, var, what) in [(m1, v1, "without"), (m8, v8, "with")] {
        let se = (var / 40.0).sqrt();
        assert!(
            (mean - exact).abs() <= 4.0 * se + 1e-4 * exact,
            "{what} the pass: {mean} ± {se} vs {exact}"
        );
    }
    assert!(v8 * 2.0 < v1, "penumbra pass variance {v8} vs {v1}");
}

#[test]
fn occluded_disks_agree_with_area_sampling() {
    // A disk, circular or made elliptic by its transform, partly hidden by the occluder of
    // `occluded_rect`: light sampling alone and hdEmbree's estimator (uniform area samples,
    // the plain estimator) agree within their noise, over 8 seeds each. (A light chosen by a
    // selector goes alone as well: MIS against BSDF samples is tested where the BSDF is not
    // Lambertian.)
    let disk_at = |scale: DVec3| {
        let mut l = Light::with_defaults(
            "/Disk",
            LightShape::Disk { radius: 0.4 },
            aimed(DVec3::new(0.2, 1.5, 0.0), DVec3::new(-0.1, -1.0, 0.05))
                * DMat4::from_scale(scale),
        );
        l.params.intensity = 4.0;
        let mut s = occluded_rect();
        s.lights = vec![l];
        s
    };
    let stats = |s: &Scene, sampling: SamplingMode| {
        let v: Vec<f64> = (0..8u64)
            .map(|seed| {
                let mut o = options(Profile::Spec, 1 << 13, [1, 1]);
                o.integrator = IntegratorKind::Direct;
                o.selection = LightSelection::All;
                o.sampling = sampling;
                o.seed = 40 + seed;
                Renderer::new(s, o).unwrap().pixel_value(0, 0).x
            })
            .collect();
        let mean = v.iter().sum::<f64>() / 8.0;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / 7.0;
        (mean, var / 8.0)
    };
    for (scale, what) in [
        (DVec3::ONE, "circular"),
        (DVec3::new(1.3, 0.7, 1.0), "elliptic"),
    ] {
        let s = disk_at(scale);
        let (a, va) = stats(&s, SamplingMode::Lux);
        let (m, vm) = stats(&s, SamplingMode::Reference);
        let unshadowed = read(
            &probe_scene(s.lights.clone(), 0.0, 0.0),
            1 << 12,
            LightSelection::All,
            0,
        );
        assert!(
            a < 0.9 * unshadowed && a > 0.1 * unshadowed,
            "{what}: partly shadowed: {a} of {unshadowed}"
        );
        let se = (va + vm).sqrt();
        assert!(
            (a - m).abs() <= 4.0 * se,
            "{what} disk: light alone {a} vs area samples {m} (σ {se:.2e})"
        );
        assert!(
            se < 2e-3 * a,
            "{what}: the comparison resolves 0.8 % ({se:.2e})"
        );
    }
}

/// The luxtest frames lit by a sphere, a disk and a rect (frame 1, `hdembree`: Lambertian
/// floor and occluder), with and without closed forms, the same samples otherwise. Where the
/// closed forms apply the pixels lose the light samples' noise (the sphere's projected-cap
/// samples are exact where unblocked, so there only its penumbra, now exact too, changes);
/// the image means agree within 4 standard errors of the per-pixel differences.
#[test]
fn closed_forms_change_the_luxtest_frames_by_rounding_or_noise_only() {
    let load = |name: &str| {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/luxtest/usd")
            .join(format!("{name}.usda"));
        lux::usd::load_stage(p, 1.0).unwrap()
    };
    let render = |s: &Scene, closed: bool| {
        let mut o = options(Profile::HdEmbree, 8, [64, 64]);
        o.adaptive = Some(lux::render::settings::AdaptiveSampling::OFF);
        o.visibility = if closed {
            lux::render::settings::VisibilityMode::Exact
        } else {
            lux::render::settings::VisibilityMode::Rays
        };
        Renderer::new(s, o).unwrap().render(&|_| {})
    };
    for name in ["sphere", "disk", "rect"] {
        let s = load(name);
        let ((on, on_stats), (off, off_stats)) = (render(&s, true), render(&s, false));
        assert!(
            on_stats.shadow_rays * 2 < off_stats.shadow_rays,
            "{name}: closed forms used ({} vs {} shadow rays)",
            on_stats.shadow_rays,
            off_stats.shadow_rays
        );
        let pairs = on.pixels.iter().zip(&off.pixels);
        let n = on.pixels.len() as f64;
        for k in 0..3 {
            let d: Vec<f64> = pairs
                .clone()
                .map(|(a, b)| a[k] as f64 - b[k] as f64)
                .collect();
            let mean = d.iter().sum::<f64>() / n;
            let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let image = on.pixels.iter().map(|p| p[k] as f64).sum::<f64>() / n;
            assert!(image > 1e-3, "{name}: lit");
            assert!(
                mean.abs() <= 4.0 * (var / n).sqrt(),
                "{name} channel {k}: mean difference {mean:.3e}, σ/√n {:.3e}",
                (var / n).sqrt()
            );
        }
    }
}

/// A closed box of half-extent `h` about `c`, turned by `turn` (12 triangles, wound either
/// way: the solid test orients them).
fn solid_box(path: &str, c: DVec3, h: f64, turn: glam::DQuat) -> Mesh {
    let points = (0..8)
        .map(|i| {
            let s = |b: usize| if i & b == 0 { -h } else { h };
            c + turn * DVec3::new(s(1), s(2), s(4))
        })
        .collect();
    let quads = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let tris = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    Mesh::new(path, points, tris)
}

/// A faceted ball of radius `r` about `c`: an octahedron whose faces are split in four
/// `levels` times, corners pushed out to the sphere (8·4^levels triangles).
fn faceted_ball(path: &str, c: DVec3, r: f64, levels: u32) -> Mesh {
    // (±x, ±y, ±z in that order)
    let mut points: Vec<DVec3> = (0..6)
        .map(|i| {
            let mut v = DVec3::ZERO;
            v[i / 2] = if i % 2 == 0 { 1.0 } else { -1.0 };
            v
        })
        .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut split = |a: u32, b: u32, points: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                points.push((points[a as usize] + points[b as usize]).normalize());
                points.len() as u32 - 1
            })
        };
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    split(a, b, &mut points),
                    split(b, c, &mut points),
                    split(c, a, &mut points),
                );
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    Mesh::new(path, points.iter().map(|p| c + r * *p).collect(), tris)
}

/// A sphere, a rect and a disk light behind a few opaque triangles (visibility/penumbra.rs): where the
/// triangles lie in front of the light, its penumbra is exact — no shadow ray, the same value
/// at any seed and sample count — and equals what light sampling with shadow rays
/// (`--visibility rays`) and MIS converge to: behind one card, behind two overlapping ones
/// (their union), behind a closed box and a faceted ball of 512 triangles overlapping each
/// other and a card (their silhouettes, visibility/solid.rs). Where one reaches past the
/// sphere's nearest point or the rect's or disk's plane, it is sampled as before and converges
/// to the same.
#[test]
fn sphere_rect_and_disk_penumbrae_are_exact_where_few_triangles_block() {
    let c = DVec3::new(0.3, 1.2, -0.2);
    let mut sph = Light::with_defaults(
        "/Sphere",
        LightShape::Sphere { radius: 0.3 },
        DMat4::from_translation(c),
    );
    sph.params.intensity = 2.0;
    // A 0.6 × 0.6 rect at the same place, facing the point.
    let mut rect = Light::with_defaults(
        "/Rect",
        LightShape::Rect {
            width: 0.6,
            height: 0.6,
        },
        aimed(c, -c),
    );
    rect.params.intensity = 2.0;
    // A disk of radius 0.3 there, facing the point.
    let mut disk = Light::with_defaults("/Disk", LightShape::Disk { radius: 0.3 }, aimed(c, -c));
    disk.params.intensity = 2.0;
    let disk_projected = lux::irradiance::projected::disk(
        DVec3::ZERO,
        DVec3::Y,
        c,
        aimed(c, -c).transform_vector3(DVec3::NEG_Z),
        0.3,
    )
    .unwrap();
    let rect_corners: Vec<DVec3> = [(-0.3, -0.3), (0.3, -0.3), (0.3, 0.3), (-0.3, 0.3)]
        .iter()
        .map(|&(x, y)| aimed(c, -c).transform_point3(DVec3::new(x, y, 0.0)))
        .collect();
    let quad = |path: &str, q: [DVec3; 4]| Mesh::new(path, q.to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
    // A tilted card halfway up whose edge crosses the light from the probed point.
    let card = |path: &str, at: DVec3| {
        quad(
            path,
            [
                at + DVec3::new(-0.3, 0.0, -0.3),
                at + DVec3::new(0.3, 0.05, -0.3),
                at + DVec3::new(0.3, 0.1, 0.3),
                at + DVec3::new(-0.3, 0.05, 0.3),
            ],
        )
    };
    let run = |s: &Scene, spp: u32, closed: bool, selection: LightSelection, seed: u64| {
        let mut o = options(Profile::Spec, spp, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        o.selection = selection;
        o.seed = seed;
        o.visibility = if closed {
            lux::render::settings::VisibilityMode::Exact
        } else {
            lux::render::settings::VisibilityMode::Rays
        };
        o.adaptive = Some(lux::render::settings::AdaptiveSampling::OFF);
        let (img, stats) = Renderer::new(s, o).unwrap().render(&|_| {});
        (img.pixels[0][0] as f64, stats.shadow_rays)
    };
    let projected = lux::irradiance::projected::sphere(DVec3::ZERO, DVec3::Y, c, 0.3).unwrap();
    let rect_projected = lux::irradiance::projected::polygon(DVec3::ZERO, DVec3::Y, &rect_corners);
    // A long card reaching past the plane of the sphere's nearest point (in front of the
    // sphere along every ray that meets both, but not proven so), and one rising through the
    // rect's or disk's plane beside it.
    let flat_long = [
        DVec3::new(0.3, 0.85, -0.6),
        DVec3::new(0.3, 0.85, 0.4),
        DVec3::new(1.5, 0.85, 0.4),
        DVec3::new(1.5, 0.85, -0.6),
    ];
    let rising_long = [
        DVec3::new(0.3, 0.85, -0.6),
        DVec3::new(0.3, 0.85, 0.4),
        DVec3::new(1.5, 1.6, 0.4),
        DVec3::new(1.5, 1.6, -0.6),
    ];
    for (light, pi, long_card) in [
        (sph, projected, flat_long),
        (rect, rect_projected, rising_long),
        (disk, disk_projected, rising_long),
    ] {
        let name = light.path.clone();
        let unshadowed = 2.0 * pi / PI;
        let mut one = probe_scene(vec![light], 0.0, 0.0);
        // (a footprint of 10⁻⁸: the penumbra's gradient varies the pixel by ~10⁻⁷ of its value)
        one.cameras[0].horizontal_aperture = 1e-8;
        one.cameras[0].vertical_aperture = 1e-8;
        one.meshes.push(card("/Card", DVec3::new(0.35, 0.6, -0.1)));
        // Two cards, the second below the first and overlapping it as seen from the point.
        let mut two = one.clone();
        two.meshes
            .push(card("/Below", DVec3::new(0.1, 0.45, -0.45)));
        let mut long = one.clone();
        long.meshes.pop();
        long.meshes.push(quad("/Long", long_card));
        // A box and a ball overlapping each other and the card as seen from the point.
        let mut solids = one.clone();
        solids.meshes.push(solid_box(
            "/Box",
            DVec3::new(0.2, 0.42, -0.08),
            0.06,
            glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 0.5, 0.2),
        ));
        solids.meshes.push(faceted_ball(
            "/Ball",
            DVec3::new(0.15, 0.85, -0.22),
            0.08,
            3,
        ));
        // The card subdivided 4 × 4: its outline in the shadow BVH stands for it, one convex
        // polygon rather than triangles (visibility/planar.rs, penumbra::past), and the penumbra
        // is the two-triangle card's.
        let mut grid = one.clone();
        let flat = grid.meshes.pop().unwrap();
        let corner = |u: f64, v: f64| {
            let q = &flat.positions;
            (1.0 - v) * ((1.0 - u) * q[0] + u * q[1]) + v * ((1.0 - u) * q[3] + u * q[2])
        };
        let points: Vec<DVec3> = (0..25)
            .map(|i| corner((i % 5) as f64 / 4.0, (i / 5) as f64 / 4.0))
            .collect();
        let cells = (0..16u32).flat_map(|c| {
            let a = c / 4 * 5 + c % 4;
            [[a, a + 1, a + 6], [a, a + 6, a + 5]]
        });
        grid.meshes
            .push(Mesh::new("/Grid", points, cells.collect()));
        let (whole, rays) = run(&grid, 4, true, LightSelection::All, 1);
        assert_eq!(rays, 0, "{name}: the subdivided card's penumbra is exact");
        close(
            whole,
            run(&one, 4, true, LightSelection::All, 1).0,
            1e-9,
            &format!("{name}: subdivided card"),
        );
        for (what, s, exact) in [
            ("one card", &one, true),
            ("overlapping cards", &two, true),
            ("a box, a ball and a card", &solids, true),
            ("a long card", &long, false),
        ] {
            let what = format!("{name}, {what}");
            let (v, rays) = run(s, 4, true, LightSelection::All, 1);
            // Mean and standard error of 32 independent 2¹⁴-sample estimates.
            let converged = |closed: bool, selection: LightSelection, seed: u64| {
                let x: Vec<f64> = (0..32)
                    .map(|i| run(s, 1 << 14, closed, selection, seed + 100 * i).0)
                    .collect();
                let mean = x.iter().sum::<f64>() / 32.0;
                let var = x.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 31.0;
                (mean, (var / 32.0).sqrt())
            };
            let (sampled, se_s) = converged(false, LightSelection::All, 2);
            let (mis, se_m) = converged(true, LightSelection::Power, 3);
            assert!(
                sampled > 0.03 * unshadowed && sampled < 0.9 * unshadowed,
                "{what}: a penumbra ({sampled} of {unshadowed})"
            );
            // (4σ: the comparisons resolve about 1 %; lux_irradiance::hidden's tests check the
            // closed forms themselves to 2·10⁻⁶)
            assert!(
                se_s < 3e-3 * sampled && se_m < 3e-3 * mis,
                "{what}: {se_s:.1e} {se_m:.1e}"
            );
            let se = (se_s * se_s + se_m * se_m).sqrt();
            assert!(
                (sampled - mis).abs() <= 4.0 * se,
                "{what}: light sampling {sampled} vs MIS {mis} (σ {se:.1e})"
            );
            if exact {
                assert_eq!(rays, 0, "{what}: no shadow ray");
                for seed in 4..8 {
                    close(
                        run(s, 1, true, LightSelection::All, seed).0,
                        v,
                        1e-6,
                        &format!("{what}: seed {seed}"),
                    );
                }
                assert!(
                    (v - sampled).abs() <= 4.0 * se_s && (v - mis).abs() <= 4.0 * se_m,
                    "{what}: exact {v} vs sampled {sampled} ± {se_s:.1e}, MIS {mis} ± {se_m:.1e}"
                );
            } else {
                assert!(rays > 0, "{what}: sampled");
                let (alone, se_a) = converged(true, LightSelection::All, 5);
                let se = (se_s * se_s + se_a * se_a).sqrt();
                assert!(
                    (alone - sampled).abs() <= 4.0 * se,
                    "{what}: {alone} vs {sampled} (σ {se:.1e})"
                );
            }
        }
    }
}

/// Twelve spheres, disks and rects of uniform radiance around the occluded rect's blocker,
/// a sphere cut by the floor's plane (partly above the probe's horizon) and a disk below it.
fn many_lights() -> Vec<Light> {
    let mut cut = Light::with_defaults(
        "/Cut",
        LightShape::Sphere { radius: 0.15 },
        DMat4::from_translation(DVec3::new(0.7, 0.05, 0.2)),
    );
    cut.params.intensity = 2.0;
    let below = Light::with_defaults(
        "/Below",
        LightShape::Disk { radius: 0.3 },
        aimed(DVec3::new(-0.3, -0.4, 0.1), DVec3::Y),
    );
    (0..12)
        .map(|i| {
            let a = i as f64 * 0.52;
            let pos = DVec3::new(0.9 * a.cos(), 1.2 + 0.08 * i as f64, 0.9 * a.sin());
            let shape = match i % 3 {
                0 => LightShape::Sphere { radius: 0.12 },
                1 => LightShape::Disk { radius: 0.2 },
                _ => LightShape::Rect {
                    width: 0.3,
                    height: 0.2,
                },
            };
            let mut l = Light::with_defaults(
                format!("/L{i}"),
                shape,
                aimed(pos, DVec3::new(-pos.x * 0.5, -1.0, -pos.z * 0.5)),
            );
            l.params.intensity = 1.0 + 0.25 * i as f64;
            l
        })
        .chain([cut, below])
        .collect()
}

#[test]
fn lights_chosen_by_the_bvh_go_alone_and_agree_with_every_light_sampled() {
    // Fourteen uniform lights (more than `AUTO_ALL_LIGHTS`: one chosen by the light BVH per
    // light sample) over the Lambertian floor, partly hidden by the blocker, one cut by the
    // floor's plane and one below it (the BVH gives lights below a receiver's horizon nothing:
    // the cut sphere must keep its share). The chosen lights are
    // estimated by light sampling alone: no BSDF ray is traced (the only rays besides shadow
    // rays are the camera's), and the mean over seeds agrees with every light sampled at
    // every point within the standard errors of both. Unblocked, it agrees with the sum of
    // the twelve closed forms.
    let mut s = occluded_rect();
    s.lights = many_lights();
    let stats = |s: &Scene, selection: LightSelection, spp: u32| {
        let n = 16u64;
        let v: Vec<f64> = (0..n)
            .map(|seed| {
                let mut o = options(Profile::Spec, spp, [1, 1]);
                o.integrator = IntegratorKind::Direct;
                o.visibility = lux::render::settings::VisibilityMode::Rays;
                o.selection = selection;
                o.seed = 70 + seed;
                let r = Renderer::new(s, o).unwrap();
                if selection == LightSelection::Auto {
                    let (_, st) = r.render(&|_| {});
                    assert_eq!(st.rays - st.shadow_rays, st.samples, "only camera rays");
                    assert!(st.shadow_rays > 0);
                }
                r.pixel_value(0, 0).x
            })
            .collect();
        let mean = v.iter().sum::<f64>() / n as f64;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
        (mean, var / n as f64)
    };
    let (chosen, vc) = stats(&s, LightSelection::Auto, 1 << 12);
    let (every, ve) = stats(&s, LightSelection::All, 1 << 10);
    let se = (vc + ve).sqrt();
    assert!(
        (chosen - every).abs() <= 4.0 * se,
        "BVH-chosen {chosen} vs every light {every} (σ {se:.2e})"
    );
    assert!(se < 3e-3 * every, "resolves 1.2 % ({se:.2e} of {every})");
    // Unblocked: the closed forms' sum (every light, 2 light samples each: exact where
    // unblocked), averaged over the pixel's footprint (4096 camera samples: near the floor the
    // cut sphere's irradiance varies across it by ~1 %).
    let open = probe_scene(many_lights(), 0.0, 0.0);
    let exact = {
        let mut o = options(Profile::Spec, 1 << 12, [1, 1]);
        o.integrator = IntegratorKind::Direct;
        o.selection = LightSelection::All;
        o.light_samples = Some(2);
        Renderer::new(&open, o).unwrap().pixel_value(0, 0).x
    };
    let (c, v) = stats(&open, LightSelection::Auto, 1 << 12);
    assert!(
        (c - exact).abs() <= 4.0 * v.sqrt() + 1e-6 * exact,
        "unblocked: BVH-chosen {c} vs closed forms {exact} (σ {:.2e})",
        v.sqrt()
    );
    assert!(
        chosen < 0.97 * exact,
        "the blocker shadows the probe: {chosen} of {exact}"
    );
}
