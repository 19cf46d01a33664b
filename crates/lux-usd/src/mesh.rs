//! `UsdGeomMesh` triangulation and primvar expansion into world-space triangle meshes.

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};
use openusd::usd::Prim;

/// A renderable triangle mesh: in world space, or — when [`Mesh::prototype`] is set — in the
/// space of an instancing prototype, drawn once per [`Instance`] of that prototype.
///
/// Triangles are wound so that `(b − a) × (c − a)` points to the USD **front** side in the
/// mesh's own space (the `orientation` and a mirroring transform up to that space are already
/// accounted for; an instance transform that mirrors flips it again).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// The gprim's prim path.
    pub path: String,
    /// Vertex positions (world space, or prototype space for a prototype's mesh).
    pub positions: Vec<DVec3>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Unit shading normals per triangle corner (`normals` / `primvars:normals`) in the
    /// mesh's space, when authored.
    pub normals: Option<Vec<[DVec3; 3]>>,
    /// `primvars:displayColor` per triangle corner, when authored.
    pub colors: Option<Vec<[DVec3; 3]>>,
    /// Texture coordinates per triangle corner from the primvar the bound material reads.
    pub uvs: Option<Vec<[DVec2; 3]>>,
    /// The primvars the bound material's `UsdPrimvarReader_*` shaders read, per triangle
    /// corner (those the gprim authors).
    pub primvars: Vec<CornerPrimvar>,
    /// `doubleSided` (Gprim fallback false; UsdGeomPlane's fallback true).
    pub double_sided: bool,
    /// Index into `Scene::materials` of the bound material (`material:binding`, resolved
    /// within the prototype for a prototype's mesh; see [`Instance::material`]).
    pub material: Option<usize>,
    /// Index into `Scene::lights` when the gprim has `MeshLightAPI`.
    pub light: Option<usize>,
    /// LTESpectralAPI inputs authored on the gprim itself (`wavelength:reflectance`, …); a
    /// reflectance here wins over the material's.
    pub spectral: crate::spectral::SurfaceSpectral,
    /// The [`Prototype`] (index into `Scene::prototypes`) this mesh belongs to: `None` for a
    /// mesh drawn once in world space.
    pub prototype: Option<usize>,
    /// The gprim schema the triangles came from.
    pub gprim: Gprim,
    /// For a subdivision surface not yet refined ([`crate::Scene::refine_subdivision`]): its
    /// control cage, whose polygons `triangles` holds meanwhile (what a renderer draws at
    /// refinement level 0). `None` for polygons and refined surfaces.
    pub subdivision: Option<std::sync::Arc<crate::subdiv::Cage>>,
}

impl Mesh {
    /// This mesh under the affine map `m` (positions, shading normals by the inverse
    /// transpose; a mirroring `m` reverses the winding, so the front side stays the USD front
    /// side, and reorders per-corner primvars with it).
    pub fn transformed(&self, m: &DMat4) -> Mesh {
        let mirror = DMat3::from_mat4(*m).determinant() < 0.0;
        Mesh {
            positions: self
                .positions
                .iter()
                .map(|p| m.transform_point3(*p))
                .collect(),
            triangles: self
                .triangles
                .iter()
                .map(|t| if mirror { [t[0], t[2], t[1]] } else { *t })
                .collect(),
            normals: self.normals.clone().map(|n| normals_to_world(n, m, mirror)),
            colors: self.colors.clone().map(|c| mirror_corners(c, mirror)),
            uvs: self.uvs.clone().map(|c| mirror_corners(c, mirror)),
            primvars: self
                .primvars
                .iter()
                .map(|p| CornerPrimvar {
                    name: p.name.clone(),
                    values: mirror_corners(p.values.clone(), mirror),
                })
                .collect(),
            subdivision: self
                .subdivision
                .as_ref()
                .map(|c| std::sync::Arc::new(c.transformed(m))),
            ..self.clone()
        }
    }
}

/// A primvar per triangle corner: up to four components (`float` in `x`, `float2` in `xy`,
/// …; the rest 0), in the mesh's triangle order.
#[derive(Clone, Debug, PartialEq)]
pub struct CornerPrimvar {
    /// The primvar's name without `primvars:`.
    pub name: String,
    /// Its values at each triangle's corners.
    pub values: Vec<[DVec4; 3]>,
}

