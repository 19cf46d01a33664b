//! The renderer reads IES profiles and textures from inside a `.usdz` package: the lights
//! prepared from the package emit exactly what those of the same loose `.usda` emit.

use glam::DVec3;
use lux_math::Profile;
use lux_render::light::{LightOptions, LightSelection, LightSet, Seen};
use lux_usd::load_stage;
use std::fs;
use std::path::PathBuf;

const SCENE: &str = r#"#usda 1.0
(
    defaultPrim = "World"
)
def Xform "World"
{
    def SphereLight "Bulb" (
        prepend apiSchemas = ["ShapingAPI"]
    )
    {
        float inputs:radius = 0.1
        asset inputs:shaping:ies:file = @assets/tiny.ies@
        double3 xformOp:translate = (0, 0, 2)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def RectLight "Panel"
    {
        asset inputs:texture:file = @assets/grid.png@
        double3 xformOp:translate = (1, 0, 2)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
}
"#;

/// Two assets made here: a tiny IES profile and a 2 × 2 PNG.
fn assets() -> Vec<(&'static str, Vec<u8>)> {
    let ies = b"IESNA:LM-63-2002\n[TEST] lux packaged-asset test\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n100 60 0\n".to_vec();
    let mut png = std::io::Cursor::new(Vec::new());
    image::RgbImage::from_fn(2, 2, |x, y| {
        image::Rgb([(x * 255) as u8, (y * 255) as u8, 40])
    })
    .write_to(&mut png, image::ImageFormat::Png)
    .unwrap();
    vec![
        ("assets/tiny.ies", ies),
        ("assets/grid.png", png.into_inner()),
    ]
}

#[test]
fn packaged_assets_render_like_loose_files() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("packaged_assets-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("assets")).unwrap();
    fs::write(dir.join("scene.usda"), SCENE).unwrap();
    let mut w = openusd::usdz::ArchiveWriter::create(dir.join("scene.usdz")).unwrap();
    w.add_layer("scene.usda", SCENE.as_bytes()).unwrap();
    for (file, bytes) in assets() {
        fs::write(dir.join(file), &bytes).unwrap();
        w.add_layer(file, &bytes).unwrap();
    }
    w.finish().unwrap();

    let opts = LightOptions {
        cone_clipping: true,
        profile: Profile::Spec,
        selection: LightSelection::All,
        strict: false,
    };
    let loose = load_stage(dir.join("scene.usda"), 1.0).unwrap();
    let packed = load_stage(dir.join("scene.usdz"), 1.0).unwrap();
    let texture = packed.lights[1].texture.as_ref().unwrap();
    let resolved = texture.resolved.as_ref().unwrap().to_string_lossy();
    assert!(
        resolved.ends_with("scene.usdz[assets/grid.png]"),
        "{resolved}"
    );
    let a = LightSet::new(&loose, opts).unwrap();
    let b = LightSet::new(&packed, opts).unwrap();
    assert_eq!(a.lights.len(), 2);
    assert_eq!(b.lights.len(), 2);
    let dirs = [
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(0.3, -0.2, -0.9),
        DVec3::new(-0.5, 0.4, -0.6),
    ];
    // points on the sphere's lower half and on the rect
    let points = [DVec3::new(0.0, 0.0, -0.1), DVec3::new(0.06, 0.0, -0.08)];
    for (x, y) in a.lights.iter().zip(&b.lights) {
        let (bx, by) = (x.base(), y.base());
        assert_eq!(bx.path, by.path);
        assert_eq!(bx.radiance, by.radiance, "{}", bx.path);
        assert_eq!(bx.shaping.has_ies(), by.shaping.has_ies(), "{}", bx.path);
        for d in dirs {
            for p in points {
                assert_eq!(x.le(p, d, Seen::Lit), y.le(p, d, Seen::Lit), "{}", bx.path);
            }
        }
    }
    assert!(
        b.lights[0].base().shaping.has_ies(),
        "the packaged IES is used"
    );
    let lit = b.lights[0].le(DVec3::new(0.0, 0.0, -0.1), DVec3::NEG_Z, Seen::Lit);
    assert!(
        lit.max_element() > 0.0,
        "the profile emits straight down: {lit}"
    );
}
