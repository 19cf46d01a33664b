//! Subdivision surfaces: a `UsdGeomMesh` whose `subdivisionScheme` is `catmullClark` (also
//! when unauthored: the schema's fallback), `loop` or `bilinear` is a limit surface, not its
//! polygons. The loader keeps such a mesh's control cage ([`Cage`]: points, faces and the
//! subdivision tags, the primvars the renderer reads in their authored form) beside the cage's
//! triangulation; [`refine`] turns the cage into triangles whose vertices lie on the limit
//! surface, with normals from the limit surface's tangents, and [`LevelRule`] says at which level a
//! renderer refines (a fixed level, or the mesh's size on screen).
//!
//! The subdivision rules are OpenSubdiv's, through `opensubdiv-rs` (a pure-Rust port of
//! OpenSubdiv's Sdc/Vtr/Far layers): the same rules and tags USD's own renderers use (Hydra
//! Storm and hdEmbree refine through OpenSubdiv; `PxOsd` maps the USD tokens below to it).
//!
//! | USD (`UsdGeomMesh`) | here | OpenSubdiv |
//! |---|---|---|
//! | `subdivisionScheme` (`catmullClark` default, `loop`, `bilinear`; `none` is not a cage) | [`Scheme`] | `Sdc::SchemeType` |
//! | `interpolateBoundary` (`edgeAndCorner` default, `edgeOnly`, `none`) | [`Boundary`] | `VtxBoundaryInterpolation` |
//! | `faceVaryingLinearInterpolation` (`cornersPlus1` default, `none`, `cornersOnly`, `cornersPlus2`, `boundaries`, `all`) | [`FaceVarying`] | `FVarLinearInterpolation` |
//! | `triangleSubdivisionRule` (`catmullClark` default, `smooth`) | [`TriangleRule`] | `TriangleSubdivision` |
//! | `creaseIndices` / `creaseLengths` / `creaseSharpnesses` | [`Crease`] per edge | edge sharpness |
//! | `cornerIndices` / `cornerSharpnesses` | [`Corner`] | vertex sharpness |
//! | `holeIndices` | [`Cage::holes`] | hole tags |
//!
//! A sharpness of 10 or more is infinitely sharp (OpenSubdiv's `SHARPNESS_INFINITE`, as
//! `PxOsd` documents); semi-sharp creases decay by one per level (uniform creasing,
//! OpenSubdiv's default and `PxOsd`'s).

mod level;
mod read;
mod refine;

pub use level::{LevelRule, MAX_LEVEL, Refinement, TARGET_SAGITTA_PIXELS, screen_level};
pub(crate) use read::read_cage;
pub use refine::{MAX_REFINED_TRIANGLES, Refined, refine};

use glam::{DMat3, DMat4, DVec3, DVec4};

/// `UsdGeomMesh.subdivisionScheme` of a subdivided mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// `catmullClark` (the schema fallback): quads after one level; B-spline limit surface on
    /// regular regions.
    CatmullClark,
    /// `loop`: triangles only; quartic box-spline limit surface on regular regions.
    Loop,
    /// `bilinear`: refined linearly (every face its own bilinear patch).
    Bilinear,
}

impl Scheme {
    /// The scheme of a `subdivisionScheme` token (`None`: unauthored, the fallback):
    /// `Ok(None)` for `none` (polygons), `Err` with the token for one the schema does not allow.
    pub fn parse(token: Option<&str>) -> Result<Option<Scheme>, String> {
        Ok(Some(match token {
            None | Some("catmullClark") => Scheme::CatmullClark,
            Some("loop") => Scheme::Loop,
            Some("bilinear") => Scheme::Bilinear,
            Some("none") => return Ok(None),
            Some(other) => return Err(other.to_owned()),
        }))
    }

    /// The schema token.
    pub fn token(self) -> &'static str {
        match self {
            Scheme::CatmullClark => "catmullClark",
            Scheme::Loop => "loop",
            Scheme::Bilinear => "bilinear",
        }
    }
}

