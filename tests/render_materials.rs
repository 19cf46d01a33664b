//! Materials as their MaterialX definitions shade them, measured on the Cornell box
//! (`tests/data/cornell/`, variants written by `variants.py`):
//!
//! - standard_surface and open_pbr_surface configured as pure diffuse (specular weight 0,
//!   metalness 0, diffuse roughness 0) are, by their graphs, a Lambertian `base_color` — the
//!   compiled graphs fold to exactly that, and render exactly like `--surfaces lambert`;
//! - the same diffuse surface shaded through lux-bsdf's Oren–Nayar closure (its roughness read
//!   per hit from a primvar the meshes lack, so nothing folds) renders like `--surfaces lambert`
//!   to the noise: the closure tree, its sampling and MIS are unbiased;
//! - a UsdPreviewSurface with `useSpecularWorkflow = 1` and `specularColor = 0` is, by
//!   MaterialX's graph of it, a generalized Schlick lobe (`color0 = 0`, `color90 = 1`) layered
//!   over Lambertian `diffuseColor`: within a few per cent of Lambertian, darker only by what
//!   the grazing Fresnel of the top layer takes (direct light on the box: 0.967 / 0.971 /
//!   0.981 of Lambertian per channel at 64 spp; the hand-written model before gave 0.78 / 0.80 /
//!   0.85);
//! - a smooth pane of open_pbr_surface transmission of ior 1 (no Fresnel: every ray passes
//!   straight through), solid or thin-walled, between the camera and the lower part of the box
//!   leaves the picture as it was, to the noise: the path integrator follows delta
//!   transmission. (The pane stops below the line of sight to the light, which the camera does
//!   not see directly but would see through a pane, as in a mirror.)

use lux_math::Profile;
use lux_render::conformance::{ProfileSource, ResolvedProfile};
use lux_render::material::SurfaceModel;
use lux_render::render::{RenderOptions, Renderer};
use lux_render::settings::{AdaptiveSampling, IntegratorKind};
use lux_usd::{LoadOptions, Time, load_stage_with};
use std::path::PathBuf;

fn cornell(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/cornell/{name}.usda"))
}

/// Direct lighting of a Cornell variant at 64 × 64, `spp` samples, no adaptive sampling.
fn render(stage: &std::path::Path, surfaces: SurfaceModel, spp: u32, seed: u64) -> Vec<[f32; 4]> {
    let scene = load_stage_with(stage, Time::Start, &LoadOptions::default()).unwrap();
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.integrator = IntegratorKind::Direct;
    o.surfaces = surfaces;
    o.spp = spp;
    o.seed = seed;
    o.adaptive = Some(AdaptiveSampling::OFF);
    o.resolution = Some([64, 64]);
    let r = Renderer::new(&scene, o).unwrap();
    let w: Vec<_> = r.warnings().collect();
    assert!(w.is_empty(), "{w:?}");
    r.render(&|_| {}).0.pixels
}

fn means(px: &[[f32; 4]]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in px {
        for c in 0..3 {
            m[c] += f64::from(p[c]);
        }
    }
    m.map(|v| v / px.len() as f64)
}

#[test]
fn pure_diffuse_standard_surface_and_open_pbr_render_as_lambert() {
    let lambert = render(&cornell("cornell"), SurfaceModel::Lambert, 4, 0);
    for v in ["cornell_standard_surface", "cornell_open_pbr"] {
        let scene = load_stage_with(cornell(v), Time::Start, &LoadOptions::default()).unwrap();
        for m in &scene.materials {
            let g = m.graph.as_ref().expect("a MaterialX graph");
            assert!(
                g.model.ends_with("_surfaceshader") && g.notes.is_empty(),
                "{v}"
            );
        }
        assert_eq!(
            render(&cornell(v), SurfaceModel::Preview, 4, 0),
            lambert,
            "{v}"
        );
    }
}

