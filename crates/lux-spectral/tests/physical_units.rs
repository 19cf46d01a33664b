//! Physical light units: power → luminance → power by independent quadrature of the emitted
//! flux (over the surface and all directions, with shaping), dome/distant illuminance, 683 lm/W.

mod common;

use common::rel;
use glam::DVec3;
use lux_math::LightKind;
use lux_spectral::*;
use std::f64::consts::PI;

/// A focus-like test shaping: |cos θ|^k about the light's −Z axis.
fn focus(k: i32) -> impl Fn(DVec3) -> f64 {
    move |w: DVec3| w.z.abs().powi(k)
}

/// Orthonormal tangents of a unit normal.
fn basis(n: DVec3) -> (DVec3, DVec3) {
    let a = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let t = n.cross(a).normalize();
    (t, n.cross(t))
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    Rect(f64, f64),
    Disk(f64),
    Sphere(f64),
    Cylinder(f64, f64),
}

/// Surface points (position is irrelevant here, only the normal and the area weight) by an
/// equal-area midpoint grid; returns (normal, area) cells.
fn surface(shape: Shape, n: usize) -> Vec<(DVec3, f64)> {
    let mut cells = Vec::new();
    for i in 0..n {
        for j in 0..2 * n {
            let (u, v) = (
                (i as f64 + 0.5) / n as f64,
                (j as f64 + 0.5) / (2 * n) as f64,
            );
            let da = 1.0 / (2 * n * n) as f64;
            match shape {
                Shape::Rect(w, h) => cells.push((-DVec3::Z, w * h * da)),
                Shape::Disk(r) => cells.push((-DVec3::Z, PI * r * r * da)),
                Shape::Sphere(r) => {
                    let z = -1.0 + 2.0 * u;
                    let s = (1.0 - z * z).sqrt();
                    let phi = 2.0 * PI * v;
                    cells.push((
                        DVec3::new(s * phi.cos(), s * phi.sin(), z),
                        4.0 * PI * r * r * da,
                    ));
                }
                Shape::Cylinder(r, len) => {
                    let phi = 2.0 * PI * v;
                    cells.push((
                        DVec3::new(0.0, phi.cos(), phi.sin()),
                        2.0 * PI * r * len * da,
                    ));
                }
            }
        }
    }
    cells
}

/// Φ = ∫_A ∫_{H(n)} L f(ω) (ω·n) dω dA by midpoint quadrature (cos θ, φ) around each normal.
fn flux_by_quadrature(shape: Shape, luminance: f64, f: &dyn Fn(DVec3) -> f64) -> f64 {
    let (nc, np) = (48, 96);
    let dw = (1.0 / nc as f64) * (2.0 * PI / np as f64);
    let mut total = 0.0;
    for (n, da) in surface(shape, 24) {
        let (t, b) = basis(n);
        let mut s = 0.0;
        for i in 0..nc {
            let c = (i as f64 + 0.5) / nc as f64;
            let sn = (1.0 - c * c).sqrt();
            for j in 0..np {
                let phi = (j as f64 + 0.5) * 2.0 * PI / np as f64;
                let w = t * (sn * phi.cos()) + b * (sn * phi.sin()) + n * c;
                s += f(w) * c;
            }
        }
        total += luminance * s * dw * da;
    }
    total
}

