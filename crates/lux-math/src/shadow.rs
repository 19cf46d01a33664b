//! UsdLux `ShadowAPI`: how strongly an occluder shadows a light, and the colour of the shadowed
//! light.

use glam::DVec3;

/// Shadow strength in \[0, 1\] of an occluder at distance `t` from the shaded point
/// (`ShadowAPI` `inputs:shadow:distance` = `max_distance`, `inputs:shadow:falloff` = `falloff`,
/// `inputs:shadow:falloffGamma` = `gamma`):
///
/// - `max_distance` < 0 (the default −1): no limit, strength 1;
/// - `t` > `max_distance`: 0, the occluder is too far to cast a shadow;
/// - with `falloff` > 0 (clamped to `max_distance`), inside the falloff zone
///   `max_distance − falloff < t ≤ max_distance` the strength falls from 1 to 0 as
///   `((max_distance − t) / falloff)^gamma`; closer occluders shadow fully.
///
/// Non-finite inputs: a NaN or infinite `max_distance` counts as no limit, a NaN `falloff`
/// as none, a non-finite or negative `gamma` as 1; a NaN `t` shadows fully.
pub fn shadow_strength(t: f64, max_distance: f64, falloff: f64, gamma: f64) -> f64 {
    if !max_distance.is_finite() || max_distance < 0.0 || t.is_nan() {
        return 1.0;
    }
    if t > max_distance {
        return 0.0;
    }
    let f = if falloff.is_nan() {
        0.0
    } else {
        falloff.min(max_distance)
    };
    if f <= 0.0 || t <= max_distance - f {
        return 1.0;
    }
    let g = if gamma.is_finite() && gamma >= 0.0 {
        gamma
    } else {
        1.0
    };
    ((max_distance - t) / f).clamp(0.0, 1.0).powf(g)
}

/// The multiplier of a light's contribution behind an occluder of strength `s`
/// ([`shadow_strength`]): `lerp(s, white, shadowColor)` per channel (`inputs:shadow:color`,
/// default black, i.e. `1 − s`). Negative or non-finite colour components count as 0.
pub fn shadowed(s: f64, color: DVec3) -> DVec3 {
    let c = if color.is_finite() {
        color.max(DVec3::ZERO)
    } else {
        DVec3::ZERO
    };
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        1.0
    };
    DVec3::ONE * (1.0 - s) + c * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn schema_defaults_shadow_fully_and_black() {
        assert_eq!(shadow_strength(123.0, -1.0, -1.0, 1.0), 1.0);
        assert_eq!(shadowed(1.0, DVec3::ZERO), DVec3::ZERO);
        assert_eq!(shadowed(0.0, DVec3::ZERO), DVec3::ONE);
        assert_eq!(
            shadowed(1.0, DVec3::new(0.2, 0.3, 0.4)),
            DVec3::new(0.2, 0.3, 0.4)
        );
    }

    #[test]
    fn distance_and_falloff_zone() {
        // max 10, falloff 4: full up to 6, linear to 0 at 10, none beyond.
        assert_eq!(shadow_strength(5.0, 10.0, 4.0, 1.0), 1.0);
        assert_eq!(shadow_strength(6.0, 10.0, 4.0, 1.0), 1.0);
        assert_eq!(shadow_strength(8.0, 10.0, 4.0, 1.0), 0.5);
        assert_eq!(shadow_strength(8.0, 10.0, 4.0, 2.0), 0.25);
        assert_eq!(shadow_strength(10.0, 10.0, 4.0, 1.0), 0.0);
        assert_eq!(shadow_strength(10.5, 10.0, 4.0, 1.0), 0.0);
        // No falloff: a hard cut at the max distance.
        assert_eq!(shadow_strength(9.9, 10.0, -1.0, 1.0), 1.0);
        assert_eq!(shadow_strength(10.1, 10.0, -1.0, 1.0), 0.0);
        // A falloff longer than the distance is clamped to it.
        assert_eq!(shadow_strength(5.0, 10.0, 40.0, 1.0), 0.5);
    }

    proptest! {
        #[test]
        fn strength_is_in_unit_range_and_non_increasing(
            t in -1.0e3..1.0e3f64, dt in 0.0..10.0f64,
            d in prop_oneof![Just(-1.0), 0.0..100.0f64, Just(f64::NAN), Just(f64::INFINITY)],
            f in prop_oneof![Just(-1.0), 0.0..100.0f64, Just(f64::NAN)],
            g in prop_oneof![0.0..5.0f64, Just(f64::NAN)],
        ) {
            let a = shadow_strength(t, d, f, g);
            let b = shadow_strength(t + dt, d, f, g);
            prop_assert!((0.0..=1.0).contains(&a));
            prop_assert!(b <= a + 1e-12, "{a} then {b}");
            let c = shadowed(a, DVec3::new(0.5, f64::NAN, -1.0));
            prop_assert!(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0);
        }
    }
}
