//! Many-lights benchmark: what a sample costs with 1,000 small area lights against one.
//!
//! A 40 × 40 floor with a grid of blocks on it, lit from above by `N` small lights (rect, disk
//! and sphere in turn, on a jittered grid, varied colours and intensities), seen by a
//! perspective camera; the one-light scene has the same geometry and a single light. Both are
//! rendered at 256 × 256 with the `spec` profile's direct integrator and the light BVH choosing
//! one light per shading point (`--light-selection bvh`; MIS with a BSDF ray that finds the
//! area lights it crosses through the BVH of light shapes), then with the default selection
//! (`auto`: a single light is sampled alone, without a BSDF ray). Prints time per sample and
//! the ratio many / one (the issue's bound is 3).
//!
//! ```sh
//! cargo run --release --example many_lights -- [LIGHTS=1000] [SPP=16]
//! ```

use glam::{DMat4, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::light::LightSelection;
use lux::render::render::{RenderOptions, Renderer};
use lux::usd::{Camera, Light, Mesh, Scene};

/// A deterministic number in [0, 1) from an integer (SplitMix64's finaliser).
fn hash01(i: u64) -> f64 {
    let mut x = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (x ^ (x >> 31)) as f64 / 18_446_744_073_709_551_616.0
}

fn quad(path: &str, c: DVec3, sx: f64, sz: f64, y: f64) -> Mesh {
    Mesh::new(
        path,
        vec![
            DVec3::new(c.x - sx, y, c.z - sz),
            DVec3::new(c.x - sx, y, c.z + sz),
            DVec3::new(c.x + sx, y, c.z + sz),
            DVec3::new(c.x + sx, y, c.z - sz),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// The floor, a grid of raised blocks (tops at y = 0.5) and the camera.
fn geometry() -> Scene {
    let mut s = Scene::empty("many_lights.usda");
    s.meshes.push(quad("/Floor", DVec3::ZERO, 20.0, 20.0, 0.0));
    for i in 0..10 {
        for j in 0..10 {
            let c = DVec3::new(-18.0 + 4.0 * i as f64, 0.0, -18.0 + 4.0 * j as f64);
            s.meshes
                .push(quad(&format!("/Block_{i}_{j}"), c, 0.6, 0.6, 0.5));
        }
    }
    // Looking down at the floor from above one side.
    let cam = DMat4::from_translation(DVec3::new(0.0, 28.0, 30.0))
        * DMat4::from_rotation_x(-(28.0f64 / 30.0).atan());
    s.cameras.push(Camera::with_defaults("/Camera", cam));
    s
}

/// `n` small lights 3 units above the floor on a jittered grid, aimed down.
fn lights(n: usize) -> Vec<Light> {
    let side = (n as f64).sqrt().ceil() as usize;
    let pitch = 38.0 / side as f64;
    let down = DMat4::from_rotation_x(-std::f64::consts::FRAC_PI_2);
    (0..n)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            let p = DVec3::new(
                -19.0 + pitch * (i as f64 + 0.25 + 0.5 * hash01(3 * k as u64)),
                2.5 + hash01(3 * k as u64 + 1),
                -19.0 + pitch * (j as f64 + 0.25 + 0.5 * hash01(3 * k as u64 + 2)),
            );
            let m = DMat4::from_translation(p) * down;
            let shape = match k % 3 {
                0 => LightShape::Rect {
                    width: 0.2,
                    height: 0.1,
                },
                1 => LightShape::Disk { radius: 0.08 },
                _ => LightShape::Sphere { radius: 0.06 },
            };
            let mut l = Light::with_defaults(format!("/Light_{k}"), shape, m);
            l.params.intensity = 20.0 * (0.5 + hash01(7 * k as u64));
            l.params.color = DVec3::new(
                0.6 + 0.4 * hash01(11 * k as u64),
                0.6 + 0.4 * hash01(13 * k as u64),
                0.6 + 0.4 * hash01(17 * k as u64),
            );
            l
        })
        .collect()
}

/// Seconds per sample of a render of `scene` (best of 3).
fn per_sample(scene: &Scene, spp: u32, selection: LightSelection) -> (f64, f64) {
    let mut best = f64::INFINITY;
    let mut mean = 0.0;
    for seed in 0..3 {
        let mut o = RenderOptions::new(ResolvedProfile {
            profile: Profile::Spec,
            source: ProfileSource::CommandLine,
        });
        o.spp = spp;
        o.resolution = Some([256, 256]);
        o.seed = seed;
        o.selection = selection;
        let r = Renderer::new(scene, o).expect("scene prepares");
        let (img, stats) = r.render(&|_| {});
        best = best.min(stats.seconds / stats.samples as f64);
        mean = img.pixels.iter().map(|p| p[1] as f64).sum::<f64>() / img.pixels.len() as f64;
    }
    (best, mean)
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(1000);
    let spp = args.get(1).copied().unwrap_or(16) as u32;
    println!(
        "threads: {}; 256×256, {spp} spp",
        rayon::current_num_threads()
    );
    let mut one = geometry();
    one.lights = lights(1);
    let mut many = geometry();
    many.lights = lights(n);
    for (label, sel) in [("bvh", LightSelection::Bvh), ("auto", LightSelection::Auto)] {
        let (t1, m1) = per_sample(&one, spp, sel);
        let (tn, mn) = per_sample(&many, spp, sel);
        println!(
            "selection {label}: 1 light {:.1} ns/sample (image mean {m1:.4})",
            t1 * 1e9
        );
        println!(
            "selection {label}: {n} lights {:.1} ns/sample (image mean {mn:.4})",
            tn * 1e9
        );
        println!(
            "selection {label}: cost ratio {n} / 1 lights: {:.2}",
            tn / t1
        );
    }
}
