//! The prepared scene an integrator and the visibility accelerations read ([`World`]).

use crate::geometry::Geometry;
use crate::light::LightSet;
use crate::material::Materials;
use lux_usd::Scene;

/// The prepared scene: geometry, lights and materials over the stage they came from.
#[derive(Clone, Copy)]
pub struct World<'a> {
    /// The stage the rest was prepared from (mesh attributes for shading).
    pub scene: &'a Scene,
    /// Triangles and instances.
    pub geometry: &'a Geometry,
    /// The lights, their selection and the analytic lights' BVH.
    pub lights: &'a LightSet,
    /// Surfaces' BSDFs.
    pub materials: &'a Materials,
    /// Whether some surface lets rays through ([`Materials::any_transparent`]).
    pub transparent: bool,
    /// Whether some surface glows from a texture or a primvar ([`Materials::emission`]), which
    /// only camera and BSDF rays find.
    pub textured_emission: bool,
}