/// The UsdGeom gprim type a [`Mesh`] was made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Gprim {
    /// `Mesh` (polygons, fan-triangulated).
    Mesh,
    /// `Sphere`, tessellated.
    Sphere,
    /// `Cube`, tessellated.
    Cube,
    /// `Cylinder`, tessellated.
    Cylinder,
    /// `Cone`, tessellated.
    Cone,
    /// `Capsule`, tessellated.
    Capsule,
    /// `Plane`, tessellated.
    Plane,
    /// `BasisCurves`, swept into tubes or ribbons ([`crate::curves`]).
    BasisCurves,
    /// `NurbsCurves`, swept into tubes or ribbons ([`crate::curves`]).
    NurbsCurves,
    /// `Points`, one sphere per point ([`crate::points`]).
    Points,
}

impl Gprim {
    /// The gprim of a prim type name for the gprims drawn through `Mesh` topology or implicit
    /// tessellation; `None` for anything else — curves and points included, which the walk
    /// tessellates on their own path ([`crate::curves`], [`crate::points`]).
    pub fn of_type(type_name: &str) -> Option<Gprim> {
        Some(match type_name {
            "Mesh" => Gprim::Mesh,
            "Sphere" => Gprim::Sphere,
            "Cube" => Gprim::Cube,
            "Cylinder" => Gprim::Cylinder,
            "Cone" => Gprim::Cone,
            "Capsule" => Gprim::Capsule,
            "Plane" => Gprim::Plane,
            _ => return None,
        })
    }
}

/// Geometry shared by instances: the meshes of a native-instancing prototype
/// (`/__Prototype_N`, the shared subtree of every `instanceable` prim with the same
/// composition) or of a `UsdGeomPointInstancer` prototype (a target of its `prototypes`
/// relationship), in the prototype root's space.
#[derive(Clone, Debug, PartialEq)]
pub struct Prototype {
    /// The prototype's prim path (`/__Prototype_1`, or the PointInstancer's target).
    pub path: String,
    /// Indices into `Scene::meshes` of its meshes (whose `prototype` is this one).
    pub meshes: Vec<usize>,
}

/// One placement of a [`Prototype`] in the world: a native instance (an `instanceable` prim)
/// or one entry of a PointInstancer's `protoIndices`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The instance prim's path, or for a PointInstancer `"/Path/To/Instancer[i]"` (`i` the
    /// index into `protoIndices`).
    pub path: String,
    /// Index into `Scene::prototypes`.
    pub prototype: usize,
    /// Prototype-to-world transform (glam column form). Native: the instance prim's world
    /// transform. PointInstancer: the instancer's world transform after the instance's own
    /// (`scale`, `orientation`, `position`, UsdGeomPointInstancer's
    /// `ComputeInstanceTransformsAtTime`) after the prototype root's local transform.
    pub to_world: DMat4,
    /// The material bound on the instance's side (inherited from the instance prim or its
    /// ancestors): used by prototype meshes that have no binding of their own.
    pub material: Option<usize>,
}

impl Mesh {
    /// A single-sided mesh without primvars, material or light, for scenes built in code.
    /// Triangles are wound with `(b − a) × (c − a)` towards the front side.
    pub fn new(path: impl Into<String>, positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            path: path.into(),
            positions,
            triangles,
            normals: None,
            colors: None,
            uvs: None,
            primvars: Vec::new(),
            double_sided: false,
            material: None,
            light: None,
            spectral: Default::default(),
            prototype: None,
            gprim: Gprim::Mesh,
            subdivision: None,
        }
    }
}

/// The triangulated topology of a gprim in its local space, before transforming.
pub struct Topology {
    /// Local points.
    pub points: Vec<DVec3>,
    /// Triangles (indices into `points`), wound right-handed (front side by the right-hand rule).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the authored face it came from and its three face-vertex indices.
    pub corners: Vec<(usize, [usize; 3])>,
    /// Number of faces.
    pub face_count: usize,
    /// The authored faces (`faceVertexCounts`, `faceVertexIndices`, `holeIndices`) and
    /// `orientation` (true for `leftHanded`), for a subdivision cage; `None` for an implicit
    /// gprim or when a face has fewer than 3 vertices or an index out of range.
    pub faces: Option<AuthoredFaces>,
}

/// A `Mesh`'s faces as authored (every face valid).
pub struct AuthoredFaces {
    /// `faceVertexCounts`.
    pub sizes: Vec<u32>,
    /// `faceVertexIndices`.
    pub vertices: Vec<u32>,
    /// `holeIndices` within range.
    pub holes: Vec<u32>,
    /// `orientation = "leftHanded"`.
    pub left_handed: bool,
}