/// `UsdGeomMesh.interpolateBoundary`: how boundary edges and corners of the cage are refined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Boundary {
    /// `none`: boundary faces are not part of the surface's interpolated boundary (the
    /// boundary shrinks).
    None,
    /// `edgeOnly`: boundary edges are infinitely sharp creases; corners are smoothed.
    EdgeOnly,
    /// `edgeAndCorner` (the schema fallback): boundary edges sharp and corners (vertices of
    /// one face) pinned.
    #[default]
    EdgeAndCorner,
}

/// `UsdGeomMesh.faceVaryingLinearInterpolation`: where face-varying primvars (UVs, colours per
/// face corner) are interpolated linearly rather than smoothly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FaceVarying {
    /// `none`: smooth everywhere (boundaries and corners included).
    None,
    /// `cornersOnly`: linear at corners.
    CornersOnly,
    /// `cornersPlus1` (the schema fallback): corners and junctions of three or more seams.
    #[default]
    CornersPlus1,
    /// `cornersPlus2`: as `cornersPlus1`, and darts and concave corners.
    CornersPlus2,
    /// `boundaries`: linear along every boundary and seam.
    Boundaries,
    /// `all`: linear everywhere (bilinear face-varying data).
    All,
}

/// `UsdGeomMesh.triangleSubdivisionRule`: how Catmull–Clark refines triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleRule {
    /// `catmullClark` (the schema fallback): the standard weights.
    #[default]
    CatmullClark,
    /// `smooth`: the smooth-triangle weights (OpenSubdiv's `TRI_SUB_SMOOTH`).
    Smooth,
}

/// One creased cage edge (from `creaseIndices`, `creaseLengths`, `creaseSharpnesses`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crease {
    /// The edge's two vertices (indices into [`Cage::points`]).
    pub edge: [u32; 2],
    /// Its sharpness: 0 smooth, ≥ 10 infinitely sharp, semi-sharp in between.
    pub sharpness: f32,
}

/// One sharpened cage vertex (from `cornerIndices`, `cornerSharpnesses`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// The vertex (index into [`Cage::points`]).
    pub vertex: u32,
    /// Its sharpness: 0 smooth, ≥ 10 infinitely sharp.
    pub sharpness: f32,
}

/// A primvar's `interpolation` (UsdGeomPrimvar): how many values it has and how they are
/// interpolated over a subdivision surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// One value for the whole mesh.
    Constant,
    /// One value per face.
    Uniform,
    /// One value per point, interpolated linearly (bilinearly over each face).
    Varying,
    /// One value per point, interpolated by the subdivision scheme (as the points are).
    Vertex,
    /// One value per face corner, interpolated by the scheme's face-varying rules
    /// ([`FaceVarying`]), discontinuous across seams.
    FaceVarying,
}

impl Interpolation {
    /// The interpolation of a primvar's `interpolation` metadata token; `None` if unknown.
    pub fn parse(token: &str) -> Option<Interpolation> {
        Some(match token {
            "constant" => Interpolation::Constant,
            "uniform" => Interpolation::Uniform,
            "varying" => Interpolation::Varying,
            "vertex" => Interpolation::Vertex,
            "faceVarying" => Interpolation::FaceVarying,
            _ => return None,
        })
    }
}

/// A primvar of a cage in its authored form: `values` (up to four components, the rest 0) and
/// for every element of its interpolation (the mesh, a face, a point, a face corner in
/// [`Cage::face_vertices`] order) the index of its value (`primvars:NAME:indices`, or the
/// element's own index when unindexed). Every index is in range.
#[derive(Clone, Debug, PartialEq)]
pub struct CagePrimvar {
    /// How the primvar varies over the surface.
    pub interpolation: Interpolation,
    /// The distinct values.
    pub values: Vec<DVec4>,
    /// Per element, the index into `values`.
    pub indices: Vec<u32>,
}