#[test]
fn shaping_integral_closed_forms() {
    let g = |s, f: &dyn Fn(DVec3) -> f64| ShapingIntegral::integrate(s, f, 256).unwrap().value();
    for shape in [
        LightKind::Rect,
        LightKind::Disk,
        LightKind::Sphere,
        LightKind::Cylinder,
    ] {
        assert!(rel(g(shape, &|_| 1.0), PI) < 1e-4, "{shape:?} unshaped");
    }
    // ∫_H cos^k cos dω = 2π/(k+2);  ¼ ∫_S² |cos|^k dω = π/(k+1).
    assert!(rel(g(LightKind::Rect, &focus(4)), 2.0 * PI / 6.0) < 1e-4);
    assert!(rel(g(LightKind::Sphere, &focus(4)), PI / 5.0) < 1e-4);
    assert_eq!(
        ShapingIntegral::sphere(4.0 * PI).unwrap(),
        ShapingIntegral::UNSHAPED
    );
    assert_eq!(
        ShapingIntegral::cylinder(PI * PI).unwrap(),
        ShapingIntegral::UNSHAPED
    );
    assert!(ShapingIntegral::new(0.0).is_err() && ShapingIntegral::new(f64::NAN).is_err());
    // G is defined for the four area light kinds only; the others are typed errors, not a
    // silent flat emitter
    for kind in [
        LightKind::Distant,
        LightKind::Dome,
        LightKind::Portal,
        LightKind::Mesh,
    ] {
        let want = Err(SpectralError::NotAnAreaEmitter {
            light: kind.usd_type_name(),
        });
        assert_eq!(ShapingIntegral::integrate(kind, |_| 1.0, 16), want);
        assert_eq!(
            ShapingIntegral::from_integrals(kind, None, DVec3::ONE),
            want
        );
        assert_eq!(
            ShapingIntegral::from_integrals(kind, Some(DVec3::ONE), DVec3::ONE),
            want
        );
        assert_eq!(
            ShapingIntegral::from_integrals_textured(kind, None, DVec3::ONE, DVec3::splat(0.5)),
            want
        );
    }
}

#[test]
fn power_to_luminance_to_power_round_trip_by_quadrature() {
    let shapes = [
        (Shape::Rect(2.0, 0.5), LightKind::Rect),
        (Shape::Disk(0.7), LightKind::Disk),
        (Shape::Sphere(0.3), LightKind::Sphere),
        (Shape::Cylinder(0.2, 1.5), LightKind::Cylinder),
    ];
    for (shape, emitter) in shapes {
        let area = match shape {
            Shape::Rect(w, h) => w * h,
            Shape::Disk(r) => PI * r * r,
            Shape::Sphere(r) => 4.0 * PI * r * r,
            Shape::Cylinder(r, l) => 2.0 * PI * r * l,
        };
        for k in [0, 4] {
            let f = focus(k);
            let shaping = if k == 0 {
                ShapingIntegral::UNSHAPED
            } else {
                ShapingIntegral::integrate(emitter, &f, 512).unwrap()
            };
            let geometry = LightGeometry::Area {
                world_area: area,
                shaping,
            };
            // Photometric: 1600 lm.
            let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(1600.0));
            let e = emitted(&inputs, &geometry, ColorSpace::Rec709).unwrap();
            let flux = flux_by_quadrature(shape, e.luminance, &f);
            assert!(rel(flux, 1600.0) < 5e-3, "{shape:?} k={k}: {flux} lm");
            assert_eq!(e.rgb, DVec3::splat(e.luminance)); // white: rgb (1,1,1) per nit
            // Radiometric, blackbody 3000 K: 2.34 W over [380, 780] nm.
            let mut inputs = PhysicalLightInputs::new(PhysicalQuantity::RadiometricPower(2.34));
            inputs.illuminant = IlluminantKind::Blackbody;
            inputs.color_temperature = 3000.0;
            let e = emitted(&inputs, &geometry, ColorSpace::Rec709).unwrap();
            let k_eff =
                Spectrum::Blackbody(Blackbody::visible(3000.0).unwrap()).luminous_efficacy();
            let watts = flux_by_quadrature(shape, e.luminance, &f) / k_eff;
            assert!(rel(watts, 2.34) < 5e-3, "{shape:?} k={k}: {watts} W");
            assert!(rel(ColorSpace::Rec709.luminance(e.rgb), e.luminance) < 1e-12);
        }
    }
}

