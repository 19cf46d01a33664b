//! The bundled demo scene (`scenes/demo`: every UsdLux light kind, an IES profile, a textured
//! rect light and a textured dome), embedded in the binary so that an installed `lux` renders
//! it too: from the source tree when it is there, else from a copy written to a temporary
//! folder.

use std::path::{Path, PathBuf};

/// The scene's files, name and contents.
const FILES: [(&str, &[u8]); 4] = [
    ("demo.usda", include_bytes!("../../scenes/demo/demo.usda")),
    (
        "demo_spot.ies",
        include_bytes!("../../scenes/demo/demo_spot.ies"),
    ),
    (
        "sky_latlong.exr",
        include_bytes!("../../scenes/demo/sky_latlong.exr"),
    ),
    (
        "stained_glass.png",
        include_bytes!("../../scenes/demo/stained_glass.png"),
    ),
];

/// The demo's `.usda`: in the source tree if it exists there, else in `fallback_dir`, where
/// the embedded files are written (an existing identical copy is reused).
pub fn scene_path(fallback_dir: &Path) -> Result<PathBuf, String> {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo/demo.usda");
    if source.is_file() {
        return Ok(source);
    }
    write_copy(fallback_dir)
}

/// Writes the embedded scene into `dir` (created if needed) and returns its `.usda`.
pub fn write_copy(dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the demo folder: {e}", dir.display()))?;
    for (name, bytes) in FILES {
        let p = dir.join(name);
        if std::fs::read(&p).is_ok_and(|old| old == bytes) {
            continue;
        }
        std::fs::write(&p, bytes)
            .map_err(|e| format!("{}: cannot write the demo scene: {e}", p.display()))?;
    }
    Ok(dir.join(FILES[0].0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_copy_equals_the_source_tree() {
        let dir = std::env::temp_dir().join(format!("lux-demo-test-{}", std::process::id()));
        let usda = write_copy(&dir).unwrap();
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo");
        for (name, _) in FILES {
            assert_eq!(
                std::fs::read(dir.join(name)).unwrap(),
                std::fs::read(src.join(name)).unwrap(),
                "{name}"
            );
        }
        // the copy loads with its textures and IES profile resolved next to it
        let scene = lux_usd::load_stage(&usda, 1.0).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert!(scene.lights.iter().all(|l| {
            l.texture
                .as_ref()
                .is_none_or(|t| t.resolved.as_ref().is_some_and(|p| p.starts_with(&dir)))
        }));
        // a second write reuses the identical files
        assert_eq!(write_copy(&dir).unwrap(), usda);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
