//! Physical light units and the spectral API wired into the renderer (issue 8): the loader
//! reads the attributes and their metadata, the renderer emits lux-spectral's conversion, and
//! rendered irradiance matches the authored physical quantity.

mod common;

use common::{probe, probe_scene};
use glam::{DMat4, DQuat, DVec3};
use lux::math::{LightShape, Profile};
use lux::render::conformance::{ProfileSource, ResolvedProfile};
use lux::render::light::{LightOptions, LightSelection, LightSet};
use lux::render::render::{RenderOptions, Renderer};
use lux::shaping::{Shaping, ShapingOptions, ShapingParams};
use lux::spectral::{
    ColorSpace, Illuminant, IlluminantKind, Interpolation, IorInterpolation, PhysicalLightInputs,
    PhysicalQuantity, SpectralAttribute, WavelengthUnit, resolve_illuminant,
};
use lux::usd::{Light, PhysicalLight, PoleAxis, Scene, load_stage};
use std::f64::consts::PI;
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/physical_lights.usda")
}

fn lights(scene: &Scene) -> LightSet {
    LightSet::new(
        scene,
        LightOptions {
            cone_clipping: true,
            profile: Profile::Spec,
            selection: LightSelection::All,
            strict: false,
        },
    )
    .unwrap()
}

fn radiance(set: &LightSet, path: &str) -> DVec3 {
    set.lights
        .iter()
        .find(|l| l.base().path == path)
        .unwrap_or_else(|| panic!("{path} prepared"))
        .base()
        .radiance
}

