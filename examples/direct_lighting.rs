//! A renderer's first loop, with the small lux crates only (lux-math, lux-ies, lux-shaping,
//! lux-sample, lux-spectral; no USD, no images, no threads): the direct lighting of one UsdLux
//! light at shading points, in world space. Copy it into your renderer.
//!
//! The light is a `RectLight` of 0.4 × 0.25 under a non-uniform scale, 1.2 above a floor and
//! aimed down, specified physically (`PhotometricAreaLightAPI`, `photometric:power` = 1000 lm,
//! white), shaped by the `ShapingAPI` (a 60° cone with a soft edge, a tinted focus) and an IES
//! profile (`shaping:ies:file` with `ies:normalize`). The chain, one crate per step:
//!
//! 1. the light, described once: its `LightShape` (the schema's `inputs:width`/`height`) and
//!    its light-to-world `LightTransform` (lux-math);
//! 2. the IES profile: `IesFile::parse` → `PhotometricWeb` (lux-ies);
//! 3. the shaping: `Shaping::new` with the `inputs:shaping:*` values and the web (lux-shaping);
//! 4. the emitted radiance: 1000 lm → luminance `L = Φ / (A·G)` with the exact world area
//!    `A` and the shaping integral `G` (lux-spectral's `LightGeometry::from_shape`,
//!    `ShapingIntegral::from_integrals`, lux-shaping's `Shaping::emitter_integral`);
//! 5. the sampler: `lux_sample::Light::from_shape` with the same shape and transform;
//! 6. the estimator at a shading point `(p, n)`: for each light sample `s`,
//!    `L(s) = base · shaping.factor_world(xf, −s.wi)` (the world direction from the light
//!    towards `p`, mapped to light space by `L⁻¹`), and
//!    `E ≈ mean(L(s) · max(0, n·s.wi) / s.pdf)`.
//!
//! Without shaping the same loop converges to the closed form `L · Π`,
//! `Π = light.projected_solid_angle(&Reference)` (one-sided), which `main` prints as a check.
//! `tests/direct_lighting_example.rs` holds this loop to lux's renderer, which renders the same
//! light onto a white floor.
//!
//! ```sh
//! cargo run --release --example direct_lighting
//! ```

use lux_ies::{IesFile, PhotometricWeb};
use lux_math::glam::{DMat4, DQuat, DVec3};
use lux_math::{LightShape, LightTransform, Profile};
use lux_sample::{Light, Reference, SplitMix64};
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
use lux_spectral::{
    ColorSpace, LightGeometry, PhysicalLightInputs, PhysicalQuantity, ShapingIntegral, emitted,
    resolve_illuminant,
};
use std::error::Error;

/// A type C profile, 0–90° vertical, quadrant-symmetric (0–90° horizontal): brighter along
/// C0 than along C90, dark from 90° down.
pub const SPOT_IES: &str = "IESNA:LM-63-2002
[TEST] lux direct_lighting example
TILT=NONE
1 -1 1 7 3 1 2 0 0 0
1 1 10
0 15 30 45 60 75 90
0 45 90
1000 950 800 500 200 50 0
1000 900 700 400 150 30 0
1000 850 600 300 100 10 0
";

/// The light's `inputs:shaping:*` values.
pub fn shaping_params() -> ShapingParams {
    ShapingParams {
        focus: 1.5,
        focus_tint: DVec3::new(0.2, 0.5, 0.9),
        cone_angle_deg: 60.0,
        cone_softness: 0.3,
        ies_angle_scale: 0.0,
        ies_normalize: true,
    }
}

/// `inputs:width`, `inputs:height`.
pub const SHAPE: LightShape = LightShape::Rect {
    width: 0.4,
    height: 0.25,
};

/// `photometric:power`, lm.
pub const LUMENS: f64 = 1000.0;

/// The light-to-world matrix (glam column convention): 1.2 above the origin, its −Z aimed down
/// (world −Y), turned 30° about that axis, stretched 1.5 × along its X and 0.6 × along its Y.
pub fn light_to_world() -> DMat4 {
    let aim = DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::NEG_Y);
    DMat4::from_translation(DVec3::new(0.0, 1.2, 0.0))
        * DMat4::from_quat(aim)
        * DMat4::from_rotation_z(30f64.to_radians())
        * DMat4::from_scale(DVec3::new(1.5, 0.6, 1.0))
}