/// The same round trip with an RGB shaping factor whose integrals the caller supplies (as the
/// renderer does from lux-shaping): a tinted focus, f_c(ω) = t_c + (1 − t_c)·cos²θ (the
/// ShapingAPI's `lerp(|cos θ|^focus, focusTint, white)` with focus 2), whose integrals have
/// closed forms — flat ∫_H f_c cos θ dω = t_c·π + (1 − t_c)·π/2; sphere ∫_{S²} f_c dω =
/// t_c·4π + (1 − t_c)·4π/3; cylinder (axis X, ω = (cos α, sin α cos β, sin α sin β))
/// ∫_{S²} f_c √(1 − ω_x²) dω = t_c·π² + (1 − t_c)·∫ sin⁴α dα ∫ sin²β dβ = t_c·π² + (1 − t_c)·3π²/8.
/// The emitted luminous flux, integrated over the surface and all directions with the factor
/// weighted by the light's colour of one nit, must give back the authored power.
#[test]
fn power_round_trip_with_caller_supplied_rgb_integrals() {
    let tint = [0.2, 0.4, 1.0];
    let integrals = |per_channel: &dyn Fn(f64) -> f64| tint.map(per_channel);
    let shapes = [
        (
            Shape::Rect(2.0, 0.5),
            LightKind::Rect,
            integrals(&|t| t * PI + (1.0 - t) * PI / 2.0),
        ),
        (
            Shape::Disk(0.7),
            LightKind::Disk,
            integrals(&|t| t * PI + (1.0 - t) * PI / 2.0),
        ),
        (
            Shape::Sphere(0.3),
            LightKind::Sphere,
            integrals(&|t| t * 4.0 * PI + (1.0 - t) * 4.0 * PI / 3.0),
        ),
        (
            Shape::Cylinder(0.2, 1.5),
            LightKind::Cylinder,
            integrals(&|t| t * PI * PI + (1.0 - t) * 3.0 * PI * PI / 8.0),
        ),
    ];
    for illuminant in [IlluminantKind::White, IlluminantKind::Blackbody] {
        let mut inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(1200.0));
        inputs.illuminant = illuminant;
        inputs.color_temperature = 2700.0;
        let ill = resolve_illuminant(&inputs, ColorSpace::Rec709).unwrap();
        for (shape, emitter, channel_integrals) in shapes {
            let g = ShapingIntegral::from_integrals(
                emitter,
                Some(DVec3::from(channel_integrals)),
                ill.rgb_per_nit,
            )
            .unwrap();
            let area = match shape {
                Shape::Rect(w, h) => w * h,
                Shape::Disk(r) => PI * r * r,
                Shape::Sphere(r) => 4.0 * PI * r * r,
                Shape::Cylinder(r, l) => 2.0 * PI * r * l,
            };
            let geometry = LightGeometry::Area {
                world_area: area,
                shaping: g,
            };
            let e = emitted(&inputs, &geometry, ColorSpace::Rec709).unwrap();
            let f = |w: DVec3| {
                let c2 = w.z * w.z;
                lux_math::luminance(ill.rgb_per_nit * DVec3::from(tint.map(|t| t + (1.0 - t) * c2)))
            };
            let flux = flux_by_quadrature(shape, e.luminance, &f);
            assert!(
                rel(flux, 1200.0) < 5e-3,
                "{illuminant:?} {shape:?}: {flux} lm"
            );
        }
    }
    // No integrals (an unshaped light) is exactly the unshaped π.
    assert_eq!(
        ShapingIntegral::from_integrals(LightKind::Rect, None, DVec3::ONE).unwrap(),
        ShapingIntegral::UNSHAPED
    );
}

#[test]
fn textured_shaping_integral_weights_the_texture_mean() {
    let id = None; // unshaped
    let white = DVec3::ONE;
    let flat = LightKind::Rect;
    // a white texture is the untextured G
    assert_eq!(
        ShapingIntegral::from_integrals_textured(flat, id, white, DVec3::ONE).unwrap(),
        ShapingIntegral::from_integrals(flat, id, white).unwrap()
    );
    // unshaped: G = π · Y(rgb_per_nit · mean); a grey mean of ½ halves G
    let half = ShapingIntegral::from_integrals_textured(flat, id, white, DVec3::splat(0.5));
    assert!(rel(half.unwrap().value(), 0.5 * PI) < 1e-12);
    let tint = DVec3::new(0.2, 0.7, 0.1);
    let g = ShapingIntegral::from_integrals_textured(flat, id, white, tint).unwrap();
    let want = PI * lux_math::luminance(tint);
    assert!(rel(g.value(), want) < 1e-12, "{} vs {want}", g.value());
    // no power is reachable through a black texture; bad texels are typed errors
    for bad in [
        DVec3::ZERO,
        DVec3::new(-0.1, 0.5, 0.5),
        DVec3::new(f64::NAN, 0.5, 0.5),
        DVec3::new(0.5, f64::INFINITY, 0.5),
    ] {
        assert!(
            ShapingIntegral::from_integrals_textured(flat, id, white, bad).is_err(),
            "{bad:?}"
        );
    }
}