impl CagePrimvar {
    /// The value of element `i`.
    pub fn at(&self, i: usize) -> DVec4 {
        self.values[self.indices[i] as usize]
    }
}

/// The control cage of a subdivision surface, in the space of its [`crate::Mesh`] (world, or
/// a prototype's), faces wound so that the right-hand rule gives the USD front side there
/// (`orientation = "leftHanded"` and a mirroring transform are already accounted for by
/// reversing each face's corners, face-varying data with them).
#[derive(Clone, Debug, PartialEq)]
pub struct Cage {
    /// `subdivisionScheme`.
    pub scheme: Scheme,
    /// `interpolateBoundary`.
    pub boundary: Boundary,
    /// `faceVaryingLinearInterpolation`.
    pub face_varying: FaceVarying,
    /// `triangleSubdivisionRule`.
    pub triangle_rule: TriangleRule,
    /// Control points (`points`, transformed).
    pub points: Vec<DVec3>,
    /// `faceVertexCounts`: corners of each face (every face has at least 3).
    pub face_sizes: Vec<u32>,
    /// `faceVertexIndices`, face by face (every index in range).
    pub face_vertices: Vec<u32>,
    /// `holeIndices`: faces cut out of the surface.
    pub holes: Vec<u32>,
    /// Creased edges.
    pub creases: Vec<Crease>,
    /// Sharpened vertices.
    pub corners: Vec<Corner>,
    /// `primvars:displayColor` (xyz), when authored.
    pub colors: Option<CagePrimvar>,
    /// The texture coordinates the bound material reads (xy), when authored.
    pub uvs: Option<CagePrimvar>,
    /// The primvars the bound material's primvar readers read (`crate::CornerPrimvar` once
    /// refined), by name.
    pub primvars: Vec<(String, CagePrimvar)>,
}

impl Cage {
    /// The cage under the affine map `m` (a mirroring map reverses every face, so that the
    /// front side stays the USD front side).
    pub fn transformed(&self, m: &DMat4) -> Cage {
        let mut c = self.clone();
        for p in &mut c.points {
            *p = m.transform_point3(*p);
        }
        if DMat3::from_mat4(*m).determinant() < 0.0 {
            c.reverse_faces();
        }
        c
    }

    /// Reverses the corner order of every face (`[a, b, c, d]` → `[a, d, c, b]`), and of the
    /// face-varying primvars' elements with them.
    pub fn reverse_faces(&mut self) {
        let mut start = 0usize;
        for &n in &self.face_sizes {
            let n = n as usize;
            let range = start + 1..start + n;
            self.face_vertices[range.clone()].reverse();
            let named = self.primvars.iter_mut().map(|(_, p)| p);
            for pv in [&mut self.colors, &mut self.uvs]
                .into_iter()
                .flatten()
                .chain(named)
            {
                if pv.interpolation == Interpolation::FaceVarying {
                    pv.indices[range.clone()].reverse();
                }
            }
            start += n;
        }
    }

    /// The number of triangles refining at `level` makes (holes included): every quad
    /// (Catmull–Clark, bilinear) or triangle (Loop) face `2 · 4^level` or `4^level`, an n-gon
    /// under a quad scheme `n` quads of `4^(level−1)` each.
    pub fn refined_triangles(&self, level: u32) -> u64 {
        if level == 0 {
            return self
                .face_sizes
                .iter()
                .map(|&n| n.saturating_sub(2) as u64)
                .sum();
        }
        let l = level.min(31) as u64;
        let quads_per_quad = 1u64 << (2 * l);
        self.face_sizes
            .iter()
            .map(|&n| match (self.scheme, n) {
                (Scheme::Loop, _) => quads_per_quad,
                (_, 4) => 2 * quads_per_quad,
                (_, n) => 2 * n as u64 * (quads_per_quad / 4),
            })
            .fold(0u64, u64::saturating_add)
    }
}
