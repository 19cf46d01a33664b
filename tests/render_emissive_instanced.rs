//! Emissive geometry inside instanced prototypes lights the scene: each instance of a mesh
//! whose material emits is a light, as if the mesh had been written out in world space under
//! that instance's transform (native instancing and UsdGeomPointInstancer).
//!
//! The stages are `tests/data/emissive_instanced/*.usda`; `usd_core_facts.json` there is what
//! usd-core composes from them (`usd_core_facts.py`): instances, prototypes and every emitter's
//! world corners, emission and front side. The tests check that lux composes the same, that
//! the instanced stages render bit for bit as their flattened twins (flattened by lux-usd, or
//! in code the way flattening maps a mesh), or within `f32` rounding of the twin usd-core
//! flattened, and that one instance's light on a Lambertian floor point is the polygon's
//! closed form `E = L·Π` within the estimate's own standard error.

mod common;

use common::{options, probe_camera};
use glam::DVec3;
use lux::math::Profile;
use lux::render::geometry::Hit;
use lux::render::light::LightSelection;
use lux::render::render::Renderer;
use lux::render::settings::IntegratorKind;
use lux::sample::{Reference, SplitMix64, Strategy};
use lux::usd::{Scene, load_stage};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/emissive_instanced")
        .join(name)
}