#[test]
fn dome_illuminance_round_trip_with_a_textured_sky() {
    // Texture luminance Y(ω) = 1 + 0.5 cos θ about up: m = (1/π)(π + π/3) = 4/3.
    let m = 4.0 / 3.0;
    let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricIlluminance(10000.0));
    let e = emitted(
        &inputs,
        &LightGeometry::Dome {
            cosine_weighted_mean: m,
        },
        ColorSpace::Rec709,
    )
    .unwrap();
    // E = ∫_{H+} L Y(ω) cos θ dω by midpoint quadrature in θ.
    let n = 2000;
    let mut e_up = 0.0;
    for i in 0..n {
        let th = (i as f64 + 0.5) * (PI / 2.0) / n as f64;
        e_up += e.luminance * (1.0 + 0.5 * th.cos()) * th.cos() * th.sin() * 2.0 * PI * (PI / 2.0)
            / n as f64;
    }
    assert!(rel(e_up, 10000.0) < 1e-5, "{e_up}");
    assert!(rel(e.luminance, 10000.0 / (PI * m)) < 1e-12);
}

#[test]
fn distant_illuminance_for_any_angle() {
    for angle in [0.53, 10.0, 80.0, 179.0, 200.0, 359.0] {
        let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricIlluminance(10000.0));
        let e = emitted(
            &inputs,
            &LightGeometry::Distant { angle_deg: angle },
            ColorSpace::Rec709,
        )
        .unwrap();
        assert!(!e.delta);
        // Illuminance on a facing one-sided patch: ∫ over the cone ∩ front hemisphere of L cos θ.
        let tmax = (angle.to_radians() / 2.0).min(PI / 2.0);
        let n = 4000;
        let mut got = 0.0;
        for i in 0..n {
            let th = (i as f64 + 0.5) * tmax / n as f64;
            got += e.luminance * th.cos() * th.sin() * 2.0 * PI * tmax / n as f64;
        }
        assert!(rel(got, 10000.0) < 1e-5, "{angle}°: {got}");
    }
    let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricIlluminance(500.0));
    let e = emitted(
        &inputs,
        &LightGeometry::Distant { angle_deg: 0.0 },
        ColorSpace::Rec709,
    )
    .unwrap();
    assert!(e.delta && e.luminance == 500.0);
}

#[test]
fn radiometric_irradiance_uses_the_illuminant_efficacy() {
    let inputs = PhysicalLightInputs::new(PhysicalQuantity::RadiometricIrradiance(14.64));
    let e = emitted(
        &inputs,
        &LightGeometry::Distant { angle_deg: 0.0 },
        ColorSpace::Rec709,
    )
    .unwrap();
    let k = resolve_illuminant(&inputs, ColorSpace::Rec709)
        .unwrap()
        .efficacy;
    assert!(rel(e.luminance, 14.64 * k) < 1e-12);
    // D65 over [380, 780] nm: K = 683·∫Sȳ/∫S, computed here by 1 nm trapezoids from the tables.
    let d65 = Illuminant::D65.spectrum();
    let (mut num, mut den) = (0.0, 0.0);
    for l in 380..=780 {
        let w = if l == 380 || l == 780 { 0.5 } else { 1.0 };
        num += w * d65.eval(l as f64) * cmf(l as f64).y;
        den += w * d65.eval(l as f64);
    }
    assert!(
        rel(k, 683.0 * num / den) < 1e-4,
        "{k} vs {}",
        683.0 * num / den
    );
}