/// Everything a renderer keeps of one light.
pub struct ShapedLight {
    /// Light → world.
    pub xf: LightTransform,
    /// The ShapingAPI factor, IES profile included.
    pub shaping: Shaping,
    /// Base radiance (RGB nits) before shaping: what 1000 lm come to on this light.
    pub base: DVec3,
    /// The light's sampler.
    pub sampler: Light,
}

impl ShapedLight {
    /// Steps 1–5 of the module documentation (`ies`: the text of the `shaping:ies:file`).
    pub fn new(
        shape: &LightShape,
        light_to_world: DMat4,
        lumens: f64,
        params: &ShapingParams,
        ies: Option<&str>,
    ) -> Result<ShapedLight, Box<dyn Error>> {
        let xf = LightTransform::new(light_to_world)?;
        let web = match ies {
            Some(text) => Some(PhotometricWeb::new(&IesFile::parse(text)?, Profile::Spec)?),
            None => None,
        };
        let shaping = Shaping::new(params, web, ShapingOptions::default())?;
        let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(lumens));
        let rgb_per_nit = resolve_illuminant(&inputs, ColorSpace::Rec709)?.rgb_per_nit;
        let g = ShapingIntegral::from_integrals(
            shape.kind(),
            shaping.emitter_integral(shape.kind()),
            rgb_per_nit,
        )?;
        let geometry = LightGeometry::from_shape(shape, &xf, Profile::Spec, g)?;
        let base = emitted(&inputs, &geometry, ColorSpace::Rec709)?.rgb;
        let sampler = Light::from_shape(shape, &xf)?;
        Ok(ShapedLight {
            xf,
            shaping,
            base,
            sampler,
        })
    }

    /// The radiance arriving at `r` along one light sample (zero when `u` finds no sample):
    /// `(L · cos θ / pdf, …)`, the summand of the irradiance estimator (step 6).
    pub fn sample_irradiance(&self, r: &Reference, u: [f64; 2]) -> DVec3 {
        let Some(s) = self.sampler.sample(r, u) else {
            return DVec3::ZERO;
        };
        let radiance = self.base * self.shaping.factor_world(&self.xf, -s.wi);
        radiance * (r.n.dot(s.wi).max(0.0) / s.pdf)
    }

    /// The irradiance `E` at `(p, n)` from `n` light samples, and its standard error per
    /// channel.
    pub fn irradiance(&self, p: DVec3, n: DVec3, samples: usize, seed: u64) -> (DVec3, DVec3) {
        let r = Reference::surface(p, n);
        let mut rng = SplitMix64::new(seed);
        let (mut sum, mut sum2) = (DVec3::ZERO, DVec3::ZERO);
        for _ in 0..samples {
            let e = self.sample_irradiance(&r, rng.next_2d());
            sum += e;
            sum2 += e * e;
        }
        let k = samples.max(2) as f64;
        let mean = sum / k;
        let var = (sum2 / k - mean * mean).max(DVec3::ZERO) / (k - 1.0);
        (mean, var.powf(0.5))
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let light = ShapedLight::new(
        &SHAPE,
        light_to_world(),
        LUMENS,
        &shaping_params(),
        Some(SPOT_IES),
    )?;
    println!("base radiance of {LUMENS} lm: {:.3} nits", light.base);
    for x in [0.0, 0.3, 0.6, 1.2, 2.5] {
        let p = DVec3::new(x, 0.0, 0.1);
        let (e, se) = light.irradiance(p, DVec3::Y, 100_000, 1);
        println!(
            "E at {p}: {:.4} lx (± {:.4}); a white Lambertian floor reflects {:.4} nits",
            e,
            se,
            e / std::f64::consts::PI
        );
    }
    // Unshaped, the same loop converges to the closed form L·Π (one-sided projected solid
    // angle of the sampler).
    let unshaped = ShapedLight::new(
        &SHAPE,
        light_to_world(),
        LUMENS,
        &ShapingParams::NO_SHAPING,
        None,
    )?;
    let p = DVec3::new(0.3, 0.0, 0.1);
    let (e, se) = unshaped.irradiance(p, DVec3::Y, 100_000, 2);
    let pi = unshaped
        .sampler
        .projected_solid_angle(&Reference::surface(p, DVec3::Y))
        .ok_or("no closed form")?;
    println!(
        "unshaped at {p}: sampled {:.5} lx (± {:.5}), closed form L·Π = {:.5} lx",
        e,
        se,
        unshaped.base * pi
    );
    Ok(())
}
