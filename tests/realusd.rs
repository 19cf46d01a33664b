//! Real USD files as people publish them (`tests/data/realusd/`, origin and licences in its
//! `SOURCES.md` and `EXTRA_SOURCES.md`): `lux info` reports what usd-core 26.11 reports for each (numbers derived with
//! usd-core when the test was written: visible lights, meshes, other gprims, cameras, native
//! and PointInstancer instances at the stage's start time), and a small render of each is
//! finite and not black; through the built `lux` binary, usdrecord's defaults where a stage is
//! silent. (The published package leaves this suite and its data out: see Cargo.toml.)

mod common;

#[path = "../src/cli/info.rs"]
#[allow(dead_code)]
mod info;

use common::cli::{lux, render_small};
use lux_math::Profile;
use lux_render::conformance::{ProfileSource, ResolvedProfile};
use lux_render::render::{RenderOptions, Renderer};
use lux_usd::{LoadOptions, Time, WarningKind, load_stage_with};
use std::path::PathBuf;

/// What usd-core reports for one file.
struct UsdCore {
    file: &'static str,
    lights: u64,
    meshes: u64,
    other_gprims: u64,
    cameras: u64,
    point_instances: u64,
    native_instances: u64,
}

const fn f(
    file: &'static str,
    [
        lights,
        meshes,
        other_gprims,
        cameras,
        point_instances,
        native_instances,
    ]: [u64; 6],
) -> UsdCore {
    UsdCore {
        file,
        lights,
        meshes,
        other_gprims,
        cameras,
        point_instances,
        native_instances,
    }
}