#[test]
fn monochromatic_555_nm_is_683_lm_per_w() {
    // A 1 W·sr⁻¹·m⁻² line of 0.2 nm full width at 555 nm (ȳ(555) = 1): 683 nits.
    let s = SampledSpectrum::new(
        vec![554.9, 555.0, 555.1],
        vec![0.0, 10.0, 0.0],
        Interpolation::Linear,
    )
    .unwrap();
    assert!((s.integral() - 1.0).abs() < 1e-12);
    let sp = Spectrum::Sampled(s);
    assert!(rel(sp.luminance(), 683.0) < 1e-5, "{}", sp.luminance());
    assert!(rel(sp.luminous_efficacy(), 683.0) < 1e-5);
    // Held: a 1 nm box [555, 556) of 1 W/nm: 683·∫ȳ over the box.
    let s = SampledSpectrum::new(vec![555.0, 556.0], vec![1.0, 1.0], Interpolation::Held).unwrap();
    let y = 683.0 * 0.5 * (cmf(555.0).y + cmf(556.0).y);
    assert!(rel(Spectrum::Sampled(s).luminance(), y) < 1e-12);
}

#[test]
fn bad_physical_inputs_give_typed_errors() {
    let area = LightGeometry::Area {
        world_area: 1.0,
        shaping: ShapingIntegral::UNSHAPED,
    };
    let mut inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(f64::NAN));
    assert!(matches!(
        emitted(&inputs, &area, ColorSpace::Rec709),
        Err(SpectralError::InvalidValue { .. })
    ));
    inputs.quantity = PhysicalQuantity::PhotometricPower(-1.0);
    assert!(emitted(&inputs, &area, ColorSpace::Rec709).is_err());
    inputs.quantity = PhysicalQuantity::PhotometricPower(100.0);
    let bad_area = LightGeometry::Area {
        world_area: 0.0,
        shaping: ShapingIntegral::UNSHAPED,
    };
    assert!(emitted(&inputs, &bad_area, ColorSpace::Rec709).is_err());
    let dome = LightGeometry::Dome {
        cosine_weighted_mean: 1.0,
    };
    assert!(matches!(
        emitted(&inputs, &dome, ColorSpace::Rec709),
        Err(SpectralError::QuantityMismatch { .. })
    ));
    inputs.illuminant = IlluminantKind::Custom;
    let err = emitted(&inputs, &area, ColorSpace::Rec709).unwrap_err();
    assert!(
        err.to_string().contains("physical:customIlluminant"),
        "{err}"
    );
    // Entirely infrared: no luminance.
    inputs.custom_illuminant = vec![[900.0, 1.0], [1000.0, 1.0]];
    assert!(matches!(
        emitted(&inputs, &area, ColorSpace::Rec709),
        Err(SpectralError::ZeroLuminance { .. })
    ));
    inputs.custom_illuminant = vec![[500.0, 1.0], [600.0, -1.0]];
    assert!(emitted(&inputs, &area, ColorSpace::Rec709).is_err());
    inputs.illuminant = IlluminantKind::Blackbody;
    inputs.color_temperature = -5.0;
    assert!(emitted(&inputs, &area, ColorSpace::Rec709).is_err());
    assert_eq!(
        IlluminantKind::parse("blackbody").unwrap(),
        IlluminantKind::Blackbody
    );
    assert!(IlluminantKind::parse("Blackbody").is_err());
}