/// Reads and fan-triangulates a `Mesh` prim (`points`, `faceVertexCounts`, `faceVertexIndices`,
/// `holeIndices`, `orientation`). Faces with fewer than 3 vertices or out-of-range indices are
/// skipped with a warning; a count/index length mismatch skips the whole mesh (`None`).
pub fn mesh_topology(r: &mut Reader<'_>, prim: &Prim) -> Result<Option<Topology>, LoadError> {
    let points = r.vec3_array(prim, "points")?.unwrap_or_default();
    let counts = r.int_array(prim, "faceVertexCounts")?.unwrap_or_default();
    let indices = r.int_array(prim, "faceVertexIndices")?.unwrap_or_default();
    let holes = r.int_array(prim, "holeIndices")?.unwrap_or_default();
    let left = r.text(prim, "orientation")?.as_deref() == Some("leftHanded");
    // Saturating: absurd counts (int64 arrays of huge values) must not overflow.
    let total = counts
        .iter()
        .fold(0i64, |acc, c| acc.saturating_add((*c).max(0)));
    if total != indices.len() as i64 || counts.iter().any(|c| *c < 0) {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "faceVertexCounts sum to {total} but faceVertexIndices has {} entries; mesh skipped",
                indices.len()
            ),
        );
        return Ok(None);
    }
    // `total` equals the index count here, so every count is ≤ MAX_ARRAY_LEN and the sum fits.
    let tri_count: usize = counts.iter().map(|c| (*c as usize).saturating_sub(2)).sum();
    if tri_count > r.limits.max_array_len {
        return Err(LoadError::TooLarge {
            file: r.file.clone(),
            prim: prim.path().to_string(),
            what: "triangulation",
            count: tri_count,
            limit: r.limits.max_array_len,
        });
    }
    let mut triangles = Vec::with_capacity(tri_count);
    let mut corners = Vec::with_capacity(tri_count);
    let mut bad_faces = 0usize;
    let holes: std::collections::HashSet<i64> = holes.into_iter().collect();
    let mut start = 0usize;
    for (face, &n) in counts.iter().enumerate() {
        let n = n as usize;
        let fv = start..start + n;
        start += n;
        if holes.contains(&(face as i64)) {
            continue;
        }
        if n < 3
            || indices[fv.clone()]
                .iter()
                .any(|&i| i < 0 || i as usize >= points.len())
        {
            bad_faces += 1;
            continue;
        }
        let first = fv.start;
        for k in 1..n - 1 {
            let (b, c) = if left {
                (first + k + 1, first + k)
            } else {
                (first + k, first + k + 1)
            };
            triangles.push([indices[first] as u32, indices[b] as u32, indices[c] as u32]);
            corners.push((face, [first, b, c]));
        }
    }
    if bad_faces > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!("{bad_faces} faces with < 3 vertices or out-of-range indices skipped"),
        );
    }
    let faces = (bad_faces == 0).then(|| AuthoredFaces {
        sizes: counts.iter().map(|&c| c as u32).collect(),
        vertices: indices.iter().map(|&i| i as u32).collect(),
        holes: {
            let mut h: Vec<u32> = holes
                .iter()
                .filter_map(|&h| {
                    u32::try_from(h)
                        .ok()
                        .filter(|&h| (h as usize) < counts.len())
                })
                .collect();
            h.sort_unstable();
            h
        },
        left_handed: left,
    });
    Ok(Some(Topology {
        points,
        triangles,
        corners,
        face_count: counts.len(),
        faces,
    }))
}