/// `[lights, meshes, other gprims, cameras, PointInstancer instances, native instances]`: the
/// 14 files of `SOURCES.md`, then the 27 of `EXTRA_SOURCES.md`.
const FILES: [UsdCore; 41] = [
    f(
        "usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda",
        [5, 12, 0, 1, 0, 0],
    ),
    f("usdwg/full_assets/Teapot/Teapot.usd", [0, 1, 0, 0, 0, 0]),
    f(
        "usdwg/full_assets/SubdivisionSurfaces/Creases_SpinningPyramids.usda",
        [0, 3, 0, 1, 0, 3],
    ),
    f(
        "usdwg/test_assets/RoughnessTest/RoughnessTest.usdz",
        [0, 6, 0, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/schemaTests/usdGeom/primitives/all_primitives.usda",
        [0, 0, 5, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_composition/payload/payload_invalid.usda",
        [0, 0, 1, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_configuration/upAxis/upAxis_Z.usda",
        [0, 0, 3, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdLux/usdLux.usda",
        [1, 0, 2, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLDomeLight/domeLightZup.usda",
        [1, 0, 1, 2, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_basic.usda",
        [0, 2, 1, 0, 4, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLAnimatedLights/lightMoving.usda",
        [1, 0, 1, 0, 0, 0],
    ),
    f(
        "openusd/extras/usd/tutorials/animatedTop/top.geom.usd",
        [0, 1, 0, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLBasicLighting/basicDrawing.usda",
        [0, 0, 6, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/bin/testusdview/testenv/testUsdviewRenderSettingsEdits/test.usda",
        [1, 0, 4, 1, 0, 0],
    ),
    f(
        "Autodesk-maya-usd/test/lib/usd/translators/UsdImportLightTest/LightsTest.usda",
        [4, 0, 0, 0, 0, 0],
    ),
    f(
        "Autodesk-maya-usd/test/lib/usd/translators/UsdImportLightTest/LightsTest_2011.usda",
        [4, 0, 0, 0, 0, 0],
    ),
    f(
        "Autodesk-maya-usd/test/lib/usd/translators/UsdImportRfMLightTest/RfMLightsTest.usda",
        [7, 2, 0, 0, 0, 0],
    ),
    f(
        "Autodesk-maya-usd/test/lib/usd/translators/UsdImportSkeleton/skelCube.usda",
        [0, 1, 0, 0, 0, 0],
    ),
    f(
        "openusd/extras/usd/examples/usdSemanticsExamples/bookshelf.usda",
        [0, 0, 6, 0, 0, 0],
    ),
    f(
        "openusd/extras/usd/tutorials/simpleShading/simpleShading.usda",
        [0, 1, 0, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usd/usdLux/testenv/testUsdLuxLinkingAPI/linking_example.usda",
        [8, 0, 2, 0, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLAnimatedCamera/cameraMoving.usda",
        [0, 2, 0, 1, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLCameraExposure/cameraExposure.usda",
        [0, 2, 0, 1, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLDomeLight/multiDomeLights.usda",
        [2, 0, 1, 2, 0, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/instance.usda",
        [0, 7, 12, 0, 0, 1],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/nestedInstance.usda",
        [0, 7, 12, 0, 0, 1],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/sphereInstancer.usda",
        [0, 0, 0, 0, 25, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/ni_pi.usda",
        [0, 0, 2, 0, 7, 2],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_masking.usda",
        [0, 0, 1, 0, 5, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_ni.usda",
        [0, 0, 16, 0, 24, 17],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_pi.usda",
        [0, 0, 16, 0, 29, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_pi_time.usda",
        [0, 0, 5, 0, 11, 0],
    ),
    f(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_pi_varying.usda",
        [0, 0, 3, 0, 6, 0],
    ),
    f(
        "usdwg/test_assets/CompositionPuzzles/VariantSetAndLocal2/puzzle_2.usda",
        [0, 0, 1, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/PrimvarInterpolation/primvar_interpolation.usda",
        [0, 7, 0, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_composition/active.usda",
        [0, 0, 1, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_composition/class_inherit.usda",
        [0, 0, 2, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_composition/inherit_and_specialize.usda",
        [0, 0, 6, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_composition/purpose.usda",
        [0, 0, 1, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/foundation/stage_configuration/upAxis/upAxis_invalid.usda",
        [0, 0, 3, 0, 0, 0],
    ),
    f(
        "usdwg/test_assets/schemaTests/usdGeom/meshes/normals_types/normalsTypes.usda",
        [0, 17, 0, 0, 0, 0],
    ),
];

fn path(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/realusd")
        .join(file)
}

#[test]
fn lux_info_counts_what_usd_core_counts() {
    for e in &FILES {
        let args = info::InfoArgs {
            scene: path(e.file),
            frame: None,
            json: true,
            strict: false,
            disable_camera_light: false,
            subdiv_level: None,
        };
        let report = info::report(&args).unwrap_or_else(|err| panic!("{}: {err}", e.file));
        let v: serde_json::Value = serde_json::from_str(&report).unwrap();
        let c = &v["counts"];
        let got = [
            c["lights"].as_u64(),
            c["meshes"].as_u64(),
            c["other_gprims"].as_u64(),
            c["cameras"].as_u64(),
            c["point_instances"].as_u64(),
            c["native_instances"].as_u64(),
        ];
        let want = [
            e.lights,
            e.meshes,
            e.other_gprims,
            e.cameras,
            e.point_instances,
            e.native_instances,
        ]
        .map(Some);
        assert_eq!(
            got, want,
            "{}: [lights, meshes, other gprims, cameras, point instances, native instances]",
            e.file
        );
        // usdrecord's defaults are said, exactly when the stage lacks a camera / a light
        let defaults = v["defaults"].as_array().unwrap();
        let says = |what: &str| defaults.iter().any(|d| d.as_str().unwrap().contains(what));
        assert_eq!(
            says("no camera"),
            e.cameras == 0,
            "{}: {defaults:?}",
            e.file
        );
        assert_eq!(says("no light"), e.lights == 0, "{}: {defaults:?}", e.file);
    }
}

/// usd-core composes these stages with warnings for what it cannot open; so does lux, naming
/// the arc, its layer and the prim — and a strict load refuses them.
#[test]
fn what_usd_core_warns_about_lux_warns_about() {
    let cases = [(
        "usdwg/test_assets/foundation/stage_composition/payload/payload_invalid.usda",
        "/World/invalid_payload",
        "file_does_not_exist.usda",
    )];
    for (file, prim, what) in cases {
        let s = load_stage_with(path(file), Time::Start, &LoadOptions::default()).unwrap();
        let w = s
            .warnings
            .iter()
            .find(|w| w.kind == WarningKind::Composition && w.prim.starts_with(prim))
            .unwrap_or_else(|| panic!("{file}: no composition warning: {:#?}", s.warnings));
        assert!(w.message.contains(what), "{file}: {w}");
        assert!(w.message.contains("arc authored in"), "{file}: {w}");
        let mut strict = LoadOptions::default();
        strict.strict = true;
        assert!(
            load_stage_with(path(file), Time::Start, &strict).is_err(),
            "{file}: a strict load refuses it"
        );
    }
}

/// usd-core's PyPI wheels lack usdMtlx and warn about the StandardShaderBall's `.mtlx`
/// references; lux composes them as usdMtlx does (documents translated to its prims). Each
/// MaterialX example material (variant `example_material`), in both shading models (variant
/// `material_model`: standard_surface and open_pbr_surface), loads without a composition or
/// material warning, reaches the renderer as a graph of that model with a surface and no note,
/// and renders finite and lit with no material warning.
#[test]
fn materialx_variants_of_the_shader_ball_render_as_authored() {
    let ball = path("usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda");
    let dir = std::env::temp_dir().join(format!("lux-ball-variants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (model, nodedef) in [
        ("standard_surface", "ND_standard_surface_surfaceshader"),
        ("OpenPBRSurface", "ND_open_pbr_surface_surfaceshader"),
    ] {
        for example in ["bubblegum", "glass", "gold", "plastic"] {
            let stage = dir.join(format!("{model}_{example}.usda"));
            std::fs::write(
                &stage,
                format!(
                    "#usda 1.0\n(\n    defaultPrim = \"standard_shader_ball_scene\"\n    \
                     subLayers = [@{}@]\n)\nover \"standard_shader_ball_scene\" (\n    \
                     variants = {{ string example_material = \"mtlx_{example}\" }}\n)\n{{\n    \
                     over \"materials\" {{ over \"examples\" (variants = {{ string \
                     material_model = \"{model}\" }}) {{ }} }}\n}}\n",
                    ball.display()
                ),
            )
            .unwrap();
            let what = format!("{model} {example}");
            let s = load_stage_with(&stage, Time::Start, &LoadOptions::default()).unwrap();
            let bad = |w: &&lux_usd::Warning| {
                w.kind == WarningKind::Composition || w.prim.contains("/examples/")
            };
            assert!(
                !s.warnings.iter().any(|w| bad(&w)),
                "{what}: {:#?}",
                s.warnings
            );
            let m = s
                .materials
                .iter()
                .find(|m| m.path.ends_with(&format!("/examples/mtlx/{example}")))
                .unwrap_or_else(|| panic!("{what}: not bound"));
            let g = m.graph.as_ref().expect("a MaterialX graph");
            assert_eq!(g.model, nodedef, "{what}");
            assert!(
                g.surface.is_some() && g.notes.is_empty(),
                "{what}: {:?}",
                g.notes
            );
            let mut options = RenderOptions::new(ResolvedProfile {
                profile: Profile::Spec,
                source: ProfileSource::CommandLine,
            });
            options.spp = 1;
            options.resolution = Some([32, 18]);
            let renderer = Renderer::new(&s, options).unwrap();
            let material_warnings: Vec<_> = renderer
                .warnings()
                .filter(|w| w.contains("/examples/"))
                .collect();
            assert!(
                material_warnings.is_empty(),
                "{what}: {material_warnings:?}"
            );
            let (image, _) = renderer.render(&|_| {});
            let sum: f64 = image
                .pixels
                .iter()
                .map(|p| f64::from(p[0] + p[1] + p[2]))
                .sum();
            assert!(sum.is_finite() && sum > 0.0, "{what}: {sum}");
        }
    }
}

/// Every stage renders (finite pixels, no error: a texture or IES file that is missing gives its
/// fallback with a warning), and is not black when it has geometry.
#[test]
fn small_renders_are_finite_and_lit() {
    for e in &FILES {
        let mut scene = load_stage_with(path(e.file), Time::Start, &LoadOptions::default())
            .unwrap_or_else(|err| panic!("{}: {err}", e.file));
        scene.add_usdrecord_defaults(true);
        let mut options = RenderOptions::new(ResolvedProfile {
            profile: Profile::Spec,
            source: ProfileSource::CommandLine,
        });
        options.spp = 2;
        options.resolution = Some([48, 36]);
        let renderer =
            Renderer::new(&scene, options).unwrap_or_else(|err| panic!("{}: {err}", e.file));
        let (image, _) = renderer.render(&|_| {});
        let mut sum = 0.0;
        for p in &image.pixels {
            assert!(p.iter().all(|c| c.is_finite()), "{}: {p:?}", e.file);
            sum += f64::from(p[0] + p[1] + p[2]);
        }
        // A stage of lights alone (a DCC's light export) has nothing for them to light.
        let has_geometry = e.meshes + e.other_gprims + e.point_instances > 0;
        assert_eq!(
            sum > 0.0,
            has_geometry,
            "{}: lit iff there is geometry",
            e.file
        );
    }
}

/// PointInstancer masks and prototypes as UsdImaging draws them: `inactiveIds` and
/// time-sampled `invisibleIds` (usd-core's `ComputeMaskAtTime` leaves 4, 3, 3 instances at
/// frames 0, 1, 2), and prototypes authored under an `over` (25 spheres, the `over` prototype
/// itself ignored).
#[test]
fn point_instancer_masks_and_hidden_prototypes() {
    let dir = "openusd/pxr/usdImaging/usdImagingGL/testenv";
    let masking = path(&format!(
        "{dir}/testUsdImagingGLPointInstancer/pi_masking.usda"
    ));
    for (frame, drawn) in [(0.0, 4), (1.0, 3), (2.0, 3), (3.0, 4)] {
        let s = load_stage_with(&masking, frame, &LoadOptions::default()).unwrap();
        assert_eq!(s.instances.len(), drawn, "pi_masking at {frame}");
        assert_eq!(
            s.gprims.point_instances, 5,
            "every protoIndices entry is counted"
        );
    }
    let spheres = path(&format!(
        "{dir}/testUsdImagingGLInstancing/sphereInstancer.usda"
    ));
    let s = load_stage_with(&spheres, Time::Start, &LoadOptions::default()).unwrap();
    assert_eq!(s.instances.len(), 25);
    assert_eq!(s.prototypes.len(), 1);
    let xs: Vec<f64> = s.instances.iter().map(|i| i.to_world.w_axis.x).collect();
    assert_eq!(xs[..5], [0.0, 200.0, 400.0, 600.0, 800.0]);
}

/// Native instancing shares geometry: an instanceable prim referencing an inactive source is
/// drawn from its prototype (7 meshes, 8 implicit surfaces, a BasisCurves and 2 Points,
/// stored once).
#[test]
fn native_instances_share_their_prototype() {
    let f = path(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/instance.usda",
    );
    let s = load_stage_with(&f, Time::Start, &LoadOptions::default()).unwrap();
    assert_eq!(s.instances.len(), 1);
    assert_eq!(s.prototypes[0].meshes.len(), 18);
    assert!(s.meshes.iter().all(|m| m.prototype == Some(0)));
}

/// A texture lux cannot read (a missing RenderMan `.tex` on one of two dome lights) is a
/// warning naming that light and file; the light emits without it and the other light is
/// untouched. A strict render refuses it.
#[test]
fn an_unreadable_light_texture_is_that_lights_warning() {
    let f = path(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLDomeLight/multiDomeLights.usda",
    );
    let scene = load_stage_with(&f, Time::Start, &LoadOptions::default()).unwrap();
    let mut options = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    options.resolution = Some([32, 24]);
    let r = Renderer::new(&scene, options.clone()).unwrap();
    assert_eq!(r.lights().lights.len(), 2, "both domes emit");
    let w: Vec<&String> = r.warnings().collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("UVtemplate_1x1.tex") && w[0].contains("/Scene/lights/DomeLight1"),
        "{}",
        w[0]
    );
    assert!(!w[0].contains("DomeLight2"), "{}", w[0]);
    options.strict = true;
    let e = Renderer::new(&scene, options)
        .err()
        .expect("strict refuses it");
    assert!(e.to_string().contains("UVtemplate_1x1.tex"), "{e}");
}

/// `lux ARGS…` through the built binary, without the user's profile environment and config files.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lux-realusd-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// usdrecord's behaviour where the stage is silent, said in the log: a stage without camera or
/// light gets a framing camera and a camera light (`--disable-camera-light` turns the light
/// off, and the render is then black); the frame is the stage's startTimeCode; `--camera`
/// takes a bare name when it is unique and says which names exist when it is not found.
#[test]
fn usdrecord_defaults_and_camera_names() {
    let out = tmp("defaults.exr");
    let teapot = path("usdwg/full_assets/Teapot/Teapot.usd");
    let o = render_small(&teapot, &out, &[], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("no camera on the stage: usdrecord's framing camera"),
        "{e}"
    );
    assert!(
        e.contains("no light on the stage: usdrecord's camera light"),
        "{e}"
    );
    let lit = lux_render::image_io::Texture::load(&out).unwrap();
    assert!(
        lit.texels().iter().any(|p| p[0] > 0.0),
        "the camera light lights the teapot"
    );
    let o = render_small(&teapot, &out, &["--disable-camera-light"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains("camera light (a DistantLight"),
        "{}",
        stderr(&o)
    );
    let dark = lux_render::image_io::Texture::load(&out).unwrap();
    assert!(
        dark.texels().iter().all(|p| p[0] == 0.0),
        "no light, no image"
    );
    // two cameras: a bare name picks one; an unknown name lists them
    let dome = path(
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLDomeLight/domeLightZup.usda",
    );
    let o = render_small(&dome, &out, &["--camera", "BackCamera"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = render_small(&dome, &out, &["--camera", "SideCamera"], &[]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("SideCamera") && e.contains("FrontCamera") && e.contains("BackCamera"),
        "{e}"
    );
    // the stage's startTimeCode when no --frame is given (the ShaderBall starts at 3)
    let ball = path("usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda");
    let o = lux(&["info", ball.to_str().unwrap(), "--json"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["frame"], 3.0);
}

/// `lux info --json` reports the world box of what is drawn — posed, refined, curves and
/// points included — and how many of each: a skinned arm (usd-core's `UsdSkel.BakeSkinning`
/// and `BBoxCache` give (−0.5, −0.5, 0)..(0.5, 0.5, 4) at time 1, `SOURCES.md` of the skel test
/// data; its limit surface inside that box in spec), a default-scheme cube refined by the spec
/// profile (its face centres, the limit points 68/81 out, bound it), OpenUSD's basicDrawing
/// and instancing test (curves and points drawn).
#[test]
fn json_report_gives_drawn_bounds_and_counts() {
    let report = |path: PathBuf, frame: Option<f64>| -> serde_json::Value {
        let args = info::InfoArgs {
            scene: path,
            frame,
            json: true,
            strict: false,
            disable_camera_light: false,
            subdiv_level: None,
        };
        serde_json::from_str(&info::report(&args).unwrap()).unwrap()
    };
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    // (the published package leaves this suite out: it reads data beside it)
    let arm_path = root.join("crates/lux-usd/tests/data/skel/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdSkel/arm.usda");
    let v3 = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let close = |got: Vec<f64>, want: [f64; 3]| {
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-5 * 4.0, "{got:?} vs {want:?}");
        }
    };
    // The arm is a subdivision surface: in the hdembree profile (its polygons, as usd-core
    // bounds its points) the box is usd-core's; in spec its limit surface lies inside it.
    let dir = std::env::temp_dir().join(format!("lux-info-bounds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let hdembree = dir.join("arm_hdembree.usda");
    std::fs::write(
        &hdembree,
        format!(
            "#usda 1.0\n(\n    subLayers = [@{}@]\n)\ndef RenderSettings \"Settings\" {{\n    uniform token lux:conformanceProfile = \"hdembree\"\n}}\n",
            arm_path.display()
        ),
    )
    .unwrap();
    let arm = report(hdembree, Some(1.0));
    assert_eq!(arm["profile"]["name"], "hdembree", "{}", arm["profile"]);
    assert_eq!(arm["counts"]["posed_meshes"], 1);
    assert_eq!(arm["counts"]["refined_meshes"], 0);
    close(v3(&arm["bounds"]["min"]), [-0.5, -0.5, 0.0]);
    close(v3(&arm["bounds"]["max"]), [0.5, 0.5, 4.0]);
    let arm = report(arm_path, Some(1.0));
    assert_eq!(arm["counts"]["posed_meshes"], 1);
    assert_eq!(arm["counts"]["refined_meshes"], 1);
    let (lo, hi) = (v3(&arm["bounds"]["min"]), v3(&arm["bounds"]["max"]));
    for k in 0..3 {
        assert!(lo[k] >= [-0.5, -0.5, 0.0][k] - 1e-9 && hi[k] <= [0.5, 0.5, 4.0][k] + 1e-9);
    }
    // A cube left at the default scheme, with a camera 10 away.
    let cube = dir.join("cube.usda");
    std::fs::write(
        &cube,
        r#"#usda 1.0
def Mesh "Cube" {
    int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
    int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
    point3f[] points = [(-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1), (-1, -1, -1), (1, -1, -1)]
}
def Camera "Cam" {
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
"#,
    )
    .unwrap();
    let c = report(cube, None);
    assert_eq!(c["counts"]["refined_meshes"], 1);
    let limit = 68.0 / 81.0;
    close(v3(&c["bounds"]["min"]), [-limit; 3]);
    close(v3(&c["bounds"]["max"]), [limit; 3]);
    let drawing = report(
        root.join("tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLBasicLighting/basicDrawing.usda"),
        None,
    );
    let counts = &drawing["counts"];
    assert_eq!(counts["curves"], 3, "{counts}");
    assert!(
        counts["not_drawn"].as_object().unwrap().is_empty(),
        "{counts}"
    );
    // OpenUSD's instancing test: 7 meshes (default scheme) refined, 1 curve and 2 points
    // prims drawn through the instance, the Volume not drawn.
    let inst = report(
        root.join("tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/instance.usda"),
        None,
    );
    let counts = &inst["counts"];
    assert_eq!(
        [
            &counts["refined_meshes"],
            &counts["curves"],
            &counts["points"]
        ],
        [7, 1, 2],
        "{counts}"
    );
    assert_eq!(counts["not_drawn"]["Volume"], 1);
}
