//! Fuzz target: any `.usda` text either loads into a `Scene` or gives a typed `LoadError`
//! (never a panic), at an integer and a fractional frame; a loaded scene is internally
//! consistent (triangle indices in range, one per-corner value per triangle, material and
//! light indices in range). The text is loaded from memory (`load_usda_str`), with reduced
//! size limits so that no input can allocate gigabytes. Seed it with `./seed.sh` (the luxtest
//! scenes and the lux-render scene tests).
#![no_main]

use libfuzzer_sys::fuzz_target;
use lux_usd::{LoadOptions, Scene, load_usda_str};

fn check(s: &Scene) {
    for m in &s.meshes {
        let n = m.positions.len();
        assert!(m.triangles.iter().flatten().all(|&k| (k as usize) < n));
        let t = m.triangles.len();
        assert!(m.normals.as_ref().is_none_or(|v| v.len() == t));
        assert!(m.colors.as_ref().is_none_or(|v| v.len() == t));
        assert!(m.uvs.as_ref().is_none_or(|v| v.len() == t));
        assert!(m.material.is_none_or(|i| i < s.materials.len()));
        assert!(m.light.is_none_or(|i| i < s.lights.len()));
    }
    for l in &s.lights {
        assert!(l.params.intensity.is_finite());
        assert!(l.params.color.is_finite());
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let mut options = LoadOptions::default();
    options.max_array_len = 1 << 16;
    options.max_depth = 64;
    for frame in [1.0, 2.5] {
        if let Ok(scene) = load_usda_str(&text, frame, &options) {
            check(&scene);
        }
    }
});
