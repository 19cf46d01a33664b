//! `.usda`, `.usdc` and `.usdz`: `roundtrip.usda` is written out by `openusd` itself as a
//! binary crate layer (`Layer::export`) and as USDZ packages (`Layer::export` for a
//! single-layer package, `usdz::ArchiveWriter` for one that also carries the scene's assets),
//! and every form loads to the same `Scene` at every frame tested.

use lux_usd::{AssetRef, Input, Scene, WarningKind, load_stage, usda_fix};
use std::fs;
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

/// A fresh directory holding a copy of `roundtrip.usda` and the assets it names.
fn workdir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("scene_formats-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("assets")).unwrap();
    fs::copy(scenes().join("roundtrip.usda"), dir.join("roundtrip.usda")).unwrap();
    for (file, bytes) in assets() {
        fs::write(dir.join(file), bytes).unwrap();
    }
    dir
}

/// The scene's assets, made here: two tiny IES files and a 2 × 2 PNG.
fn assets() -> Vec<(&'static str, Vec<u8>)> {
    let ies = |cd: &str| {
        format!(
            "IESNA:LM-63-2002\n[TEST] lux loader test\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n{cd} {cd} 0\n"
        )
        .into_bytes()
    };
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::from_fn(2, 2, |x, y| {
        image::Rgb([(x * 255) as u8, (y * 255) as u8, 0])
    })
    .write_to(&mut png, image::ImageFormat::Png)
    .unwrap();
    vec![
        ("assets/tiny.ies", ies("100")),
        ("assets/other.ies", ies("50")),
        ("assets/grid.png", png.into_inner()),
    ]
}

/// Writes `dir/roundtrip.usdc`, `dir/roundtrip.usdz` (layer + assets) and `dir/single.usdz`
/// (layer only) with openusd's writers.
fn write_binary_forms(dir: &Path) {
    // openusd 0.6 cannot parse scalar asset time samples; the loader's own rewrite (which it
    // applies to every .usda it opens) turns them into one-element asset arrays first.
    let text = fs::read_to_string(dir.join("roundtrip.usda")).unwrap();
    let fixed = usda_fix::rewrite_asset_time_samples(&text).expect("scene has asset samples");
    let fixed_path = dir.join("roundtrip_fixed.usda");
    fs::write(&fixed_path, fixed).unwrap();
    let stage = openusd::usd::Stage::open(fixed_path.to_str().unwrap()).unwrap();
    let layer = stage.root_layer();
    layer
        .export(dir.join("roundtrip.usdc").to_str().unwrap())
        .unwrap();
    layer
        .export(dir.join("single.usdz").to_str().unwrap())
        .unwrap();
    let usdc = fs::read(dir.join("roundtrip.usdc")).unwrap();
    assert_eq!(&usdc[..8], b"PXR-USDC", "binary crate file");
    let mut w = openusd::usdz::ArchiveWriter::create(dir.join("roundtrip.usdz")).unwrap();
    w.add_layer("roundtrip.usdc", &usdc).unwrap();
    for (file, bytes) in assets() {
        w.add_layer(file, &bytes).unwrap();
    }
    w.finish().unwrap();
    assert_eq!(&fs::read(dir.join("roundtrip.usdz")).unwrap()[..2], b"PK");
}

fn for_each_asset(scene: &mut Scene, f: &mut dyn FnMut(&mut AssetRef)) {
    for l in &mut scene.lights {
        if let Some(a) = &mut l.texture {
            f(a);
        }
        if let Some(a) = l.shaping.as_mut().and_then(|s| s.ies_file.as_mut()) {
            f(a);
        }
    }
    for m in &mut scene.materials {
        if let Input::Texture(t) = &mut m.diffuse
            && let Some(a) = &mut t.file
        {
            f(a);
        }
        // The files of the material's MaterialX graph (the same texture, read as a network).
        for n in m.graph.iter_mut().flat_map(|g| g.nodes.iter_mut()) {
            for i in &mut n.inputs {
                if let lux_usd::shading::Source::Value(lux_usd::shading::Value::File(v)) =
                    &mut i.source
                {
                    f(&mut v.asset);
                }
            }
        }
        // …and of the network it was flattened from.
        for n in m.network.iter_mut().flat_map(|g| g.nodes.iter_mut()) {
            for i in &mut n.inputs {
                if let lux_usd::shading::NetSource::Value(lux_usd::shading::Value::File(v)) =
                    &mut i.source
                {
                    f(&mut v.asset);
                }
            }
        }
    }
}