fn close3(got: DVec3, want: DVec3, rel: f64, what: &str) {
    assert!(
        (got - want).abs().max_element() <= rel * want.abs().max_element(),
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn loader_reads_physical_attributes_and_spectral_metadata() {
    let scene = load_stage(data(), 1.0).unwrap();
    assert_eq!(scene.unit_for_wavelength, WavelengthUnit::Nanometers);
    let l = scene.light("/World/Lumens").unwrap();
    assert!(l.api_schemas.iter().any(|a| a == "PhotometricAreaLightAPI"));
    let p = l.physical.as_ref().expect("physical light units");
    assert_eq!(p.quantity, Some(PhysicalQuantity::PhotometricPower(800.0)));
    assert_eq!(p.illuminant, IlluminantKind::Blackbody);
    let p = scene.light("/World/Preset").unwrap();
    let e = p.emission_spectrum.as_ref().unwrap();
    assert_eq!(e.illuminant_preset, Some(Illuminant::D65));
    assert!(e.values.is_empty());
    let m = scene.light("/World/Micrometres").unwrap();
    let e = m.emission_spectrum.as_ref().unwrap();
    assert_eq!(e.unit_for_wavelength, Some(WavelengthUnit::Micrometers));
    assert_eq!(e.interpolation, Interpolation::Held);
    let grey = scene
        .meshes
        .iter()
        .find(|m| m.path == "/World/Grey")
        .unwrap();
    assert_eq!(
        grey.spectral.ior.as_ref().unwrap().interpolation,
        IorInterpolation::Sellmeier
    );
}

/// Physical light units of `quantity` with a white illuminant.
fn physical(quantity: PhysicalQuantity) -> Option<PhysicalLight> {
    Some(PhysicalLight {
        quantity: Some(quantity),
        illuminant: IlluminantKind::White,
        custom_illuminant: Vec::new(),
    })
}

#[test]
fn renderer_emits_the_converted_radiance() {
    let scene = load_stage(data(), 1.0).unwrap();
    let set = lights(&scene);
    // Rect: L = Φ/(A·π) nits, coloured by the 3000 K blackbody's colour of one nit.
    let mut inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(800.0));
    inputs.illuminant = IlluminantKind::Blackbody;
    inputs.color_temperature = 3000.0;
    let ill = resolve_illuminant(&inputs, ColorSpace::Rec709).unwrap();
    close3(
        radiance(&set, "/World/Lumens"),
        ill.rgb_per_nit * (800.0 / (2.0 * 0.5 * PI)),
        1e-9,
        "photometric rect",
    );
    // Sphere: Φv = K·W over the white illuminant (D65 on 380–780 nm), L = Φv/(4πr²·π).
    let white = resolve_illuminant(
        &PhysicalLightInputs::new(PhysicalQuantity::RadiometricPower(5.0)),
        ColorSpace::Rec709,
    )
    .unwrap();
    assert!(
        white.efficacy > 150.0 && white.efficacy < 400.0,
        "{}",
        white.efficacy
    );
    let area = 4.0 * PI * 0.25 * 0.25;
    close3(
        radiance(&set, "/World/Watts"),
        DVec3::splat(5.0 * white.efficacy / (area * PI)),
        1e-9,
        "radiometric sphere",
    );
    // Distant: E/(π sin²θmax) for the 0.53° sun (`float inputs:angle`: the f32 value).
    let s = ((0.53f32 as f64).to_radians() / 2.0).sin();
    close3(
        radiance(&set, "/World/Sun"),
        DVec3::splat(100000.0 / (PI * s * s)),
        1e-9,
        "photometric sun",
    );
    // Preset D65 emission with intensity 2: D65 is the Rec.709 white, so (2, 2, 2).
    close3(
        radiance(&set, "/World/Preset"),
        DVec3::splat(2.0),
        2e-3,
        "d65 preset",
    );
    // A µm table (held) is the same SPD as its nm version; out-of-gamut (negative) Rec.709
    // components are clamped to 0 on emission.
    let nm = lux::spectral::SpectralInputs {
        emission: Some(lux::spectral::SpectralAttribute {
            values: vec![[500.0, 1.0], [600.0, 1.0]],
            interpolation: lux::spectral::Interpolation::Held,
            ..Default::default()
        }),
        ..Default::default()
    };
    let want = nm
        .emission_rgb_per_nit(ColorSpace::Rec709)
        .unwrap()
        .unwrap()
        .max(DVec3::ZERO);
    let got = radiance(&set, "/World/Micrometres");
    close3(got, want, 1e-6, "µm emission");
    assert!(got.z == 0.0 && got.y > got.x, "{got}");
}

/// lux-spectral takes the shaping factor's integrals from the caller; the renderer computes
/// them with lux-shaping (`Shaping::emitter_integral`). For a real ShapingAPI — a soft,
/// tinted, focused cone — the resulting G must equal an independent midpoint quadrature of the
/// same factor (`ShapingIntegral::integrate`, weighted by the luminance of the light's colour of
/// one nit), for every area light kind and illuminant colour. lux-spectral's own tests show that
/// Φ = L·A·G for such a G gives back the authored power.
#[test]
fn shaping_integrals_from_lux_shaping_match_a_quadrature_of_the_factor() {
    use lux::math::LightKind;
    use lux::spectral::ShapingIntegral;
    let params = ShapingParams {
        focus: 2.0,
        focus_tint: DVec3::new(0.2, 0.4, 1.0),
        cone_angle_deg: 55.0,
        cone_softness: 0.5,
        ..ShapingParams::default()
    };
    let shaping = Shaping::new(&params, None, ShapingOptions::default()).unwrap();
    // The midpoint rule's error on 1024 cells in cos θ (h = 2/1024) is about h²/24·∫|f''|: the
    // cone's smoothstep ramp (27.5° to 55°, Δθ = 0.48 rad) has |f''| ≤ 6/(Δθ²·sin²27.5°) ≈ 120
    // in cos θ over a band of 0.31, which bounds it near 4·10⁻⁵ of G (measured: 2·10⁻⁶);
    // lux-shaping's integrals add 10⁻¹⁰.
    const TOL: f64 = 1e-4;
    for illuminant in [IlluminantKind::White, IlluminantKind::Blackbody] {
        let mut inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(1200.0));
        inputs.illuminant = illuminant;
        inputs.color_temperature = 2700.0;
        let rgb = resolve_illuminant(&inputs, ColorSpace::Rec709)
            .unwrap()
            .rgb_per_nit;
        for kind in [
            LightKind::Rect,
            LightKind::Disk,
            LightKind::Sphere,
            LightKind::Cylinder,
        ] {
            let g = ShapingIntegral::from_integrals(kind, shaping.emitter_integral(kind), rgb)
                .unwrap()
                .value();
            let factor = |w: DVec3| lux::math::luminance(rgb * shaping.factor(w));
            let q = ShapingIntegral::integrate(kind, factor, 1024)
                .unwrap()
                .value();
            assert!(
                (g - q).abs() < TOL * q,
                "{illuminant:?} {kind:?}: G = {g}, quadrature {q}"
            );
        }
    }
    // An identity shaping has no integrals: G is exactly the unshaped π.
    assert_eq!(Shaping::identity().emitter_integral(LightKind::Rect), None);
    assert_eq!(
        ShapingIntegral::from_integrals(LightKind::Rect, None, DVec3::ONE).unwrap(),
        ShapingIntegral::UNSHAPED
    );
}

