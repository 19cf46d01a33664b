//! Adaptive sampling (`RenderOptions::adaptive`, adaptive.rs and tiles.rs): extra samples go where a pixel's
//! neighbourhood varies and nowhere else, every pixel stays an unbiased estimate, and a band
//! of rows or another thread count gives the same bits.
//!
//! The scene: the white floor lit straight down by a DistantLight, seen from above through an
//! orthographic camera, its edge at `x = 16.3` pixels. Column 16 is 30 % covered, so its
//! expected alpha is exactly 0.3 and its expected colour 0.3 × the lit floor's.

mod common;

use common::{floor, options, probe_camera};
use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::image_io::ImageRgba;
use lux::render::render::{RenderOptions, RenderStats, Renderer};
use lux::render::settings::{AdaptiveSampling, NoiseMeasure};
use lux::usd::{Light, Scene};

/// Image side in pixels; the camera's 4 scene units span it (1/8 unit a pixel).
const N: u32 = 32;
/// The floor's edge, in pixels from the image's left side.
const EDGE: f64 = 16.3;

fn edge_scene() -> Scene {
    let mut s = Scene::empty("code.usda");
    let mut f = floor();
    let xe = -2.0 + EDGE * 4.0 / N as f64;
    for p in &mut f.positions {
        if p.x > 0.0 {
            p.x = xe;
        }
    }
    s.meshes.push(f);
    let mut c = probe_camera(0.0, 0.0);
    c.horizontal_aperture = 40.0;
    c.vertical_aperture = 40.0;
    s.cameras.push(c);
    // A DistantLight shines along its −Z axis: turn −Z to −Y (straight down).
    let down = DMat4::from_rotation_x(-std::f64::consts::FRAC_PI_2);
    assert!((down.transform_vector3(DVec3::NEG_Z) - DVec3::NEG_Y).length() < 1e-12);
    s.lights.push(Light::with_defaults(
        "/Sun",
        LightShape::Distant { angle_deg: 0.53 },
        down,
    ));
    s
}

fn opts(spp: u32, seed: u64, adaptive: AdaptiveSampling) -> RenderOptions {
    let mut o = options(Profile::HdEmbree, spp, [N, N]);
    o.seed = seed;
    o.adaptive = Some(adaptive);
    o
}

fn render(scene: &Scene, o: RenderOptions) -> (ImageRgba, RenderStats) {
    Renderer::new(scene, o).unwrap().render(&|_| {})
}

fn px(img: &ImageRgba, x: u32, y: u32) -> [f32; 4] {
    img.pixels[(y * N + x) as usize]
}

#[test]
fn extra_samples_go_to_the_edge_only() {
    let scene = edge_scene();
    let a = AdaptiveSampling::DEFAULT;
    let (uniform, us) = render(&scene, opts(2, 1, AdaptiveSampling::OFF));
    let (adaptive, st) = render(&scene, opts(2, 1, a));
    assert_eq!(us.adaptive_samples, 0);
    assert_eq!(us.samples, (N * N * 2) as u64);
    assert_eq!(st.samples, (N * N * 2) as u64 + st.adaptive_samples);
    // Columns 15–17 see the edge among their neighbours; each of their N pixels takes at most
    // max_factor × spp samples.
    let most = 3 * N as u64 * (a.max_factor as u64 - 1) * 2;
    assert!(
        st.adaptive_samples > N as u64 && st.adaptive_samples <= most,
        "{} extra samples",
        st.adaptive_samples
    );
    for y in 0..N {
        for x in 0..N {
            let (u, v) = (px(&uniform, x, y), px(&adaptive, x, y));
            if (15..=17).contains(&x) {
                continue;
            }
            // Elsewhere the neighbourhood is flat: no extra sample, the same bits.
            assert_eq!(u.map(f32::to_bits), v.map(f32::to_bits), "pixel ({x}, {y})");
        }
        // The edge column takes extra samples (it cannot stay at its 2-sample value).
        assert_ne!(px(&uniform, 16, y), px(&adaptive, 16, y), "row {y}");
    }
    // The lit floor is lit (not a vacuous comparison) and the empty side empty.
    assert!(px(&adaptive, 4, 4)[0] > 0.01 && px(&adaptive, 4, 4)[3] == 1.0);
    assert_eq!(px(&adaptive, 28, 4), [0.0; 4]);
}

