//! What the lights of instanced emissive geometry cost, measured by a counting allocator (this
//! test binary's global allocator, so it holds one test: the counts are not shared).
//!
//! - A point instancer of 100 000 instances of a prototype that does not emit makes no light
//!   and holds no light memory.
//! - 10 000 instances of an emissive two-triangle card make 10 000 lights: the bytes the light
//!   set holds per instance are measured and bounded (the `Light` itself is most of it).

use glam::{DMat4, DQuat, DVec3};
use lux_math::Profile;
use lux_render::geometry::Geometry;
use lux_render::light::{Light, LightOptions, LightSelection, LightSet};
use lux_usd::{Instance, Material, Mesh, Prototype, Scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(n: usize) {
    let live = LIVE.fetch_add(n, Ordering::Relaxed) + n;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

// SAFETY: every call is forwarded to the system allocator unchanged; only counters are updated.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grew(layout.size());
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size >= layout.size() {
            grew(new_size - layout.size());
        } else {
            LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A point instancer's worth of `n` instances of a 0.6 × 0.4 card (two triangles, facing −Y)
/// emitting when `emissive`, each translated, turned and scaled differently.
fn cards(n: usize, emissive: bool) -> Scene {
    let mut s = Scene::empty("cards.usda");
    s.materials.push(Material {
        emissive: if emissive {
            DVec3::new(2.0, 1.0, 0.5)
        } else {
            DVec3::ZERO
        },
        ..Material::new("/Looks/Card")
    });
    let mut card = Mesh::new(
        "/World/PI/Protos/Card/Glow",
        vec![
            DVec3::new(-0.3, 0.0, -0.2),
            DVec3::new(0.3, 0.0, -0.2),
            DVec3::new(0.3, 0.0, 0.2),
            DVec3::new(-0.3, 0.0, 0.2),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    card.material = Some(0);
    card.prototype = Some(0);
    s.meshes.push(card);
    s.prototypes.push(Prototype {
        path: "/World/PI/Protos/Card".to_owned(),
        meshes: vec![0],
    });
    let side = (n as f64).sqrt().ceil() as usize;
    for i in 0..n {
        let (x, z) = ((i % side) as f64, (i / side) as f64);
        let k = i as f64;
        s.instances.push(Instance {
            path: format!("/World/PI[{i}]"),
            prototype: 0,
            to_world: DMat4::from_scale_rotation_translation(
                DVec3::new(1.0 + 0.1 * (k * 0.37).sin(), 1.0, 0.8),
                DQuat::from_euler(glam::EulerRot::XYZ, 0.3 * k.sin(), k, 0.2 * k.cos()),
                DVec3::new(x, 2.0 + 0.5 * (k * 0.11).sin(), z),
            ),
            material: None,
        });
    }
    s
}

fn options() -> LightOptions {
    LightOptions {
        profile: Profile::Spec,
        selection: LightSelection::Auto,
        strict: false,
        cone_clipping: true,
    }
}

/// `f()` and the bytes its result holds (live after minus live before), and the peak growth
/// while it ran.
fn measured<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let out = f();
    let held = LIVE.load(Ordering::Relaxed).saturating_sub(before);
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(before);
    (out, held, peak)
}

#[test]
fn instanced_emitters_cost_what_they_say() {
    // 100 000 instances of a prototype that does not emit: no light, nothing held.
    let dark = cards(100_000, false);
    let (set, held, peak) = measured(|| LightSet::new(&dark, options()).unwrap());
    assert!(set.lights.is_empty() && set.instanced_count() == 0);
    println!("100 000 dark instances: the light set holds {held} bytes (peak {peak})");
    assert!(held < 1024 && peak < 4096, "{held} {peak}");
    drop(set);

    // 10 000 instances of an emissive card: one light each.
    let n = 10_000;
    let lit = cards(n, true);
    let (set, held, peak) = measured(|| LightSet::new(&lit, options()).unwrap());
    assert_eq!(set.lights.len(), n);
    assert_eq!(set.instanced_count(), n);
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    // More than 8 lights: chosen by the light BVH, over every instance.
    assert!(set.selector.is_some());
    let per = held as f64 / n as f64;
    println!(
        "10 000 emissive card instances: the light set holds {held} bytes, {per:.0} per \
         instance (the Light enum alone is {} bytes); peak {peak}",
        size_of::<Light>()
    );
    assert!(per >= size_of::<Light>() as f64 && per < 2600.0, "{per}");
    // The light of each instance is found from its (instance, mesh).
    for i in [0, 1, 4999, n - 1] {
        let li = set.light_of(0, Some(i)).unwrap();
        assert_eq!(
            set.lights[li].base().path,
            format!("/World/PI/Protos/Card/Glow (instance /World/PI[{i}])")
        );
    }
    assert_eq!(set.light_of(0, None), None);
    // For comparison, the geometry: the prototype once, ≈ 230 bytes per instance.
    let (g, held_g, _) = measured(|| Geometry::new(&lit));
    println!(
        "the geometry holds {held_g} bytes ({:.0} per instance; heap_bytes {})",
        held_g as f64 / n as f64,
        g.heap_bytes()
    );
}