fn load(name: &str) -> Scene {
    load_stage(data(name), 1.0).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// What usd-core composes from the stage `name`.
fn facts(name: &str) -> Value {
    let text = std::fs::read_to_string(data("usd_core_facts.json")).unwrap();
    let all: Value = serde_json::from_str(&text).unwrap();
    all[name].clone()
}

fn v3(v: &Value) -> DVec3 {
    DVec3::new(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

/// One emitter as usd-core composes it.
struct Emitter {
    path: String,
    emissive: DVec3,
    corners: Vec<DVec3>,
    double_sided: bool,
    front: DVec3,
}

fn emitters(name: &str) -> Vec<Emitter> {
    facts(name)["emitters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| Emitter {
            path: e["path"].as_str().unwrap().to_owned(),
            emissive: v3(&e["emissive"]),
            corners: e["corners"].as_array().unwrap().iter().map(v3).collect(),
            double_sided: e["double_sided"].as_bool().unwrap(),
            front: v3(&e["front"]),
        })
        .collect()
}

/// Renders `s` (`w × h`, 16 spp) on `threads` threads: the pixels, after checking that
/// preparing it warned about nothing.
fn render(
    s: &Scene,
    kind: IntegratorKind,
    selection: LightSelection,
    threads: usize,
) -> Vec<[f32; 4]> {
    let mut o = options(Profile::Spec, 16, [64, 48]);
    o.integrator = kind;
    o.selection = selection;
    o.max_depth = 3;
    // Sample for sample: the closed form of a light nothing can block is proven over
    // world-space triangles only, so an instanced stage and its flattened twin would take
    // different (equally exact) estimators where it applies.
    o.visibility = lux::render::settings::VisibilityMode::Rays;
    let r = Renderer::new(s, o).unwrap();
    let warnings: Vec<&String> = r.warnings().collect();
    assert!(warnings.is_empty(), "{warnings:?}");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let (img, stats) = pool.install(|| r.render(&|_| {}));
    assert_eq!(stats.non_finite_samples, 0);
    img.pixels
}

/// `s` with every instance's prototype meshes written out in world space, in instance order,
/// as flattening maps a mesh (`Mesh::transformed`), named by their instance geometry path
/// (what light linking judges) and bound to their own material, else their instance's.
fn flatten(s: &Scene) -> Scene {
    let mut f = Scene {
        prototypes: Vec::new(),
        instances: Vec::new(),
        meshes: s
            .meshes
            .iter()
            .filter(|m| m.prototype.is_none())
            .cloned()
            .collect(),
        ..s.clone()
    };
    for (ii, inst) in s.instances.iter().enumerate() {
        for (mi, m) in s.meshes.iter().enumerate() {
            if m.prototype == Some(inst.prototype) {
                let mut w = m.transformed(&inst.to_world);
                w.prototype = None;
                w.material = m.material.or(inst.material);
                w.path = s.geometry_path(mi, Some(ii)).into_owned();
                f.meshes.push(w);
            }
        }
    }
    f
}

/// Emission (RGB) of the scene's bound material.
fn emission_of(s: &Scene, material: Option<usize>) -> DVec3 {
    material.map_or(DVec3::ZERO, |k| s.materials[k].emissive)
}

/// The lights of `a` (instanced) and `b` (flattened) are the same maths, bit for bit: power,
/// selection bounds, light samples (radiance, direction, density, distance, point) and the
/// density a ray through each triangle gives, from floor points in every direction around
/// the emitters; and rays from those points meet the same triangle at the same `t` in both.
fn assert_same_lights_and_hits(a: &Scene, b: &Scene, what: &str) {
    let o = options(Profile::Spec, 1, [4, 3]);
    let (ra, rb) = (
        Renderer::new(a, o.clone()).unwrap(),
        Renderer::new(b, o).unwrap(),
    );
    let (la, lb) = (&ra.lights().lights, &rb.lights().lights);
    assert_eq!(la.len(), lb.len(), "{what}");
    let mut rng = SplitMix64::new(7);
    let (mut samples, mut hits) = (0, 0);
    for (x, y) in la.iter().zip(lb) {
        assert_eq!(x.base().power, y.base().power, "{what}: {}", x.base().path);
        assert_eq!(x.bounds(), y.bounds(), "{what}: {}", x.base().path);
        for _ in 0..2000 {
            let [u, v] = rng.next_2d();
            let p = DVec3::new(6.0 * u - 3.0, 0.0, 6.0 * v - 3.0);
            let r = Reference::surface(p, DVec3::Y);
            let uv = rng.next_2d();
            let (sx, sy) = (
                x.sample_li(&r, uv, Strategy::Lux),
                y.sample_li(&r, uv, Strategy::Lux),
            );
            assert_eq!(sx, sy, "{what}: {} from {p}", x.base().path);
            let Some(ls) = sx else { continue };
            samples += 1;
            for tri in 0..2 {
                assert_eq!(
                    x.pdf_li_triangle(&r, tri, ls.wi).to_bits(),
                    y.pdf_li_triangle(&r, tri, ls.wi).to_bits(),
                    "{what}"
                );
            }
            let o = p + DVec3::Y * 1e-4;
            let (hx, hy) = (
                ra.geometry()
                    .intersect_any_side(a, o, ls.wi, 0.0, f64::INFINITY),
                rb.geometry()
                    .intersect_any_side(b, o, ls.wi, 0.0, f64::INFINITY),
            );
            let key = |s: &Scene, h: Hit| {
                (
                    s.geometry_path(h.mesh, h.instance).into_owned(),
                    h.tri,
                    h.t.to_bits(),
                    h.back,
                )
            };
            let (kx, ky) = (hx.map(|h| key(a, h)), hy.map(|h| key(b, h)));
            assert_eq!(kx, ky, "{what}: ray from {o} along {}", ls.wi);
            // The ray finds the emitter's light in both.
            let li = |r: &Renderer, h: Option<Hit>| {
                h.and_then(|h| r.lights().light_of(h.mesh, h.instance))
            };
            assert_eq!(li(&ra, hx), li(&rb, hy), "{what}");
            hits += usize::from(hx.is_some());
        }
    }
    assert!(
        samples > 5000 && hits > 5000,
        "{what}: {samples} samples, {hits} hits"
    );
}

/// Renders `a` and `b` (the same scene, instanced and flattened) with the direct integrator
/// (every light; the light BVH) and the path integrator, and compares them pixel by pixel.
///
/// The lights and the hits are the same bits (see [`assert_same_lights_and_hits`]); what is
/// not is the ray clearance of a hit on an instance (`Hit::offset`: at least the world one,
/// an ulp more near the origin through the rounding of `Placement::stretch`, more for a
/// scaled instance), so secondary rays from instanced surfaces start a hair apart — and the
/// `f32` traversal runs in prototype space for an instance, in world space for its twin, which
/// can turn a ray grazing an edge. Pixels seen through such rays differ: by rounding mostly,
/// rarely by a sample (`level_instances_render_as_their_flattened_twins_bit_for_bit` has
/// none of these). The test: at most 1 % of the pixels differ by more than 1e-4, and the mean
/// difference over the image is within 4 of its standard errors of zero in every channel
/// (pixels are independent estimates; their differences' spread gives the error), or below
/// 1e-6 of the image mean (rounding).
fn assert_renders_agree(a: &Scene, b: &Scene, what: &str) {
    for (kind, selection) in [
        (IntegratorKind::Direct, LightSelection::All),
        (IntegratorKind::Direct, LightSelection::Bvh),
        (IntegratorKind::Path, LightSelection::Auto),
    ] {
        let (x, y) = (render(a, kind, selection, 2), render(b, kind, selection, 2));
        let n = x.len() as f64;
        let differ = x.iter().zip(&y).filter(|(p, q)| p != q).count();
        // Pixels that differ by more than the rounding of continuous differences.
        let flipped = x
            .iter()
            .zip(&y)
            .filter(|(p, q)| {
                (0..3).any(|k| (p[k] - q[k]).abs() > 1e-4 * p[k].abs().max(q[k].abs()))
            })
            .count();
        let lit = x.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
        assert!(lit > x.len() / 2, "{what}: {lit} lit pixels");
        let mut z = [0.0; 3];
        for (k, zk) in z.iter_mut().enumerate() {
            let d: Vec<f64> = x
                .iter()
                .zip(&y)
                .map(|(p, q)| p[k] as f64 - q[k] as f64)
                .collect();
            let mean = d.iter().sum::<f64>() / n;
            let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let mean_of = x.iter().map(|p| p[k] as f64).sum::<f64>() / n;
            *zk = if var > 0.0 {
                mean / (var / n).sqrt()
            } else {
                0.0
            };
            println!(
                "{what}, {kind:?}/{selection:?}, channel {k}: image mean {mean_of:.6}, mean \
                 difference {mean:.3e} = {:.2} standard errors",
                *zk
            );
            assert!(
                zk.abs() <= 4.0 || mean.abs() <= 1e-6 * mean_of,
                "{what}, {kind:?}/{selection:?}, channel {k}"
            );
        }
        println!(
            "{what}, {kind:?}/{selection:?}: {differ} of {n} pixels differ, {flipped} by more \
             than 1e-4"
        );
        assert!(flipped * 100 <= x.len(), "{what}: {flipped} pixels differ");
    }
}

#[test]
fn lux_composes_the_stages_as_usd_core_does() {
    for name in ["native.usda", "pointinstancer.usda"] {
        let s = load(name);
        let f = facts(name);
        let native = f["native_instances"].as_array().unwrap();
        let points = f["point_instances"].as_u64().unwrap() as usize;
        assert_eq!(
            s.instances.len(),
            native.len() + points,
            "{name}: instances"
        );
        assert_eq!(s.gprims.native_instances, native.len(), "{name}");
        assert_eq!(s.gprims.point_instances, points, "{name}");
        for (inst, n) in s.instances.iter().zip(native) {
            assert_eq!(inst.path, n[0].as_str().unwrap(), "{name}");
        }
        // Native instances sharing a usd-core prototype share a lux prototype.
        for (i, a) in native.iter().enumerate() {
            for (j, b) in native.iter().enumerate() {
                assert_eq!(
                    a[1] == b[1],
                    s.instances[i].prototype == s.instances[j].prototype,
                    "{name}: {a} {b}"
                );
            }
        }
        // Every emitter: an (instance, prototype mesh) of that emission whose world
        // corners are usd-core's. Instances are in usd-core's order; meshes in prototype order.
        let mut lux_emitters = Vec::new();
        for (ii, inst) in s.instances.iter().enumerate() {
            for (mi, m) in s.meshes.iter().enumerate() {
                let e = emission_of(&s, m.material.or(inst.material));
                if m.prototype == Some(inst.prototype) && e.max_element() > 0.0 {
                    lux_emitters.push((ii, mi, e));
                }
            }
        }
        let want = emitters(name);
        assert_eq!(lux_emitters.len(), want.len(), "{name}: emitters");
        for (&(ii, mi, e), w) in lux_emitters.iter().zip(&want) {
            let m = &s.meshes[mi];
            assert_eq!(e, w.emissive, "{}", w.path);
            assert_eq!(m.double_sided, w.double_sided, "{}", w.path);
            assert!(
                w.path.ends_with(&*s.geometry_path(mi, Some(ii))),
                "{} vs {}",
                w.path,
                s.geometry_path(mi, Some(ii))
            );
            let corners: Vec<DVec3> = m
                .positions
                .iter()
                .map(|p| s.instances[ii].to_world.transform_point3(*p))
                .collect();
            for (c, wc) in corners.iter().zip(&w.corners) {
                assert!((*c - *wc).length() < 1e-12, "{}: {c} vs {wc}", w.path);
            }
        }
        // The renderer makes one light per emitter, and nothing else warns.
        let r = Renderer::new(&s, options(Profile::Spec, 1, [4, 3])).unwrap();
        assert_eq!(r.lights().instanced_count(), want.len(), "{name}");
        let warnings: Vec<&String> = r.warnings().collect();
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
    }
    // The usd-core flattening of the point instancer has the same emitters, in world space.
    let flat = load("pointinstancer_flat.usda");
    assert!(flat.instances.is_empty() && flat.prototypes.is_empty());
    let (a, b) = (
        emitters("pointinstancer.usda"),
        emitters("pointinstancer_flat.usda"),
    );
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.corners, y.corners, "{} vs {}", x.path, y.path);
        assert_eq!(x.emissive, y.emissive);
    }
}

