//! Reading a `UsdGeomMesh`'s subdivision cage: the scheme, the tags and the primvars the
//! renderer reads, with a warning naming the prim for whatever cannot be refined as authored.

use super::{
    Boundary, Cage, CagePrimvar, Corner, Crease, FaceVarying, Interpolation, Scheme, TriangleRule,
};
use crate::error::{LoadError, WarningKind};
use crate::mesh::Topology;
use crate::reader::Reader;
use glam::{DMat3, DMat4, DVec4};
use openusd::usd::Prim;

/// The cage of the `Mesh` prim `prim` whose faces `topo` holds (local points), placed by
/// `world`; `st` names the texture-coordinate primvar the bound material reads, `reads` the
/// primvars its primvar readers read. `Ok(None)`
/// for `subdivisionScheme = "none"` and, with a warning naming the prim, for a mesh that cannot
/// be refined as authored (an unknown scheme, invalid faces, non-triangles under Loop): it is
/// then drawn as its polygons.
pub(crate) fn read_cage(
    r: &mut Reader<'_>,
    prim: &Prim,
    topo: &Topology,
    world: &DMat4,
    st: Option<&str>,
    reads: &[String],
) -> Result<Option<Cage>, LoadError> {
    let token = r.text(prim, "subdivisionScheme")?;
    let scheme = match Scheme::parse(token.as_deref()) {
        Ok(Some(s)) => s,
        Ok(None) => return Ok(None),
        Err(token) => {
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!(
                    "subdivisionScheme {token:?} is not a UsdGeomMesh scheme (catmullClark, \
                     loop, bilinear, none); drawn as its polygons"
                ),
            );
            return Ok(None);
        }
    };
    let Some(faces) = &topo.faces else {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "a {} surface with invalid faces cannot be refined; its valid faces are drawn as \
                 polygons",
                scheme.token()
            ),
        );
        return Ok(None);
    };
    if scheme == Scheme::Loop && faces.sizes.iter().any(|&n| n != 3) {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            "subdivisionScheme \"loop\" needs triangles only; drawn as its polygons",
        );
        return Ok(None);
    }
    let n_points = topo.points.len();
    let boundary = token_or(
        r,
        prim,
        "interpolateBoundary",
        &[
            ("none", Boundary::None),
            ("edgeOnly", Boundary::EdgeOnly),
            ("edgeAndCorner", Boundary::EdgeAndCorner),
        ],
        Boundary::EdgeAndCorner,
    )?;
    let face_varying = token_or(
        r,
        prim,
        "faceVaryingLinearInterpolation",
        &[
            ("none", FaceVarying::None),
            ("cornersOnly", FaceVarying::CornersOnly),
            ("cornersPlus1", FaceVarying::CornersPlus1),
            ("cornersPlus2", FaceVarying::CornersPlus2),
            ("boundaries", FaceVarying::Boundaries),
            ("all", FaceVarying::All),
        ],
        FaceVarying::CornersPlus1,
    )?;
    let triangle_rule = token_or(
        r,
        prim,
        "triangleSubdivisionRule",
        &[
            ("catmullClark", TriangleRule::CatmullClark),
            ("smooth", TriangleRule::Smooth),
        ],
        TriangleRule::CatmullClark,
    )?;
    let creases = read_creases(r, prim, n_points)?;
    let corners = read_corners(r, prim, n_points)?;
    let fv_count = faces.vertices.len();
    let colors = match r.vec3_array(prim, "primvars:displayColor")? {
        Some(c) => cage_primvar(
            r,
            prim,
            "primvars:displayColor",
            c.into_iter().map(|v| v.extend(0.0)).collect(),
            "constant",
            [faces.sizes.len(), n_points, fv_count],
        )?,
        None => None,
    };
    let mut uvs = None;
    if let Some(st) = st {
        let name = format!("primvars:{st}");
        if let Some(v) = r.raw(prim, &name)?
            && let Some(st) = crate::value::as_vec2_array(&v)
        {
            uvs = cage_primvar(
                r,
                prim,
                &name,
                st.into_iter()
                    .map(|v| DVec4::new(v.x, v.y, 0.0, 0.0))
                    .collect(),
                "constant",
                [faces.sizes.len(), n_points, fv_count],
            )?;
        }
    }
    let mut primvars = Vec::new();
    for name in reads {
        let attr = format!("primvars:{name}");
        if let Some(values) = crate::mesh::primvar_values(r, prim, &attr)?
            && let Some(pv) = cage_primvar(
                r,
                prim,
                &attr,
                values,
                "constant",
                [faces.sizes.len(), n_points, fv_count],
            )?
        {
            primvars.push((name.clone(), pv));
        }
    }
    let mut cage = Cage {
        scheme,
        boundary,
        face_varying,
        triangle_rule,
        points: topo
            .points
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect(),
        face_sizes: faces.sizes.clone(),
        face_vertices: faces.vertices.clone(),
        holes: faces.holes.clone(),
        creases,
        corners,
        colors,
        uvs,
        primvars,
    };
    let mirror = DMat3::from_mat4(*world).determinant() < 0.0;
    if faces.left_handed != mirror {
        cage.reverse_faces();
    }
    Ok(Some(cage))
}

/// A uniform token attribute among `allowed`; unauthored gives `fallback`, an unknown token
/// `fallback` with a warning.
fn token_or<T: Copy>(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &'static str,
    allowed: &[(&str, T)],
    fallback: T,
) -> Result<T, LoadError> {
    let Some(t) = r.text(prim, name)? else {
        return Ok(fallback);
    };
    match allowed.iter().find(|(k, _)| *k == t) {
        Some((_, v)) => Ok(*v),
        None => {
            let names: Vec<&str> = allowed.iter().map(|(k, _)| *k).collect();
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "{name} {t:?} is not one of {}; the schema fallback is used",
                    names.join(", ")
                ),
            );
            Ok(fallback)
        }
    }
}