fn floor_probe_scene(light: Light, x: f64, z: f64) -> Scene {
    probe_scene(vec![light], x, z)
}

/// A 0.4 × 0.2 RectLight of `photometric:power` 800 lm, `d` above the floor, facing down.
fn lumen_rect(path: &str, d: f64) -> Light {
    let mut l = Light::with_defaults(
        path,
        LightShape::Rect {
            width: 0.4,
            height: 0.2,
        },
        DMat4::from_rotation_translation(
            DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::NEG_Y),
            DVec3::new(0.0, d, 0.0),
        ),
    );
    l.api_schemas = vec!["PhotometricAreaLightAPI".into()];
    l.physical = physical(PhysicalQuantity::PhotometricPower(800.0));
    l
}

#[test]
fn rendered_irradiance_matches_the_authored_power() {
    // A shaped rect of 800 lm (cone 30°, softness 0.4, focus 1.5) 40 units above the floor,
    // aimed down: far away it is a point source whose on-axis intensity is
    // I(0) = L·A·f(0) with L = Φ/(A·G), so E = Φ·f(0)/(G·d²) — G from lux-shaping.
    let d = 40.0;
    let params = ShapingParams {
        focus: 1.5,
        cone_angle_deg: 30.0,
        cone_softness: 0.4,
        ..ShapingParams::default()
    };
    let shaping = Shaping::new(&params, None, ShapingOptions::default()).unwrap();
    let g = shaping.integral_cos_hemisphere()[0];
    let mut l = lumen_rect("/Lumens", d);
    l.api_schemas.push("ShapingAPI".into());
    l.shaping = Some(lux::usd::ShapingInputs {
        focus: 1.5,
        cone_angle_deg: 30.0,
        cone_softness: 0.4,
        ..Default::default()
    });
    let e = probe(&floor_probe_scene(l, 0.0, 0.0), 64) * PI;
    let want = 800.0 / (g * d * d);
    assert!((e - want).abs() < 1e-3 * want, "E = {e} lux, want {want}");

    // A PhotometricDistantLightAPI sun of 50 000 lux at 30° from the zenith: E = 50000·cos 30°.
    let mut sun = Light::with_defaults(
        "/Sun",
        LightShape::Distant { angle_deg: 0.53 },
        DMat4::from_quat(DQuat::from_rotation_arc(
            DVec3::NEG_Z,
            DVec3::new(0.5, -(3f64.sqrt()) / 2.0, 0.0),
        )),
    );
    sun.api_schemas = vec!["PhotometricDistantLightAPI".into()];
    sun.physical = physical(PhysicalQuantity::PhotometricIlluminance(50000.0));
    let e = probe(&floor_probe_scene(sun, 0.0, 0.0), 64) * PI;
    let want = 50000.0 * (3f64.sqrt() / 2.0);
    assert!((e - want).abs() < 1e-3 * want, "sun E = {e}, want {want}");

    // A PhotometricDomeLightAPI of 20 000 lux without a texture: the upward floor receives it.
    let mut dome = Light::with_defaults("/Sky", LightShape::Dome, DMat4::IDENTITY);
    dome.api_schemas = vec!["PhotometricDomeLightAPI".into()];
    dome.physical = physical(PhysicalQuantity::PhotometricIlluminance(20000.0));
    let e = probe(&floor_probe_scene(dome, 0.0, 0.0), 1024) * PI;
    assert!((e - 20000.0).abs() < 2e-3 * 20000.0, "dome E = {e}");
}