/// From 2 first samples and from 1.
#[test]
fn the_edge_column_is_unbiased_and_sharper() {
    for spp in [2, 1] {
        the_edge_column_is_unbiased_and_sharper_from(spp);
    }
}

fn the_edge_column_is_unbiased_and_sharper_from(spp: u32) {
    let scene = edge_scene();
    // The lit floor's colour, from the fully covered column 8 (every sample sees it).
    let (reference, _) = render(&scene, opts(4, 99, AdaptiveSampling::OFF));
    let lit = px(&reference, 8, 8)[0] as f64;
    assert!(lit > 0.01);
    let cover = EDGE - EDGE.floor();
    let (mut sum_a, mut sum_r, mut sq, mut sq_uniform, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for seed in 0..16 {
        let (img, _) = render(&scene, opts(spp, seed, AdaptiveSampling::DEFAULT));
        let (uni, _) = render(&scene, opts(spp, seed, AdaptiveSampling::OFF));
        for y in 0..N {
            let p = px(&img, 16, y);
            sum_a += p[3] as f64;
            sum_r += p[0] as f64 / lit;
            sq += (p[3] as f64 - cover).powi(2);
            sq_uniform += (px(&uni, 16, y)[3] as f64 - cover).powi(2);
            n += 1.0;
        }
    }
    let (mean_a, mean_r) = (sum_a / n, sum_r / n);
    let rms = (sq / n).sqrt();
    // Unbiased: the mean coverage is 0.3 within 4 standard errors (the per-pixel RMS error
    // bounds the spread).
    let se = rms / n.sqrt();
    assert!(
        (mean_a - cover).abs() <= 4.0 * se + 1e-6,
        "spp {spp}: alpha {mean_a} vs {cover} (se {se})"
    );
    assert!(
        (mean_r - cover).abs() <= 4.0 * se + 1e-4,
        "spp {spp}: colour {mean_r} vs {cover} (se {se})"
    );
    // With 2 stratified samples the coverage error is up to 1/2 (with 1, 0.3 or 0.7); with
    // the edge's 16 × spp it is about 16 × smaller. Require 4 ×.
    let rms_uniform = (sq_uniform / n).sqrt();
    assert!(
        rms * 4.0 < rms_uniform,
        "spp {spp}: rms {rms} vs uniform {rms_uniform}"
    );
}

/// Bands of rows and a single thread give the whole frame's bits: by the perceived measure
/// (3 × 3 neighbours, from 2 samples and from 1) on the luxtest sphere, and by the linear
/// one (7 × 7 neighbours and the frame pilot) with adaptive splitting on the path-traced
/// Cornell box and sphere.
#[test]
fn bands_and_threads_give_the_bits_of_the_whole_frame() {
    let sphere = {
        let mut o = options(Profile::HdEmbree, 2, [48, 48]);
        o.adaptive = Some(AdaptiveSampling::DEFAULT);
        (load_sphere(), o)
    };
    let sphere1 = {
        let mut o = options(Profile::HdEmbree, 1, [48, 48]);
        o.adaptive = Some(AdaptiveSampling::DEFAULT);
        (load_sphere(), o)
    };
    let cornell = {
        let mut o = options(Profile::Spec, 2, [48, 48]);
        assert_eq!(o.adaptive(), AdaptiveSampling::PATH);
        o.max_depth = 3;
        (load_cornell(), o)
    };
    // The sphere path-traced, as the farm check renders it (48 × 32, two bands): adaptive
    // splitting reads the rays of the neighbours' first samples, and the tiles that see only
    // the background, which a band cuts elsewhere, count theirs too.
    let sphere_path = {
        let mut o = options(Profile::Spec, 4, [48, 32]);
        assert_eq!(o.adaptive(), AdaptiveSampling::PATH);
        o.seed = 3;
        (load_sphere(), o)
    };
    for (scene, o) in [sphere, sphere1, cornell, sphere_path] {
        let [w, h] = o.resolution.unwrap();
        let whole = Renderer::new(&scene, o.clone()).unwrap();
        let (full, st) = whole.render(&|_| {});
        assert!(st.adaptive_samples > 0, "the frame takes extra samples");
        let bits = |p: &[f32; 4]| p.map(f32::to_bits);
        for rows in [[0, 7], [7, 19], [19, h], [23, 24], [0, h / 2], [h / 2, h]] {
            let mut r = Renderer::new(&scene, o.clone()).unwrap();
            r.restrict_rows(rows);
            let (band, _) = r.render(&|_| {});
            for y in 0..h {
                for x in 0..w {
                    let i = (y * w + x) as usize;
                    let want = if (rows[0]..rows[1]).contains(&y) {
                        bits(&full.pixels[i])
                    } else {
                        [0; 4]
                    };
                    assert_eq!(
                        bits(&band.pixels[i]),
                        want,
                        "{:?}: rows {rows:?}, pixel ({x}, {y})",
                        o.integrator
                    );
                }
            }
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| whole.render(&|_| {}).0);
        assert!(
            one.pixels
                .iter()
                .zip(&full.pixels)
                .all(|(a, b)| bits(a) == bits(b))
        );
    }
}

#[test]
fn progress_counts_every_pixel_once_per_pass() {
    let scene = edge_scene();
    for (adaptive, passes) in [(AdaptiveSampling::DEFAULT, 2), (AdaptiveSampling::OFF, 1)] {
        let r = Renderer::new(&scene, opts(2, 0, adaptive)).unwrap();
        assert_eq!(r.progress_total(), (N * N * passes) as u64);
        let done = std::sync::atomic::AtomicU64::new(0);
        r.render(&|n| {
            done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        });
        assert_eq!(done.into_inner(), r.progress_total());
    }
}

fn load_cornell() -> Scene {
    let p = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/cornell/cornell.usda");
    lux::usd::load_stage(p, 1.0).unwrap()
}

fn load_sphere() -> Scene {
    let p = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/luxtest/usd/sphere.usda");
    lux::usd::load_stage(p, 1.0).unwrap()
}

#[test]
fn on_by_default_with_lux_sampling_only() {
    use lux::render::settings::{IntegratorKind, SamplingMode};
    let mut o = options(Profile::HdEmbree, 4, [N, N]);
    assert_eq!(o.integrator, IntegratorKind::Direct);
    assert_eq!(o.adaptive(), AdaptiveSampling::DEFAULT);
    o.sampling = SamplingMode::Reference;
    assert_eq!(o.adaptive(), AdaptiveSampling::OFF);
    let mut p = options(Profile::Spec, 4, [N, N]);
    assert_eq!(p.integrator, IntegratorKind::Path);
    assert_eq!(p.adaptive(), AdaptiveSampling::PATH);
    assert_eq!(p.adaptive().measure, NoiseMeasure::Linear);
    p.adaptive = Some(AdaptiveSampling::DEFAULT);
    assert_eq!(p.adaptive(), AdaptiveSampling::DEFAULT);
    p.adaptive = None;
    p.integrator = IntegratorKind::Light;
    assert_eq!(p.adaptive(), AdaptiveSampling::OFF);
    // An invalid threshold or factor is an error naming it.
    let scene = edge_scene();
    for (bad, what) in [
        (
            AdaptiveSampling {
                threshold: 0.0,
                max_factor: 4,
                ..AdaptiveSampling::DEFAULT
            },
            "adaptive threshold 0",
        ),
        (
            AdaptiveSampling {
                threshold: f64::NAN,
                max_factor: 4,
                ..AdaptiveSampling::DEFAULT
            },
            "adaptive threshold NaN",
        ),
        (
            AdaptiveSampling {
                threshold: 0.1,
                max_factor: 0,
                ..AdaptiveSampling::DEFAULT
            },
            "adaptive max factor 0",
        ),
    ] {
        let e = Renderer::new(&scene, opts(4, 0, bad))
            .err()
            .expect(what)
            .to_string();
        assert!(e.contains(what), "{e}");
    }
}
