//! Which family of sampling techniques a light is sampled with, chosen per call so that one
//! prepared light serves both.

/// The sampling strategy of a light sample (`sample_with` on every light type).
///
/// Both strategies are unbiased estimators of the same direct illumination; they differ only
/// in variance. `HdEmbree` exists for A/B comparisons against the reference renderer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// The technique the light was prepared with (lux's defaults: spherical rectangle, elliptic
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
