//! The renderer author's loop of `examples/direct_lighting.rs` (the small crates only: a
//! physically specified, shaped, IES-profiled RectLight under a non-uniform scale) against lux's
//! renderer given the same light as a USD scene: the reflected radiance `E/π` of a white
//! Lambertian floor, read from a 1 × 1 render of the floor point
//! (`tests/common::probe_scene`), agrees with the example's estimate at points across the beam.
//!
//! Tolerance: both are unbiased estimates of the same value, so their difference has mean 0
//! and a standard deviation of at most `√(σ_ex² + σ_render²)`; the test allows 5 of them (a
//! normal deviate beyond 5σ has probability 6·10⁻⁷; the seeds are fixed, so the outcome is
//! deterministic). `σ_render` is the standard error of the pixel's Rec.709 luminance from its
//! sample moments (`Renderer::pixel_moments`, samples treated as independent, which
//! over-estimates it for stratified samples); `σ_ex` is `Σ_c Y_c·σ_c` over the example's
//! per-channel standard errors, an upper bound of its luminance's. Both are held below 0.5 % of
//! the value, so the check resolves the shaping, the IES azimuth and the lumens conversion.

#[path = "../examples/direct_lighting.rs"]
#[allow(dead_code)]
mod example;

mod common;

use example::{LUMENS, SHAPE, SPOT_IES, ShapedLight, light_to_world, shaping_params};
use glam::DVec3;
use lux::math::{Profile, REC709_LUMINANCE, luminance};
use lux::render::render::Renderer;
use lux::render::settings::AdaptiveSampling;
use lux::spectral::{IlluminantKind, PhysicalQuantity};
use lux::usd::{AssetRef, Light, PhysicalLight, ShapingInputs};
use std::f64::consts::PI;

/// The example's light as lux-usd reads it from a stage: `RectLight` with `ShapingAPI`,
/// `PhotometricAreaLightAPI` (`photometric:power` = 1000 lm, white).
fn usd_light() -> Light {
    let dir = std::env::temp_dir().join(format!("lux-direct-lighting-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ies = dir.join("spot.ies");
    std::fs::write(&ies, SPOT_IES).unwrap();
    let p = shaping_params();
    let mut l = Light::with_defaults("/Spot", SHAPE, light_to_world());
    l.api_schemas.push("ShapingAPI".into());
    l.api_schemas.push("PhotometricAreaLightAPI".into());
    l.shaping = Some(ShapingInputs {
        focus: p.focus,
        focus_tint: p.focus_tint,
        cone_angle_deg: p.cone_angle_deg,
        cone_softness: p.cone_softness,
        ies_file: Some(AssetRef {
            authored: "spot.ies".into(),
            resolved: Some(ies),
        }),
        ies_angle_scale: p.ies_angle_scale,
        ies_normalize: p.ies_normalize,
    });
    l.physical = Some(PhysicalLight {
        quantity: Some(PhysicalQuantity::PhotometricPower(LUMENS)),
        illuminant: IlluminantKind::White,
        custom_illuminant: Vec::new(),
    });
    l
}

/// lux's render of the floor point `(x, 0, z)`: the pixel's luminance and its standard error.
fn render(light: &Light, x: f64, z: f64, spp: u32) -> (f64, f64) {
    let scene = common::probe_scene(vec![light.clone()], x, z);
    let mut o = common::options(Profile::Spec, spp, [1, 1]);
    o.adaptive = Some(AdaptiveSampling::OFF);
    let r = Renderer::new(&scene, o).unwrap();
    let (mean, y2) = r.pixel_moments(0, 0);
    let y = luminance(mean.truncate());
    (y, ((y2 - y * y).max(0.0) / f64::from(spp)).sqrt())
}

#[test]
fn the_example_loop_agrees_with_the_renderer() {
    let ex = ShapedLight::new(
        &SHAPE,
        light_to_world(),
        LUMENS,
        &shaping_params(),
        Some(SPOT_IES),
    )
    .unwrap();
    let light = usd_light();
    let mut lit = 0;
    for (x, z) in [(0.0, 0.1), (0.3, 0.1), (0.6, -0.2), (0.1, 0.7), (1.2, 0.1)] {
        let (e, se) = ex.irradiance(DVec3::new(x, 0.0, z), DVec3::Y, 400_000, 7);
        let want = luminance(e) / PI;
        let se_ex = se.dot(REC709_LUMINANCE) / PI;
        let (got, se_render) = render(&light, x, z, 1 << 14);
        let sigma = (se_ex * se_ex + se_render * se_render).sqrt();
        assert!(
            want > 5.0,
            "({x}, {z}): the example's {want} nits is not in the beam"
        );
        assert!(sigma < 5e-3 * want, "({x}, {z}): σ {sigma} of {want}");
        assert!(
            (got - want).abs() < 5.0 * sigma,
            "({x}, {z}): renderer {got} vs example {want} (σ {sigma})"
        );
        lit += 1;
    }
    assert_eq!(lit, 5);
    // outside the 60° cone (stretched to ~69° along the light's X): nothing in either
    let (e, _) = ex.irradiance(DVec3::new(2.5, 0.0, 0.1), DVec3::Y, 10_000, 7);
    assert_eq!(e, DVec3::ZERO);
    assert_eq!(render(&light, 2.5, 0.1, 256).0, 0.0);
}

/// Unshaped, the example's loop converges to the one-sided closed form `L·Π` of the rect under
/// its non-uniform scale (`Light::projected_solid_angle`), within 5 standard errors, and the
/// luminance of 1000 lm on it is `Φ / (A·π)` with the exact world area.
#[test]
fn unshaped_the_loop_converges_to_the_closed_form() {
    let ex = ShapedLight::new(
        &SHAPE,
        light_to_world(),
        LUMENS,
        &lux::shaping::ShapingParams::NO_SHAPING,
        None,
    )
    .unwrap();
    let area = 0.4 * 0.25 * 1.5 * 0.6;
    assert!(
        (ex.base - DVec3::splat(LUMENS / (area * PI)))
            .abs()
            .max_element()
            < 1e-9
    );
    for (x, z) in [(0.0, 0.0), (0.5, -0.3), (1.5, 0.4)] {
        let p = DVec3::new(x, 0.0, z);
        let (e, se) = ex.irradiance(p, DVec3::Y, 200_000, 3);
        let pi = ex
            .sampler
            .projected_solid_angle(&lux::sample::Reference::surface(p, DVec3::Y))
            .unwrap();
        let want = ex.base.x * pi;
        assert!(
            (e.x - want).abs() < 5.0 * se.x.max(1e-12 * want),
            "({x}, {z}): {} ± {} vs {want}",
            e.x,
            se.x
        );
    }
}
