//! The authored `ShapingAPI` inputs and the options that choose between documented behaviours.

use glam::DVec3;
use lux_ies::Interpolation;
use lux_math::Profile;

/// The `ShapingAPI` inputs of one light, as authored (UsdLux 26.11 `ShapingAPI`), without the
/// IES file itself (that is passed to [`Shaping::new`](crate::Shaping::new) as a
/// [`lux_ies::PhotometricWeb`]).
///
/// Plain data: nothing is checked or clamped here; [`Shaping::new`](crate::Shaping::new)
/// validates and documents what every out-of-range value does. [`Default`] gives the schema
/// defaults **with `ShapingAPI` applied** (so a 90° cone); a light without the API has no cone
/// at all, which is [`ShapingParams::NO_SHAPING`] / [`Shaping::identity`](crate::Shaping::identity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapingParams {
    /// `inputs:shaping:focus` (schema default 0). When > 0 the emission is multiplied per
    /// channel by `focusColor = lerp(|cos θ|^focus, focusTint, white)`, θ being the angle between
    /// the emission direction and the light's −Z axis. Values ≤ 0 (and NaN) are ignored, as the
    /// schema says; `+∞` is the limit of the formula (the tint everywhere except exactly on the
    /// axis).
    pub focus: f64,
    /// `inputs:shaping:focusTint` (schema default black): the colour the emission fades to away
    /// from the axis when `focus` > 0. White disables the focus. Components must be finite;
    /// negative components are treated as 0 (an emission multiplier cannot be negative).
    pub focus_tint: DVec3,
    /// `inputs:shaping:cone:angle` in degrees (schema default 90): the half-angle, measured from
    /// the light's −Z axis, beyond which nothing is emitted. Angles ≥ 180° never cut; negative
    /// angles cut everything. NaN is rejected.
    pub cone_angle_deg: f64,
    /// `inputs:shaping:cone:softness` (schema default 0): the fraction of the cone, counted
    /// inwards from its edge, over which the emission fades smoothly (Hermite `smoothStep` in
    /// the angle) from 1 to 0. Clamped to \[0, 1\] under [`Profile::Spec`], used as authored under
    /// [`Profile::HdEmbree`] (see [`Shaping::new`](crate::Shaping::new)). NaN counts as 0.
    pub cone_softness: f64,
    /// `inputs:shaping:ies:angleScale` (schema default 0): rescales the polar angle before the
    /// IES profile is looked up (see [`apply_angle_scale`](crate::apply_angle_scale)). Must be
    /// finite.
    pub ies_angle_scale: f64,
    /// `inputs:shaping:ies:normalize` (schema default false): divide the IES sample by the
    /// profile's mean intensity ([`lux_ies::PhotometricWeb::mean_intensity`]: flux/4π, or
    /// flux/2π when the vertical range spans ≤ 95.73°) so that the profile reshapes the
    /// emission without changing its total power. Under [`Profile::Spec`] the normalized IES
    /// factor integrates to exactly 4π over the sphere (mean 1), or 2π for the narrow-range
    /// profiles (mean 1 over their emitting hemisphere when they lie within 0..90° or
    /// 90..180°); for a web built under [`Profile::HdEmbree`] the divisor uses the midpoint-rule
    /// flux. A profile
    /// whose flux is 0 gives an IES factor of 0.
    pub ies_normalize: bool,
}

impl ShapingParams {
    /// The schema defaults of every `inputs:shaping:*` attribute, as on a light with
    /// `ShapingAPI` applied and nothing authored: focus 0, focusTint black, cone 90°,
    /// softness 0, angleScale 0, normalize off. Note the 90° cone: such a light emits only
    /// into the hemisphere around its −Z axis.
    pub const SCHEMA_DEFAULTS: ShapingParams = ShapingParams {
        focus: 0.0,
        focus_tint: DVec3::ZERO,
        cone_angle_deg: 90.0,
        cone_softness: 0.0,
        ies_angle_scale: 0.0,
        ies_normalize: false,
    };

    /// Parameters that shape nothing: the schema defaults with a 180° cone (which with softness
    /// 0 never cuts). [`Shaping::new`](crate::Shaping::new) with these and no IES profile equals
    /// [`Shaping::identity`](crate::Shaping::identity), the behaviour of a light without
    /// `ShapingAPI`.
    pub const NO_SHAPING: ShapingParams = ShapingParams {
        cone_angle_deg: 180.0,
        ..ShapingParams::SCHEMA_DEFAULTS
    };
}

impl Default for ShapingParams {
    /// [`ShapingParams::SCHEMA_DEFAULTS`].
    fn default() -> Self {
        ShapingParams::SCHEMA_DEFAULTS
    }
}

/// Which `inputs:shaping:ies:angleScale` formula maps the light's polar angle θ to the angle θies
/// at which the IES profile is sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AngleScaleFormula {
    /// The UsdLux 26.11 text (default), two branches with their scaling origin at θ = 0 for a
    /// positive scale and at θ = π for a negative one: `s > 0: θ/s`; `s = 0: θ`;
    /// `s < 0: (θ − π)/(−s) + π`. The hdEmbree reference renders follow it as well.
    #[default]
    TwoBranch,
    /// The single formula still printed in older openusd.org documentation:
    /// `θies = (θ − π)/(1 + s) + π`. `s = 0` is the identity; `s = −1` is undefined and rejected.
    Legacy,
}

/// Choices between documented behaviours. [`Default`]: [`Profile::Spec`],
/// [`AngleScaleFormula::TwoBranch`], [`Interpolation::Bilinear`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShapingOptions {
    /// Conformance profile: cone softness clamping (`Spec` clamps to \[0, 1\], `HdEmbree` uses
    /// the authored value). The flux `ies:normalize` divides by (exact integral vs the
    /// reference's midpoint rule) is the IES web's own, chosen when it was built with
    /// [`lux_ies::PhotometricWeb::new`] (build it with this same profile).
    pub profile: Profile,
    /// The angleScale formula.
    pub angle_scale: AngleScaleFormula,
    /// How the IES profile is interpolated between its tabulated angles.
    pub interpolation: Interpolation,
}
