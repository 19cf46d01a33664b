//! Which family of sampling techniques a light is sampled with, chosen per call so that one
//! prepared light serves both.

/// The estimator family of a light sample (`sample_with`/`pdf_with` on every light type).
///
/// **How a technique is chosen — one rule.** A light's technique is chosen once, when it is
/// built: the technique argument of its constructor (`RectLight::new(…, RectTechnique)`, …),
/// or each kind's default with [`crate::Light::from_shape`]. `sample`/`pdf` use it, and so do
/// `sample_with`/`pdf_with` with [`Strategy::Lux`] (the default). [`Strategy::HdEmbree`] is not
/// a second choice of technique but the reference renderer's estimator, for A/B comparisons:
/// it ignores the built technique and samples as the table below says, whatever it was.
/// Nothing else changes a technique (the fallbacks inside a technique, such as the spherical
/// rectangle's area sampling below [`crate::MIN_SOLID_ANGLE`], are part of that technique and
/// documented on it).
///
/// | light | `Lux` | `HdEmbree` |
/// |---|---|---|
/// | rect, disk, sphere, cylinder, mesh | the built technique | uniform by area (`Area`) |
/// | dome | the built technique (texture or MIS-compensated) | uniform over the receiver's hemisphere |
/// | distant | its cone | its cone |
///
/// Both are unbiased estimators of the same direct illumination; they differ only in variance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// The technique the light was built with (lux's defaults: spherical rectangle, elliptic
    /// cone, sphere cone, cylinder solid angle, spherical triangle, textured dome).
    #[default]
    Lux,
    /// hdEmbree's techniques: rect, disk, sphere, cylinder and mesh lights uniformly by area
    /// (density `d²/(A·cos θₗ)` per unit solid angle); the dome uniformly over the hemisphere
    /// around the receiver normal (density `1/(2π)`; uniform over the sphere, `1/(4π)`, when
    /// the reference point has no normal); the distant light as prepared (its cone is already
    /// uniform).
    HdEmbree,
}