/// `creaseIndices` (chains of vertices), `creaseLengths` (vertices per chain) and
/// `creaseSharpnesses` (one per chain, or one per edge of every chain) as creased edges.
/// Inconsistent arrays drop the creases with a warning; out-of-range vertices drop their edges.
fn read_creases(
    r: &mut Reader<'_>,
    prim: &Prim,
    n_points: usize,
) -> Result<Vec<Crease>, LoadError> {
    let indices = r.int_array(prim, "creaseIndices")?.unwrap_or_default();
    let lengths = r.int_array(prim, "creaseLengths")?.unwrap_or_default();
    let sharp = r.f64_array(prim, "creaseSharpnesses")?.unwrap_or_default();
    if indices.is_empty() && lengths.is_empty() && sharp.is_empty() {
        return Ok(Vec::new());
    }
    let total = lengths
        .iter()
        .fold(0i64, |a, &l| a.saturating_add(l.max(0)));
    let edges: i64 = lengths.iter().map(|&l| (l - 1).max(0)).sum();
    let per_chain = sharp.len() == lengths.len();
    let per_edge = sharp.len() as i64 == edges;
    if total != indices.len() as i64 || lengths.iter().any(|&l| l < 2) || !(per_chain || per_edge) {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "creases ignored: creaseLengths {lengths:?} (each at least 2, summing to the {} \
                 creaseIndices) with {} creaseSharpnesses (one per crease or one per edge)",
                indices.len(),
                sharp.len()
            ),
        );
        return Ok(Vec::new());
    }
    let mut out = Vec::with_capacity(edges as usize);
    let (mut start, mut edge, mut bad) = (0usize, 0usize, 0usize);
    for (chain, &len) in lengths.iter().enumerate() {
        let len = len as usize;
        for k in 0..len - 1 {
            let s = if per_chain { sharp[chain] } else { sharp[edge] };
            edge += 1;
            let (a, b) = (indices[start + k], indices[start + k + 1]);
            let ok = |i: i64| i >= 0 && (i as usize) < n_points;
            if !ok(a) || !ok(b) || !s.is_finite() {
                bad += 1;
                continue;
            }
            out.push(Crease {
                edge: [a as u32, b as u32],
                sharpness: s.max(0.0) as f32,
            });
        }
        start += len;
    }
    if bad > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "{bad} crease edges with out-of-range vertices or non-finite sharpness ignored"
            ),
        );
    }
    Ok(out)
}

/// `cornerIndices` and `cornerSharpnesses` (one per index) as sharpened vertices.
fn read_corners(
    r: &mut Reader<'_>,
    prim: &Prim,
    n_points: usize,
) -> Result<Vec<Corner>, LoadError> {
    let indices = r.int_array(prim, "cornerIndices")?.unwrap_or_default();
    let sharp = r.f64_array(prim, "cornerSharpnesses")?.unwrap_or_default();
    if indices.len() != sharp.len() {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "corners ignored: {} cornerIndices but {} cornerSharpnesses",
                indices.len(),
                sharp.len()
            ),
        );
        return Ok(Vec::new());
    }
    let mut bad = 0usize;
    let out = indices
        .iter()
        .zip(&sharp)
        .filter_map(|(&i, &s)| {
            let ok = i >= 0 && (i as usize) < n_points && s.is_finite();
            bad += usize::from(!ok);
            ok.then_some(Corner {
                vertex: i as u32,
                sharpness: s.max(0.0) as f32,
            })
        })
        .collect();
    if bad > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!("{bad} corners with out-of-range vertices or non-finite sharpness ignored"),
        );
    }
    Ok(out)
}

/// A primvar in its authored form: its `interpolation` (else `default_interp`) and `:indices`
/// checked against the element counts `[faces, points, face corners]`. `None`, with a warning,
/// when they do not fit.
fn cage_primvar(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &str,
    values: Vec<DVec4>,
    default_interp: &str,
    [faces, points, corners]: [usize; 3],
) -> Result<Option<CagePrimvar>, LoadError> {
    let token = r
        .attr_metadata_text(prim, name, "interpolation")
        .unwrap_or_else(|| default_interp.to_owned());
    let Some(interpolation) = Interpolation::parse(&token) else {
        r.warn(
            prim,
            WarningKind::Unsupported,
            format!("{name}: interpolation {token:?} not supported; ignored"),
        );
        return Ok(None);
    };
    let elements = match interpolation {
        Interpolation::Constant => 1,
        Interpolation::Uniform => faces,
        Interpolation::Varying | Interpolation::Vertex => points,
        Interpolation::FaceVarying => corners,
    };
    let idx_name = format!("{name}:indices");
    let indices = match r.raw(prim, &idx_name)? {
        Some(v) => crate::value::as_int_array(&v),
        None => None,
    };
    let indices: Option<Vec<u32>> = match indices {
        Some(ix) => (ix.len() >= elements)
            .then(|| {
                ix[..elements]
                    .iter()
                    .map(|&i| {
                        u32::try_from(i)
                            .ok()
                            .filter(|&i| (i as usize) < values.len())
                    })
                    .collect()
            })
            .flatten(),
        None => (values.len() >= elements).then(|| (0..elements as u32).collect()),
    };
    match indices {
        Some(indices) => Ok(Some(CagePrimvar {
            interpolation,
            values,
            indices,
        })),
        None => {
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!("{name}: too few values or indices out of range for {token} interpolation; ignored"),
            );
            Ok(None)
        }
    }
}