/// The scene with `source` cleared and resolved asset paths reduced to the asset's path
/// inside its directory or package (`…/assets/tiny.ies` and `….usdz[assets/tiny.ies]` both
/// become `assets/tiny.ies`).
fn normalised(mut s: Scene, dir: &Path) -> Scene {
    s.source = PathBuf::new();
    let dir = dir.canonicalize().unwrap();
    for_each_asset(&mut s, &mut |a| {
        if let Some(r) = &a.resolved {
            let text = r.to_string_lossy().into_owned();
            let inner = match (text.rfind('['), text.strip_suffix(']')) {
                (Some(i), Some(t)) => PathBuf::from(&t[i + 1..]),
                _ => r
                    .canonicalize()
                    .unwrap()
                    .strip_prefix(&dir)
                    .unwrap()
                    .to_path_buf(),
            };
            a.resolved = Some(inner);
        }
    });
    s
}

/// The scene without any resolved asset path and without unresolved-asset warnings.
fn without_assets(mut s: Scene) -> Scene {
    s.source = PathBuf::new();
    for_each_asset(&mut s, &mut |a| a.resolved = None);
    s.warnings
        .retain(|w| w.kind != WarningKind::UnresolvedAsset);
    s
}

const FRAMES: [f64; 6] = [-3.0, 1.0, 1.75, 2.5, 3.0, 4.0];

#[test]
fn usdc_and_usdz_written_by_openusd_load_like_the_usda() {
    let dir = workdir("all");
    write_binary_forms(&dir);
    for frame in FRAMES {
        let load = |name: &str| {
            load_stage(dir.join(name), frame).unwrap_or_else(|e| panic!("{name} @ {frame}: {e}"))
        };
        let usda = load("roundtrip.usda");
        assert_eq!(usda.lights.len(), 9, "frame {frame}");
        assert!(usda.meshes.len() >= 9, "frame {frame}");
        // every asset of the scene resolves from the text layer
        let mut unresolved = Vec::new();
        let mut copy = usda.clone();
        for_each_asset(&mut copy, &mut |r| {
            if r.resolved.is_none() {
                unresolved.push(r.authored.clone());
            }
        });
        assert!(unresolved.is_empty(), "{unresolved:?}");
        let want = normalised(usda.clone(), &dir);
        let usdc = load("roundtrip.usdc");
        assert_eq!(normalised(usdc, &dir), want, "usdc at frame {frame}");
        let usdz = load("roundtrip.usdz");
        assert_eq!(normalised(usdz, &dir), want, "usdz at frame {frame}");
        // A package without the assets: identical except that nothing resolves.
        let mut single = load("single.usdz");
        let mut resolved = Vec::new();
        for_each_asset(&mut single, &mut |a| resolved.extend(a.resolved.clone()));
        assert!(
            resolved.is_empty(),
            "nothing to resolve in the package: {resolved:?}"
        );
        assert_eq!(
            without_assets(single),
            without_assets(usda),
            "single-layer usdz at frame {frame}"
        );
    }
}

#[test]
fn resolved_package_assets_name_the_package_entry() {
    let dir = workdir("pkg");
    write_binary_forms(&dir);
    let s = load_stage(dir.join("roundtrip.usdz"), 1.0).unwrap();
    let panel = s.light("/World/Lights/Panel").unwrap();
    let r = panel.texture.as_ref().unwrap().resolved.as_ref().unwrap();
    let text = r.to_string_lossy();
    assert!(text.ends_with("roundtrip.usdz[assets/grid.png]"), "{text}");
    let spot = s.light("/World/Lights/Spot").unwrap();
    let ies = spot.shaping.as_ref().unwrap().ies_file.as_ref().unwrap();
    assert_eq!(ies.authored, "assets/tiny.ies");
    let text = ies
        .resolved
        .as_ref()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    assert!(text.ends_with("roundtrip.usdz[assets/tiny.ies]"), "{text}");
}