/// Expands a primvar to per-triangle-corner values following its `interpolation` (constant,
/// uniform, vertex/varying, faceVarying) and optional `:indices`. `None` (with a warning) when
/// the primvar is inconsistent with the topology.
pub fn expand_primvar<T: Copy>(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &str,
    values: Vec<T>,
    default_interp: &str,
    topo: &Topology,
) -> Result<Option<Vec<[T; 3]>>, LoadError> {
    let interp = r
        .attr_metadata_text(prim, name, "interpolation")
        .unwrap_or_else(|| default_interp.to_owned());
    let idx_name = format!("{name}:indices");
    let indices = match r.raw(prim, &idx_name)? {
        Some(v) => crate::value::as_int_array(&v),
        None => None,
    };
    let longest = values.len().max(indices.as_ref().map_or(0, Vec::len));
    if longest > r.limits.max_array_len {
        return Err(LoadError::TooLarge {
            file: r.file.clone(),
            prim: prim.path().to_string(),
            what: "primvar",
            count: longest,
            limit: r.limits.max_array_len,
        });
    }
    let lookup = |i: usize| -> Option<T> {
        let j = match &indices {
            Some(ix) => usize::try_from(*ix.get(i)?).ok()?,
            None => i,
        };
        values.get(j).copied()
    };
    let mut out = Vec::with_capacity(topo.triangles.len());
    for (t, (face, fv)) in topo.triangles.iter().zip(&topo.corners) {
        let mut c = [None; 3];
        for k in 0..3 {
            c[k] = match interp.as_str() {
                "constant" => lookup(0),
                "uniform" => lookup(*face),
                "vertex" | "varying" => lookup(t[k] as usize),
                "faceVarying" => lookup(fv[k]),
                other => {
                    r.warn(
                        prim,
                        WarningKind::Unsupported,
                        format!("{name}: interpolation {other:?} not supported; ignored"),
                    );
                    return Ok(None);
                }
            };
        }
        match c {
            [Some(a), Some(b), Some(d)] => out.push([a, b, d]),
            _ => {
                r.warn(
                    prim,
                    WarningKind::InvalidGeometry,
                    format!("{name}: too few values for {interp} interpolation; ignored"),
                );
                return Ok(None);
            }
        }
    }
    let _ = topo.face_count;
    Ok(Some(out))
}

/// The values of the primvar attribute `name` (`primvars:…`) as 4-vectors padded with zeros
/// (any numeric type of 1 to 4 components, an array or — for constant interpolation — a
/// single value); `None` when unauthored or not numeric (the latter with a warning, as any
/// attribute of the wrong type).
pub fn primvar_values(
    r: &Reader<'_>,
    prim: &Prim,
    name: &str,
) -> Result<Option<Vec<DVec4>>, LoadError> {
    let Some(v) = r.raw(prim, name)? else {
        return Ok(None);
    };
    let single = crate::value::as_vec4(&v)
        .or_else(|| crate::value::as_vec3(&v).map(|c| c.extend(0.0)))
        .or_else(|| crate::value::as_vec2(&v).map(|c| DVec4::new(c.x, c.y, 0.0, 0.0)))
        .or_else(|| crate::value::as_f64(&v).map(|x| DVec4::new(x, 0.0, 0.0, 0.0)));
    let values = crate::value::as_dvec4_array(&v).or_else(|| single.map(|x| vec![x]));
    if values.is_none() {
        r.type_warnings.borrow_mut().push(crate::error::Warning {
            prim: prim.path().to_string(),
            kind: WarningKind::InvalidValue,
            message: format!(
                "{name}: expected numbers of 1 to 4 components, found {}; ignored",
                crate::value::type_label(&v)
            ),
        });
    }
    Ok(values)
}

/// Transforms a local topology to world space, flipping the winding when the transform mirrors.
pub fn to_world(topo: &Topology, world: &DMat4) -> (Vec<DVec3>, Vec<[u32; 3]>, bool) {
    let positions = topo
        .points
        .iter()
        .map(|p| world.transform_point3(*p))
        .collect();
    let mirror = DMat3::from_mat4(*world).determinant() < 0.0;
    let tris = topo
        .triangles
        .iter()
        .map(|t| if mirror { [t[0], t[2], t[1]] } else { *t })
        .collect();
    (positions, tris, mirror)
}

/// Transforms per-corner normals to world space (inverse transpose), normalised; corners are
/// reordered like the triangles when `mirror`.
pub fn normals_to_world(n: Vec<[DVec3; 3]>, world: &DMat4, mirror: bool) -> Vec<[DVec3; 3]> {
    let m = DMat3::from_mat4(*world).inverse().transpose();
    n.into_iter()
        .map(|c| {
            let w = c.map(|v| (m * v).normalize_or_zero());
            if mirror { [w[0], w[2], w[1]] } else { w }
        })
        .collect()
}

/// Reorders per-corner values like mirrored triangles.
pub fn mirror_corners<T: Copy>(v: Vec<[T; 3]>, mirror: bool) -> Vec<[T; 3]> {
    if !mirror {
        return v;
    }
    v.into_iter().map(|c| [c[0], c[2], c[1]]).collect()
}