#[test]
fn oren_nayar_closure_at_roughness_zero_renders_as_lambert_to_the_noise() {
    // standard_surface's diffuse_roughness from a primvar the box lacks (default 0): the
    // graph does not fold, every hit shades through lux-bsdf's tree.
    let base = std::fs::read_to_string(cornell("cornell_standard_surface")).unwrap();
    let text = base.replace(
        "                float inputs:diffuse_roughness = 0\n",
        "                float inputs:diffuse_roughness.connect = <../Rough.outputs:out>\n",
    );
    let rough = concat!(
        "            def Shader \"Rough\"\n",
        "            {\n",
        "                uniform token info:id = \"ND_geompropvalue_float\"\n",
        "                string inputs:geomprop = \"rough\"\n",
        "                float inputs:default = 0\n",
        "                float outputs:out\n",
        "            }\n",
        "            def Shader \"Surface\"\n",
    );
    let text = text.replace("            def Shader \"Surface\"\n", rough);
    assert_eq!(text.matches("ND_geompropvalue_float").count(), 3);
    let dir = std::env::temp_dir().join(format!("lux-materials-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stage = dir.join("cornell_rough_primvar.usda");
    std::fs::write(&stage, text).unwrap();
    let scene = load_stage_with(&stage, Time::Start, &LoadOptions::default()).unwrap();
    assert!(scene.warnings.is_empty(), "{:#?}", scene.warnings);
    for m in &scene.materials {
        let g = m.graph.as_ref().unwrap();
        assert!(
            g.nodes.iter().any(|n| n.category == "geompropvalue"),
            "{}",
            m.path
        );
        let mut textures = lux_render::material::graph::TextureCache::new();
        let compiled =
            lux_render::material::graph::GraphShader::compile(g, &mut textures, &mut Vec::new());
        assert_eq!(compiled.constant_lambert(), None, "{}: folded", m.path);
        assert_eq!(compiled.primvars(), ["rough"]);
    }
    let spp = 64;
    let graph = means(&render(&stage, SurfaceModel::Preview, spp, 1));
    let lambert = [1, 2].map(|seed| {
        means(&render(
            &cornell("cornell"),
            SurfaceModel::Lambert,
            spp,
            seed,
        ))
    });
    for c in 0..3 {
        // The seed-to-seed difference of the Lambertian means measures their noise (the
        // graph's, sampled by BSDF and light with MIS, is of the same order).
        let noise = (lambert[0][c] - lambert[1][c])
            .abs()
            .max(1e-4 * lambert[0][c]);
        let d = (graph[c] - lambert[0][c]).abs();
        assert!(
            d < 6.0 * noise + 2e-3 * lambert[0][c],
            "channel {c}: graph {} lambert {:?}",
            graph[c],
            lambert
        );
    }
}

#[test]
fn diffuse_usd_preview_surface_is_within_a_few_per_cent_of_lambert() {
    let preview = means(&render(
        &cornell("cornell_preview_diffuse"),
        SurfaceModel::Preview,
        64,
        0,
    ));
    let lambert = means(&render(
        &cornell("cornell_preview_diffuse"),
        SurfaceModel::Lambert,
        64,
        0,
    ));
    for c in 0..3 {
        let ratio = preview[c] / lambert[c];
        // The top layer reflects what its Schlick Fresnel gives and takes the same energy
        // from the diffuse base: a little darker at grazing views, never brighter.
        assert!((0.95..1.0).contains(&ratio), "channel {c}: {ratio}");
    }
}

/// The box path-traced (depth 16, so that the pane's extra vertex leaves the depth budget
/// practically unchanged) at 32 × 32, `spp` samples.
fn path(stage: &std::path::Path, spp: u32, seed: u64) -> [f64; 3] {
    let scene = load_stage_with(stage, Time::Start, &LoadOptions::default()).unwrap();
    assert!(scene.warnings.is_empty(), "{:#?}", scene.warnings);
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.integrator = IntegratorKind::Path;
    o.max_depth = 16;
    o.spp = spp;
    o.seed = seed;
    o.adaptive = Some(AdaptiveSampling::OFF);
    o.resolution = Some([32, 32]);
    let r = Renderer::new(&scene, o).unwrap();
    let w: Vec<_> = r.warnings().collect();
    assert!(w.is_empty(), "{w:?}");
    means(&r.render(&|_| {}).0.pixels)
}

#[test]
fn a_pane_of_index_one_lets_the_picture_through() {
    let dir = std::env::temp_dir().join(format!("lux-pane-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = cornell("cornell");
    let spp = 256;
    let bare = [3, 4].map(|seed| path(&base, spp, seed));
    for thin in [0, 1] {
        let stage = dir.join(format!("pane_thin{thin}.usda"));
        std::fs::write(
            &stage,
            format!(
                r#"#usda 1.0
(
    defaultPrim = "World"
    upAxis = "Z"
    subLayers = [@{}@]
)
over "World"
{{
    def Material "Glass"
    {{
        token outputs:mtlx:surface.connect = </World/Glass/Surface.outputs:out>
        def Shader "Surface"
        {{
            uniform token info:id = "ND_open_pbr_surface_surfaceshader"
            float inputs:transmission_weight = 1
            float inputs:specular_ior = 1
            float inputs:specular_roughness = 0
            bool inputs:geometry_thin_walled = {thin}
            token outputs:out
        }}
    }}
    def Mesh "Pane" (prepend apiSchemas = ["MaterialBindingAPI"])
    {{
        rel material:binding = </World/Glass>
        uniform token subdivisionScheme = "none"
        uniform bool doubleSided = 1
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1.5, -2, -0.5), (1.5, -2, -0.5), (1.5, -2, 1.3), (-1.5, -2, 1.3)]
    }}
}}
"#,
                base.display()
            ),
        )
        .unwrap();
        let scene = load_stage_with(&stage, Time::Start, &LoadOptions::default()).unwrap();
        let glass = scene
            .materials
            .iter()
            .find(|m| m.path == "/World/Glass")
            .unwrap();
        let mut textures = lux_render::material::graph::TextureCache::new();
        let g = lux_render::material::graph::GraphShader::compile(
            glass.graph.as_ref().unwrap(),
            &mut textures,
            &mut Vec::new(),
        );
        assert!(g.may_transmit(), "thin {thin}");
        let through = path(&stage, spp, 3);
        for c in 0..3 {
            let noise = (bare[0][c] - bare[1][c]).abs().max(1e-3 * bare[0][c]);
            let d = (through[c] - bare[0][c]).abs();
            assert!(
                d < 6.0 * noise + 5e-3 * bare[0][c],
                "thin {thin}, channel {c}: {} through the pane, {:?} bare",
                through[c],
                bare
            );
        }
    }
}