#[test]
fn native_instances_light_as_their_flattened_stage() {
    let s = load("native.usda");
    // The same stage without instancing: lux-usd maps every mesh to the world itself.
    let text = std::fs::read_to_string(data("native.usda")).unwrap();
    assert_eq!(text.matches("instanceable = true").count(), 7);
    let dir = std::env::temp_dir().join(format!("lux-emissive-native-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let flat_file = dir.join("native_flat.usda");
    std::fs::write(
        &flat_file,
        text.replace("instanceable = true", "instanceable = false"),
    )
    .unwrap();
    let flat = load_stage(&flat_file, 1.0).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert!(flat.instances.is_empty());
    // Same lights, in the same order: 1 rect light and 6 emitters (C is mirrored, D and G
    // face up, F does not emit).
    let (ra, rb) = (
        Renderer::new(&s, options(Profile::Spec, 1, [4, 3])).unwrap(),
        Renderer::new(&flat, options(Profile::Spec, 1, [4, 3])).unwrap(),
    );
    let paths = |r: &Renderer| -> Vec<String> {
        r.lights()
            .lights
            .iter()
            .map(|l| l.base().path.clone())
            .collect()
    };
    assert_eq!(paths(&ra), paths(&rb));
    assert_eq!(ra.lights().lights.len(), 7);
    assert_eq!(ra.lights().instanced_count(), 6);
    // Determinism: the same bits for any thread count.
    assert_eq!(
        render(&s, IntegratorKind::Direct, LightSelection::Bvh, 1),
        render(&s, IntegratorKind::Direct, LightSelection::Bvh, 2)
    );
    assert_same_lights_and_hits(&s, &flat, "native vs lux-usd flattened");
    assert_renders_agree(&s, &flat, "native vs lux-usd flattened");
}

#[test]
fn point_instances_light_as_their_flattened_stage() {
    let s = load("pointinstancer.usda");
    assert_eq!(
        render(&s, IntegratorKind::Path, LightSelection::Auto, 1),
        render(&s, IntegratorKind::Path, LightSelection::Auto, 2)
    );
    // Flattened in code by the transforms lux composed: the same maths, the same bits.
    let f = flatten(&s);
    assert_same_lights_and_hits(&s, &f, "point instances vs flattened in code");
    assert_renders_agree(&s, &f, "point instances vs flattened in code");
    // Flattened by usd-core (its instance matrices, read back exactly): the same geometry up
    // to the rounding of the two transform computations (~1e-16 in the corners).
    let flat = load("pointinstancer_flat.usda");
    assert_renders_agree(&s, &flat, "point instances vs usd-core flattened");
}

/// The lux scene of `name` keeping only the instance `instance` (its path) and no
/// UsdLux light: the emitter alone above the floor.
fn only_instance(name: &str, instance: &str) -> Scene {
    let mut s = load(name);
    let keep = s
        .instances
        .iter()
        .position(|i| i.path == instance)
        .unwrap_or_else(|| panic!("{instance}"));
    s.instances = vec![s.instances[keep].clone()];
    s.lights.clear();
    s
}

/// The floor's reflected radiance at `(x, 0, z)` (albedo 1: `E/π`), estimated by `n`
/// independent pixels of `spp` samples each that all see that point: the mean and its
/// standard error per channel.
fn probe(s: &Scene, x: f64, z: f64) -> (DVec3, DVec3) {
    let (n, spp) = (64u32, 256u32);
    let mut s = s.clone();
    let mut cam = probe_camera(x, z);
    cam.horizontal_aperture = 1e-6 * n as f64;
    cam.vertical_aperture = 1e-6;
    // The camera is 10 units up; its rays start 0.4 above the floor, below every emitter, so
    // that they meet the floor point under an emitter rather than the emitter.
    cam.clipping_range = glam::DVec2::new(9.6, 1e6);
    s.cameras = vec![cam];
    let mut o = options(Profile::Spec, spp, [n, 1]);
    o.integrator = IntegratorKind::Direct;
    let r = Renderer::new(&s, o).unwrap();
    assert_eq!(r.lights().lights.len(), r.lights().instanced_count());
    let v: Vec<DVec3> = (0..n).map(|i| r.pixel_value(i, 0).truncate()).collect();
    let nf = n as f64;
    let mean = v.iter().sum::<DVec3>() / nf;
    let var = v.iter().map(|p| (*p - mean) * (*p - mean)).sum::<DVec3>() / (nf - 1.0);
    (mean, (var / nf).sqrt())
}

/// The closed form at `(x, 0, z)` of emitter `e` alone: `L·Π/π` on the side it emits to, 0
/// on the other side of a single-sided one.
fn closed_form(e: &Emitter, x: f64, z: f64) -> DVec3 {
    let p = DVec3::new(x, 0.0, z);
    let lit = e.double_sided || e.front.dot(p - e.corners[0]) > 0.0;
    let pi = lux::irradiance::projected::polygon(p, DVec3::Y, &e.corners);
    if lit {
        e.emissive * pi / PI
    } else {
        DVec3::ZERO
    }
}

/// Checks the probe against the closed form within 4 standard errors per channel.
fn check_closed_form(name: &str, instance: &str, emitter: &str, points: &[(f64, f64)]) {
    let s = only_instance(name, instance);
    let e = emitters(name)
        .into_iter()
        .find(|e| e.path == emitter)
        .unwrap();
    for &(x, z) in points {
        let want = closed_form(&e, x, z);
        let (got, se) = probe(&s, x, z);
        println!("{emitter} at ({x}, 0, {z}): {got} ± {se}, closed form {want}");
        for k in 0..3 {
            if want[k] == 0.0 {
                assert_eq!(got[k], 0.0, "{emitter} at ({x}, {z}), channel {k}");
            } else {
                assert!(
                    se[k] > 0.0 && (got[k] - want[k]).abs() <= 4.0 * se[k],
                    "{emitter} at ({x}, {z}), channel {k}: {} vs {} (s.e. {})",
                    got[k],
                    want[k],
                    se[k]
                );
                // The bound is meaningful: a few tenths of a percent.
                assert!(se[k] < 3e-3 * want[k], "{}", se[k] / want[k]);
            }
        }
    }
}

#[test]
fn a_native_instance_lights_the_floor_as_the_polygon_closed_form() {
    // Translated, rotated and non-uniformly scaled.
    check_closed_form(
        "native.usda",
        "/World/Cards/B",
        "/World/Cards/B/Glow",
        &[(-0.8, 0.6), (-0.2, 0.0)],
    );
    // Mirrored across x: the world winding turns, the front (downwards) does not.
    check_closed_form(
        "native.usda",
        "/World/Cards/C",
        "/World/Cards/C/Glow",
        &[(1.2, -0.9), (0.5, -0.3)],
    );
    // Upside down with nothing in the way: the floor sees its back, which does not emit —
    // neither to light samples nor to BSDF rays.
    check_closed_form(
        "native.usda",
        "/World/Cards/G",
        "/World/Cards/G/Face",
        &[(0.2, 1.6)],
    );
}

#[test]
fn a_point_instance_lights_the_floor_as_the_polygon_closed_form() {
    let pi = "/World/Cards";
    // Rotated by a quaternion and non-uniformly scaled.
    check_closed_form(
        "pointinstancer.usda",
        &format!("{pi}[2]"),
        "/World/Cards[2]/World/Cards/Protos/Card/Glow",
        &[(-0.8, 0.6), (-0.3, 0.2)],
    );
    // Mirrored across x.
    check_closed_form(
        "pointinstancer.usda",
        &format!("{pi}[3]"),
        "/World/Cards[3]/World/Cards/Protos/Card/Glow",
        &[(1.2, -0.9)],
    );
    // Double-sided and vertical: both sides emit.
    check_closed_form(
        "pointinstancer.usda",
        &format!("{pi}[5]"),
        "/World/Cards[5]/World/Cards/Protos/Tile",
        &[(0.9, 0.6), (0.9, 1.4)],
    );
}

#[test]
fn the_camera_sees_an_instance_glow_on_its_front_only() {
    // G faces up: seen from above, its glow (its surface reflects nothing lit here).
    let s = only_instance("native.usda", "/World/Cards/G");
    let mut top = s.clone();
    top.cameras = vec![probe_camera(0.2, 1.6)];
    let v = Renderer::new(&top, options(Profile::Spec, 16, [1, 1]))
        .unwrap()
        .pixel_value(0, 0);
    assert_eq!(v.truncate(), DVec3::new(0.25, 0.5, 2.0));
    // A's quad faces down; its board above is black: seen from above, black.
    let s = only_instance("native.usda", "/World/Cards/A");
    let mut top = s.clone();
    top.cameras = vec![probe_camera(0.3, 0.2)];
    let v = Renderer::new(&top, options(Profile::Spec, 16, [1, 1]))
        .unwrap()
        .pixel_value(0, 0);
    assert_eq!(v.truncate(), DVec3::ZERO);
}

/// `s` keeping only the instances whose path is in `keep`.
fn with_instances(s: &Scene, keep: &[&str]) -> Scene {
    let mut s = s.clone();
    s.instances.retain(|i| keep.contains(&i.path.as_str()));
    assert_eq!(s.instances.len(), keep.len());
    s
}

#[test]
fn level_instances_render_as_their_flattened_twins_bit_for_bit() {
    // Without the tilted emitters and panels every pixel of direct lighting is the same bits
    // as the flattened twin's (light sampling, shadow rays, BSDF rays and their MIS weights).
    // C (translated, turned about y, scaled non-uniformly and mirrored) is among them. Path
    // tracing continues from instanced surfaces, whose ray clearance can be an ulp larger
    // (see `assert_renders_agree`): its pixels agree to f32 rounding.
    let native = with_instances(
        &load("native.usda"),
        &[
            "/World/Cards/A",
            "/World/Cards/C",
            "/World/Cards/D",
            "/World/Cards/F",
            "/World/Cards/G",
        ],
    );
    let pi = with_instances(
        &load("pointinstancer.usda"),
        &[
            "/World/Cards[0]",
            "/World/Cards[1]",
            "/World/Cards[3]",
            "/World/Cards[6]",
        ],
    );
    for (s, what) in [(native, "native"), (pi, "point instances")] {
        let f = flatten(&s);
        for selection in [LightSelection::All, LightSelection::Bvh] {
            let (x, y) = (
                render(&s, IntegratorKind::Direct, selection, 2),
                render(&f, IntegratorKind::Direct, selection, 1),
            );
            let differ = x.iter().zip(&y).filter(|(p, q)| p != q).count();
            assert_eq!(differ, 0, "{what}, direct, {selection:?}");
        }
        let (x, y) = (
            render(&s, IntegratorKind::Path, LightSelection::Auto, 2),
            render(&f, IntegratorKind::Path, LightSelection::Auto, 2),
        );
        let worst = x
            .iter()
            .zip(&y)
            .flat_map(|(p, q)| (0..4).map(move |k| (p[k] - q[k]).abs() / q[k].abs().max(1e-3)))
            .fold(0.0f32, f32::max);
        println!("{what}, path: worst relative difference {worst:e}");
        assert!(worst < 1e-6, "{what}, path: {worst}");
    }
}