#[test]
fn latlong_cosine_weighted_mean_of_sky_textures() {
    let (w, h) = (256, 128);
    // Uniform texture: m = 1, exactly for the piecewise-constant texture whatever its size,
    // for the axes and, up to the horizon cells' finest split, for any up direction.
    for (tw, th) in [(w, h), (4, 2), (16, 8), (3, 5), (1, 1)] {
        let ones = vec![1.0f32; tw * th];
        for up in [DVec3::Y, DVec3::Z, -DVec3::Y, DVec3::X] {
            let m = latlong_cosine_weighted_mean(tw, th, &ones, up).unwrap();
            assert!((m - 1.0).abs() < 1e-12, "{tw}×{th} up {up}: {m}");
        }
        let up = DVec3::new(0.3, -0.8, 0.52);
        let m = latlong_cosine_weighted_mean(tw, th, &ones, up).unwrap();
        assert!((m - 1.0).abs() < 1e-5, "{tw}×{th} up {up}: {m}");
    }
    // A 4 × 2 texture, bright only in the upper row: its cells are whole hemispheres about
    // ±Y, so up = +Y gives the bright row's m = 1 and up = −Y gives 0; about +X, the upper
    // row is a quarter sphere around the horizon's pole: m = ½ (half of the +X hemisphere).
    let top = [1.0f32, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let m = |up| latlong_cosine_weighted_mean(4, 2, &top, up).unwrap();
    assert!((m(DVec3::Y) - 1.0).abs() < 1e-12 && m(-DVec3::Y).abs() < 1e-15);
    assert!((m(DVec3::X) - 0.5).abs() < 1e-12, "{}", m(DVec3::X));
    // Gradient Y = 1 + 0.5·cos θ about +Y (row-dependent): m = 4/3 (see the dome test).
    let mut grad = vec![0.0f32; w * h];
    for r in 0..h {
        let th = std::f64::consts::PI * (r as f64 + 0.5) / h as f64;
        for c in 0..w {
            grad[r * w + c] = (1.0 + 0.5 * th.cos()) as f32;
        }
    }
    let m = latlong_cosine_weighted_mean(w, h, &grad, DVec3::Y).unwrap();
    assert!((m - 4.0 / 3.0).abs() < 1e-4, "{m}");
    // Only the +X half (u in [0, 0.5), φ > 0) lit, up = +X: m = 1; up = −X: m = 0.
    let mut half = vec![0.0f32; w * h];
    for r in 0..h {
        for c in 0..w / 2 {
            half[r * w + c] = 1.0;
        }
    }
    assert!((latlong_cosine_weighted_mean(w, h, &half, DVec3::X).unwrap() - 1.0).abs() < 1e-3);
    assert_eq!(
        latlong_cosine_weighted_mean(w, h, &half, -DVec3::X).unwrap(),
        0.0
    );
    // Bad input.
    assert!(latlong_cosine_weighted_mean(0, 4, &[], DVec3::Y).is_err());
    assert!(latlong_cosine_weighted_mean(2, 2, &[1.0; 3], DVec3::Y).is_err());
    assert!(latlong_cosine_weighted_mean(2, 1, &[1.0, f32::NAN], DVec3::Y).is_err());
    assert!(latlong_cosine_weighted_mean(2, 1, &[1.0, 1.0], DVec3::ZERO).is_err());
}

/// `LightGeometry::from_shape`: the light described once (its `LightShape` and transform), the
/// exact world area under a non-uniform scale, and 1000 lm on a sphere light of radius r
/// converted to the luminance `Φ / (4πr²·π)` that gives the lumens back.
#[test]
fn light_geometry_from_shape() {
    use lux_math::{LightShape, LightTransform, Profile};
    let stretch = LightTransform::new(glam::DMat4::from_scale(DVec3::new(3.0, 0.5, 2.0))).unwrap();
    let rect = LightShape::Rect {
        width: 2.0,
        height: 1.0,
    };
    let g = LightGeometry::from_shape(&rect, &stretch, Profile::Spec, ShapingIntegral::UNSHAPED)
        .unwrap();
    assert_eq!(
        g,
        LightGeometry::Area {
            world_area: 6.0 * 0.5,
            shaping: ShapingIntegral::UNSHAPED
        }
    );
    let r = 0.25;
    let at = LightTransform::from_translation(DVec3::new(1.0, 2.0, 3.0));
    let sphere = LightShape::Sphere { radius: r };
    let g =
        LightGeometry::from_shape(&sphere, &at, Profile::Spec, ShapingIntegral::UNSHAPED).unwrap();
    let inputs = PhysicalLightInputs::new(PhysicalQuantity::PhotometricPower(1000.0));
    let e = emitted(&inputs, &g, ColorSpace::Rec709).unwrap();
    let area = 4.0 * PI * r * r;
    assert!((e.luminance - 1000.0 / (area * PI)).abs() < 1e-12 * e.luminance);
    assert!((e.luminance * area * PI - 1000.0).abs() < 1e-9);
    assert_eq!(
        LightGeometry::from_shape(
            &LightShape::Distant { angle_deg: 0.53 },
            &at,
            Profile::Spec,
            ShapingIntegral::UNSHAPED
        )
        .unwrap(),
        LightGeometry::Distant { angle_deg: 0.53 }
    );
    assert!(matches!(
        LightGeometry::from_shape(
            &LightShape::Portal {
                width: 1.0,
                height: 1.0
            },
            &at,
            Profile::Spec,
            ShapingIntegral::UNSHAPED
        ),
        Err(SpectralError::NotAnAreaEmitter { .. })
    ));
}