/// A linear EXR texture of `w × h` texels from `f(x, y)`, in a per-process temporary folder.
fn exr_texture(name: &str, w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3]) -> PathBuf {
    use lux::render::image_io::{ImageRgba, write_exr};
    let dir = std::env::temp_dir().join(format!("lux-physical-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    let pixels = (0..w * h)
        .map(|i| {
            let [r, g, b] = f(i % w, i / w);
            [r, g, b, 1.0]
        })
        .collect();
    write_exr(
        &p,
        &ImageRgba {
            width: w,
            height: h,
            pixels,
        },
    )
    .unwrap();
    p
}

/// Rec.709 luminance of the probed pixel times π: the illuminance at the probed floor point.
fn probed_illuminance(scene: &Scene, spp: u32) -> f64 {
    let mut o = common::options(Profile::Spec, spp, [1, 1]);
    o.selection = LightSelection::All;
    let p = Renderer::new(scene, o).unwrap().pixel_value(0, 0);
    PI * lux::math::luminance(p.truncate())
}

#[test]
fn textured_rect_power_counts_the_texture() {
    // 800 lm from a rect whose texture (mean luminance well below 1, coloured) multiplies its
    // emission: far above the floor it is a Lambertian point source of intensity Φ/π, so the
    // floor under it receives E = Φ/(π·d²) whatever the texture, as the proposal asks
    // ("taking into account all aspects of the light including … textures").
    let d = 40.0;
    let tex = exr_texture("rect_texture.exr", 4, 2, |x, y| {
        [
            0.1 + 0.5 * x as f32,
            0.2 * (y + 1) as f32,
            0.05 * (x * y) as f32,
        ]
    });
    let mut l = lumen_rect("/TexturedLumens", d);
    l.texture = Some(lux::usd::AssetRef {
        authored: "rect_texture.exr".into(),
        resolved: Some(tex),
    });
    let e = probed_illuminance(&floor_probe_scene(l, 0.0, 0.0), 4096);
    let want = 800.0 / (PI * d * d);
    assert!((e - want).abs() < 2e-3 * want, "E = {e} lux, want {want}");
}

#[test]
fn dome_illuminance_follows_the_stage_up_axis_through_pole_axis() {
    // A latlong sky bright in its upper half (texture +Y) and black below. With poleAxis "Y" on
    // a Y-up stage the whole sky above the floor is bright; with "Z" the texture's +Y turns to
    // world +Z, so only half of the floor's hemisphere is bright. Either way the photometric
    // dome must deliver the authored 20 000 lux to the upward floor: the cosine-weighted mean
    // is taken about the stage's up axis in the texture's frame.
    // 64 × 32 texels: the renderer's bilinear lookup softens the horizon edge over one texel,
    // which moves E by ≈ 0.04 % (0.65 % at 16 × 8) from the piecewise-constant mean.
    let tex = exr_texture("half_sky.exr", 64, 32, |_, y| {
        if y < 16 {
            [1.0, 1.0, 1.0]
        } else {
            [0.0, 0.0, 0.0]
        }
    });
    for pole in [PoleAxis::Y, PoleAxis::Z] {
        let mut dome = Light::with_defaults("/Sky", LightShape::Dome, DMat4::IDENTITY);
        dome.type_name = "DomeLight_1".into();
        dome.pole_axis = pole;
        dome.api_schemas = vec!["PhotometricDomeLightAPI".into()];
        dome.physical = physical(PhysicalQuantity::PhotometricIlluminance(20000.0));
        dome.texture = Some(lux::usd::AssetRef {
            authored: "half_sky.exr".into(),
            resolved: Some(tex.clone()),
        });
        let e = probed_illuminance(&floor_probe_scene(dome, 0.0, 0.0), 1 << 14);
        assert!(
            (e - 20000.0).abs() < 2e-3 * 20000.0,
            "poleAxis {pole:?}: E = {e} lux"
        );
    }
}

#[test]
fn spectral_reflectance_sets_the_albedo() {
    let scene = load_stage(data(), 1.0).unwrap();
    // The Grey triangle's constant 0.5 reflectance under the white point is ≈ grey 0.5.
    let mut s = floor_probe_scene(
        Light::with_defaults(
            "/Sun",
            LightShape::Distant { angle_deg: 0.0 },
            DMat4::from_quat(DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::NEG_Y)),
        ),
        0.0,
        0.0,
    );
    s.lights[0].params.intensity = PI;
    s.meshes[0].spectral = scene
        .meshes
        .iter()
        .find(|m| m.path == "/World/Grey")
        .unwrap()
        .spectral
        .clone();
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.spp = 4;
    o.resolution = Some([1, 1]);
    let v = Renderer::new(&s, o).unwrap().pixel_value(0, 0);
    for c in [v.x, v.y, v.z] {
        assert!((c - 0.5).abs() < 5e-3, "{v}");
    }
}

/// Spectra lux-spectral refuses: the light (or surface) is named in a warning and left out (or
/// shaded with its colour) — the other lights still render; a strict render refuses them.
#[test]
fn bad_spectra_are_warnings_naming_the_prim_and_errors_when_strict() {
    let options = |strict| LightOptions {
        cone_clipping: true,
        profile: Profile::Spec,
        selection: LightSelection::All,
        strict,
    };
    let mut l = Light::with_defaults("/Bad", LightShape::Sphere { radius: 0.1 }, DMat4::IDENTITY);
    l.emission_spectrum = Some(SpectralAttribute {
        values: vec![[600.0, 1.0], [500.0, 1.0]],
        ..SpectralAttribute::default()
    });
    let mut s = floor_probe_scene(l, 0.0, 0.0);
    s.lights.push(lumen_rect("/Good", 2.0));
    let set = LightSet::new(&s, options(false)).unwrap();
    assert_eq!(set.lights.len(), 1, "the good light still renders");
    assert_eq!(set.lights[0].base().path, "/Good");
    let w = set
        .warnings
        .iter()
        .find(|w| w.contains("/Bad"))
        .expect("a warning names the light");
    assert!(
        w.contains("wavelength:emission") && w.ends_with("the light is not rendered"),
        "{w}"
    );
    let e = LightSet::new(&s, options(true))
        .err()
        .expect("unsorted wavelengths are refused when strict");
    let msg = e.to_string();
    assert!(
        msg.contains("/Bad") && msg.contains("wavelength:emission"),
        "{msg}"
    );
    // Empty without a preset.
    let mut l = Light::with_defaults(
        "/Empty",
        LightShape::Sphere { radius: 0.1 },
        DMat4::IDENTITY,
    );
    l.emission_spectrum = Some(SpectralAttribute::default());
    let s = floor_probe_scene(l, 0.0, 0.0);
    assert!(LightSet::new(&s, options(true)).is_err());
    assert!(LightSet::new(&s, options(false)).unwrap().lights.is_empty());
    // A bad reflectance on a gprim: a warning naming the gprim, its own colour used; an error
    // when strict.
    let mut s = floor_probe_scene(
        Light::with_defaults("/L", LightShape::Sphere { radius: 0.1 }, DMat4::IDENTITY),
        0.0,
        0.0,
    );
    s.meshes[0].spectral.reflectance = Some(SpectralAttribute {
        values: vec![[400.0, 1.5], [700.0, 0.5]],
        ..SpectralAttribute::default()
    });
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    let r = Renderer::new(&s, o.clone()).unwrap();
    assert!(
        r.warnings().any(|w| w.contains("/Floor")),
        "a warning names the gprim"
    );
    o.strict = true;
    let e = Renderer::new(&s, o)
        .err()
        .expect("reflectance above 1 is refused when strict");
    assert!(e.to_string().contains("/Floor"), "{e}");
}
