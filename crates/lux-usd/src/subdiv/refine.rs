//! Refining a [`Cage`] into triangles on its limit surface.
//!
//! The cage is refined adaptively by OpenSubdiv (`opensubdiv-rs`) to isolation level `L`
//! (single-crease patches for semi-sharp creases), and its limit surface is the patch table:
//! exact bicubic B-spline (Catmull–Clark) or quartic box-spline (Loop) patches on regular
//! regions, Gregory end caps around the isolated extraordinary vertices. Every face is then
//! tessellated on its ptex domain: a quad (a triangle under Loop) into a `2^L × 2^L` grid, an
//! n-gon into `n` quads of `2^(L−1) × 2^(L−1)` (OpenSubdiv's ptex sub-faces). Because the
//! patches around an extraordinary vertex lie at level `L`, every grid point is a patch corner
//! or inside a polynomial patch, so **every vertex is the exact limit point** (the limit
//! stencil's point) and its normal is `∂S/∂u × ∂S/∂v` there (the limit tangents). The same
//! triangle count as uniform refinement at level `L`; the topology work grows with the cage's
//! irregular features, not with `4^L`.
//!
//! Grid points shared by faces (cage vertices, points along a cage edge, the spokes and centre
//! of an n-gon) are evaluated once and shared, so the triangles are watertight. Primvars:
//! `constant` and `uniform` values are copied, `varying` ones interpolated bilinearly over the
//! ptex domain (the limit of bilinear refinement), `vertex` ones by the vertex patches (as the
//! points), `faceVarying` ones by face-varying patches built from their channel's own topology
//! with the mesh's [`FaceVarying`](super::FaceVarying) rule (OpenSubdiv's non-legacy
//! face-varying patches), so seams stay seams.

use super::{Boundary, Cage, CagePrimvar, FaceVarying, Interpolation, Scheme, TriangleRule};
use glam::{DVec2, DVec3, DVec4};
use opensubdiv_rs::far::{
    AdaptiveOptions, FVarChannelDescriptor, PatchMap, PatchTable, PatchTableFactory,
    PatchTableOptions, PrimvarRefiner, TopologyDescriptor, TopologyRefinerFactory,
};
use opensubdiv_rs::sdc;
use std::collections::HashMap;

/// The most triangles one mesh is refined into (2^24): a request beyond it is refused
/// ([`refine`]) and the level rules stay below it.
pub const MAX_REFINED_TRIANGLES: u64 = 1 << 24;

/// A refined cage: triangles on the limit surface, with per-corner normals and primvars in the
/// layout of [`crate::Mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct Refined {
    /// Vertex positions on the limit surface.
    pub positions: Vec<DVec3>,
    /// Triangles, wound with `(b − a) × (c − a)` towards the front side.
    pub triangles: Vec<[u32; 3]>,
    /// Unit limit-surface normals per triangle corner (towards the front side).
    pub normals: Vec<[DVec3; 3]>,
    /// `displayColor` per triangle corner, when the cage has it.
    pub colors: Option<Vec<[DVec3; 3]>>,
    /// Texture coordinates per triangle corner, when the cage has them.
    pub uvs: Option<Vec<[DVec2; 3]>>,
    /// The cage's named primvars per triangle corner.
    pub primvars: Vec<crate::CornerPrimvar>,
    /// Faces left out of the surface because they repeat a vertex (OpenSubdiv rejects them).
    pub dropped_faces: usize,
}

/// Refines `cage` at `level` (1 to [`super::MAX_LEVEL`]: `2^level` segments along every cage
/// edge). `Err` says why the cage cannot be refined (OpenSubdiv's topology error, a level
/// beyond the limit, more than [`MAX_REFINED_TRIANGLES`] triangles).
pub fn refine(cage: &Cage, level: u32) -> Result<Refined, String> {
    if !(1..=super::MAX_LEVEL).contains(&level) {
        return Err(format!(
            "refinement level {level} is outside 1..={}",
            super::MAX_LEVEL
        ));
    }
    let count = cage.refined_triangles(level);
    if count > MAX_REFINED_TRIANGLES {
        return Err(format!(
            "level {level} would make {count} triangles, more than {MAX_REFINED_TRIANGLES}"
        ));
    }
    // OpenSubdiv code is a dependency: a panic in it on some topology must not take the load
    // down with it.
    std::panic::catch_unwind(|| Refiner::build(cage, level).map(|r| r.tessellate()))
        .unwrap_or_else(|_| Err("OpenSubdiv panicked on this topology".to_owned()))
}

/// A primvar being refined: its cage form and, for `faceVarying`, its patch channel; for
/// `vertex`, its control values at every level.
struct Channel<'a> {
    pv: &'a CagePrimvar,
    fvar: Option<(usize, Vec<[f64; 4]>)>,
    vertex: Option<Vec<[f64; 4]>>,
}

struct Refiner<'a> {
    cage: &'a Cage,
    /// Segments along a cage edge.
    n: u32,
    table: PatchTable,
    /// Control values of the points at every level (cage first), relative to `centre`.
    points: Vec<[f64; 3]>,
    centre: DVec3,
    /// The faces given to OpenSubdiv (faces repeating a vertex left out): cage face index and
    /// offset of its first corner.
    faces: Vec<(usize, usize)>,
    dropped: usize,
    /// Colours, texture coordinates, named primvars: what [`Refiner::roles`] says.
    channels: Vec<Channel<'a>>,
    roles: Vec<Role>,
}

/// What a refined channel becomes.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Colors,
    Uvs,
    /// The cage's primvar at this index.
    Named(usize),
}

/// Where a tessellation vertex lies, for sharing it between the faces that meet there.
#[derive(Clone, Copy, Hash, PartialEq, Eq)]
enum Key {
    /// A cage vertex.
    Vertex(u32),
    /// On the cage edge between two vertices (smaller first), `k` segments from the first.
    Edge(u32, u32, u32),
}

/// The output being built.
#[derive(Default)]
struct Out {
    positions: Vec<DVec3>,
    /// Limit normal per vertex (zero where the tangents are degenerate).
    normals: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Per channel, its values at each triangle's corners.
    values: Vec<Vec<[DVec4; 3]>>,
}

/// The grid of a face (or n-gon sub-face) being tessellated: each point's vertex, and its
/// channels' values (`channels` a point, point-major).
struct Grid {
    vertices: Vec<u32>,
    values: Vec<DVec4>,
    channels: usize,
}

impl Grid {
    fn new(points: usize, channels: usize) -> Grid {
        Grid {
            vertices: vec![0; points],
            values: vec![DVec4::ZERO; points * channels],
            channels,
        }
    }

    fn values_mut(&mut self, k: usize) -> &mut [DVec4] {
        &mut self.values[k * self.channels..(k + 1) * self.channels]
    }
}

impl<'a> Refiner<'a> {
    fn build(cage: &'a Cage, level: u32) -> Result<Refiner<'a>, String> {
        let finite = cage.points.iter().filter(|p| p.is_finite());
        let (lo, hi) = finite.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
            (l.min(*p), h.max(*p))
        });
        let centre = if lo.x <= hi.x {
            (lo + hi) * 0.5
        } else {
            DVec3::ZERO
        };
        // Faces that repeat a vertex are left out (OpenSubdiv's factory refuses them).
        let mut faces = Vec::with_capacity(cage.face_sizes.len());
        let mut start = 0usize;
        for (f, &n) in cage.face_sizes.iter().enumerate() {
            let fv = &cage.face_vertices[start..start + n as usize];
            let repeats = (1..fv.len()).any(|i| fv[..i].contains(&fv[i]));
            if !repeats {
                faces.push((f, start));
            }
            start += n as usize;
        }
        let dropped = cage.face_sizes.len() - faces.len();
        let sizes: Vec<usize> = faces
            .iter()
            .map(|&(f, _)| cage.face_sizes[f] as usize)
            .collect();
        let corners_of = |&(f, s): &(usize, usize)| s..s + cage.face_sizes[f] as usize;
        let vertices: Vec<u32> = faces
            .iter()
            .flat_map(|fs| cage.face_vertices[corners_of(fs)].iter().copied())
            .collect();
        let mut new_face = vec![u32::MAX; cage.face_sizes.len()];
        for (i, &(f, _)) in faces.iter().enumerate() {
            new_face[f] = i as u32;
        }
        let holes: Vec<u32> = cage
            .holes
            .iter()
            .map(|&h| new_face[h as usize])
            .filter(|&h| h != u32::MAX)
            .collect();
        let pairs: Vec<[u32; 2]> = cage.creases.iter().map(|c| c.edge).collect();
        let weights: Vec<f32> = cage.creases.iter().map(|c| c.sharpness).collect();
        let corner_v: Vec<u32> = cage.corners.iter().map(|c| c.vertex).collect();
        let corner_w: Vec<f32> = cage.corners.iter().map(|c| c.sharpness).collect();
        // The channels: colours, texture coordinates, the named primvars.
        let mut sources: Vec<(Role, &'a CagePrimvar)> = Vec::new();
        if let Some(c) = &cage.colors {
            sources.push((Role::Colors, c));
        }
        if let Some(c) = &cage.uvs {
            sources.push((Role::Uvs, c));
        }
        for (k, (_, c)) in cage.primvars.iter().enumerate() {
            sources.push((Role::Named(k), c));
        }
        // Face-varying primvars: one OpenSubdiv channel each (in channel order), indexed per
        // corner of the faces kept.
        let fvar_indices: Vec<(&CagePrimvar, Vec<u32>)> = sources
            .iter()
            .filter(|(_, pv)| pv.interpolation == Interpolation::FaceVarying)
            .map(|(_, pv)| {
                let ix = faces
                    .iter()
                    .flat_map(|fs| pv.indices[corners_of(fs)].iter().copied())
                    .collect();
                (*pv, ix)
            })
            .collect();
        let descriptors: Vec<FVarChannelDescriptor<'_>> = fvar_indices
            .iter()
            .map(|(pv, ix)| FVarChannelDescriptor::new(pv.values.len(), ix))
            .collect();
        let descriptor = TopologyDescriptor::new(cage.points.len(), &sizes, &vertices)
            .with_creases(&pairs, &weights)
            .with_corners(&corner_v, &corner_w)
            .with_holes(&holes)
            .with_fvar_channels(&descriptors);
        let options = sdc::Options::new()
            .with_vtx_boundary_interpolation(match cage.boundary {
                Boundary::None => sdc::VtxBoundaryInterpolation::None,
                Boundary::EdgeOnly => sdc::VtxBoundaryInterpolation::EdgeOnly,
                Boundary::EdgeAndCorner => sdc::VtxBoundaryInterpolation::EdgeAndCorner,
            })
            .with_fvar_linear_interpolation(match cage.face_varying {
                FaceVarying::None => sdc::FVarLinearInterpolation::None,
                FaceVarying::CornersOnly => sdc::FVarLinearInterpolation::CornersOnly,
                FaceVarying::CornersPlus1 => sdc::FVarLinearInterpolation::CornersPlus1,
                FaceVarying::CornersPlus2 => sdc::FVarLinearInterpolation::CornersPlus2,
                FaceVarying::Boundaries => sdc::FVarLinearInterpolation::Boundaries,
                FaceVarying::All => sdc::FVarLinearInterpolation::All,
            })
            .with_triangle_subdivision(match cage.triangle_rule {
                TriangleRule::CatmullClark => sdc::TriangleSubdivision::Catmark,
                TriangleRule::Smooth => sdc::TriangleSubdivision::Smooth,
            })
            .with_creasing_method(sdc::CreasingMethod::Uniform);
        let scheme = match cage.scheme {
            Scheme::CatmullClark => sdc::SchemeType::Catmark,
            Scheme::Loop => sdc::SchemeType::Loop,
            Scheme::Bilinear => sdc::SchemeType::Bilinear,
        };
        let mut refiner = TopologyRefinerFactory::create(descriptor, scheme, options)
            .map_err(|e| format!("OpenSubdiv refuses the topology: {e}"))?;
        // Isolation: at least the tessellation level (every grid point a patch corner or
        // inside a polynomial patch). Semi-sharp features decay one sharpness a level: isolated
        // until they have, the patches are the true limit surface there too, not the crease
        // masks of a still-sharp level. Around infinitely sharp features (darts where a crease
        // ends, crease junctions) the limit masks of a coarse level are approximate (against
        // Blender's OpenSubdiv, 6e-3 of a unit cube's size at level 3): they are isolated to
        // OpenSubdiv's limit, where the error is below 1e-6.
        let sharp = cage
            .creases
            .iter()
            .map(|c| c.sharpness)
            .chain(cage.corners.iter().map(|c| c.sharpness))
            .fold(0.0f32, f32::max);
        let isolation = if sharp >= 10.0 {
            super::MAX_LEVEL as usize
        } else {
            (level as usize).max(sharp.ceil() as usize)
        };
        refiner.refine_adaptive(
            AdaptiveOptions::new(isolation)
                .with_single_crease_patch(true)
                .with_consider_fvar_channels(!descriptors.is_empty()),
        );
        let table = PatchTableFactory::create_with_options(
            &refiner,
            &PatchTableOptions::new()
                .with_fvar_tables(!descriptors.is_empty())
                .with_fvar_legacy_linear_patches(false),
        )
        .map_err(|e| format!("OpenSubdiv cannot build the limit patches: {e}"))?;
        let primvars = PrimvarRefiner::new(&refiner);
        let base: Vec<[f64; 3]> = cage
            .points
            .iter()
            .map(|p| (*p - centre).to_array())
            .collect();
        let mut points = base.clone();
        for l in primvars.interpolate_all(&base) {
            points.extend(l);
        }
        let mut fvar_channel = 0usize;
        let mut channels = Vec::with_capacity(sources.len());
        for (_, pv) in &sources {
            let mut c = Channel {
                pv,
                fvar: None,
                vertex: None,
            };
            match pv.interpolation {
                Interpolation::FaceVarying => {
                    let values: Vec<[f64; 4]> = pv.values.iter().map(|v| v.to_array()).collect();
                    let mut all = values.clone();
                    for l in primvars.interpolate_face_varying_all(fvar_channel, &values) {
                        all.extend(l);
                    }
                    c.fvar = Some((fvar_channel, all));
                    fvar_channel += 1;
                }
                Interpolation::Vertex => {
                    let values: Vec<[f64; 4]> = (0..cage.points.len())
                        .map(|i| pv.at(i).to_array())
                        .collect();
                    let mut all = values.clone();
                    for l in primvars.interpolate_all(&values) {
                        all.extend(l);
                    }
                    c.vertex = Some(all);
                }
                _ => {}
            }
            channels.push(c);
        }
        let roles = sources.iter().map(|(r, _)| *r).collect();
        Ok(Refiner {
            cage,
            n: 1 << level,
            table,
            points,
            centre,
            faces,
            dropped,
            channels,
            roles,
        })
    }

    fn tessellate(self) -> Refined {
        let map = PatchMap::new(&self.table);
        let triangles = self.cage.refined_triangles(self.n.trailing_zeros()) as usize;
        let mut out = Out {
            values: vec![Vec::with_capacity(triangles); self.channels.len()],
            ..Out::default()
        };
        out.triangles.reserve(triangles);
        // A closed quad mesh has about half as many vertices as triangles.
        out.positions.reserve(triangles / 2 + 16);
        out.normals.reserve(triangles / 2 + 16);
        let mut shared: HashMap<Key, u32> = HashMap::new();
        let quads = self.cage.scheme != Scheme::Loop;
        let ptex = self.table.ptex_indices();
        let holes: std::collections::HashSet<u32> = self.cage.holes.iter().copied().collect();
        for (i, &(f, start)) in self.faces.iter().enumerate() {
            if holes.contains(&(f as u32)) {
                continue;
            }
            let fv = &self.cage.face_vertices[start..start + self.cage.face_sizes[f] as usize];
            let first_ptex = ptex.face_id(i) as usize;
            let face = FaceRef {
                cage_face: f,
                start,
                fv,
                first_ptex,
            };
            if !quads {
                self.triangle_face(&map, &face, &mut shared, &mut out);
            } else if fv.len() == 4 {
                self.quad_face(&map, &face, &mut shared, &mut out);
            } else {
                self.ngon_face(&map, &face, &mut shared, &mut out);
            }
        }
        self.finish(out)
    }

    /// Position, normal and vertex primvars at `(ptex, u, v)`, appended as a new vertex.
    fn new_vertex(&self, map: &PatchMap<'_>, ptex: usize, u: f32, v: f32, out: &mut Out) -> u32 {
        let i = out.positions.len() as u32;
        let (p, n) = match map.find_patch(ptex, u, v) {
            Some(patch) => {
                let b = self.table.evaluate_basis(patch, u, v);
                let (mut p, mut du, mut dv) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
                for (k, &cv) in b.indices.iter().enumerate() {
                    let c = self.points[cv as usize];
                    for a in 0..3 {
                        p[a] += c[a] * b.weights[k] as f64;
                        du[a] += c[a] * b.du_weights[k] as f64;
                        dv[a] += c[a] * b.dv_weights[k] as f64;
                    }
                }
                let n = DVec3::from(du).cross(DVec3::from(dv));
                (DVec3::from(p) + self.centre, n.normalize_or_zero())
            }
            None => (DVec3::NAN, DVec3::ZERO),
        };
        out.positions.push(p);
        out.normals.push(n);
        i
    }

    /// The vertex at `(ptex, u, v)`, shared under `key` when given.
    #[allow(clippy::too_many_arguments)]
    fn vertex(
        &self,
        map: &PatchMap<'_>,
        key: Option<Key>,
        ptex: usize,
        u: f32,
        v: f32,
        shared: &mut HashMap<Key, u32>,
        out: &mut Out,
    ) -> u32 {
        match key {
            Some(k) => match shared.get(&k) {
                Some(&i) => i,
                None => {
                    let i = self.new_vertex(map, ptex, u, v, out);
                    shared.insert(k, i);
                    i
                }
            },
            None => self.new_vertex(map, ptex, u, v, out),
        }
    }

    /// The channels' values at grid point `(ptex, u, v)` of `face`, into `out`;
    /// `corner_weights` gives the weights of the face's corners for `varying` data.
    fn values(
        &self,
        map: &PatchMap<'_>,
        face: &FaceRef<'_>,
        ptex: usize,
        (u, v): (f32, f32),
        corner_weights: &[(usize, f64)],
        out: &mut [DVec4],
    ) {
        if self.channels.is_empty() {
            return;
        }
        let patch = if self.channels.iter().any(Channel::needs_patch) {
            map.find_patch(ptex, u, v)
        } else {
            None
        };
        for (c, slot) in self.channels.iter().zip(out) {
            *slot = match c.pv.interpolation {
                Interpolation::Constant => c.pv.at(0),
                Interpolation::Uniform => c.pv.at(face.cage_face),
                Interpolation::Varying => corner_weights
                    .iter()
                    .map(|&(k, w)| c.pv.at(face.fv[k] as usize) * w)
                    .sum(),
                Interpolation::Vertex => match (patch, &c.vertex) {
                    (Some(p), Some(all)) => {
                        let b = self.table.evaluate_basis(p, u, v);
                        combine(&b.indices, &b.weights, all)
                    }
                    _ => DVec4::NAN,
                },
                Interpolation::FaceVarying => match (patch, &c.fvar) {
                    (Some(p), Some((ch, all))) => {
                        let b = self.table.evaluate_basis_face_varying(p, u, v, *ch);
                        combine(&b.indices, &b.weights, all)
                    }
                    _ => DVec4::NAN,
                },
            };
        }
    }

    /// A quad face: one ptex face, `(u, v)` = (0, 0), (1, 0), (1, 1), (0, 1) at its corners.
    fn quad_face(
        &self,
        map: &PatchMap<'_>,
        face: &FaceRef<'_>,
        shared: &mut HashMap<Key, u32>,
        out: &mut Out,
    ) {
        let n = self.n;
        let ptex = face.first_ptex;
        let mut grid = Grid::new(((n + 1) * (n + 1)) as usize, self.channels.len());
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                // Which cage corner or edge the point lies on, counter-clockwise from corner 0.
                let key = match (i, j) {
                    (0, 0) => Some(Key::Vertex(face.fv[0])),
                    (i, 0) if i == n => Some(Key::Vertex(face.fv[1])),
                    (i, j) if i == n && j == n => Some(Key::Vertex(face.fv[2])),
                    (0, j) if j == n => Some(Key::Vertex(face.fv[3])),
                    (i, 0) => Some(edge_key(face.fv[0], face.fv[1], i, n)),
                    (i, j) if i == n => Some(edge_key(face.fv[1], face.fv[2], j, n)),
                    (i, j) if j == n => Some(edge_key(face.fv[2], face.fv[3], n - i, n)),
                    (0, j) => Some(edge_key(face.fv[3], face.fv[0], n - j, n)),
                    _ => None,
                };
                let [w00, w10, w11, w01] = bilinear(u, v);
                let w = [(0, w00), (1, w10), (2, w11), (3, w01)];
                let k = (j * (n + 1) + i) as usize;
                grid.vertices[k] = self.vertex(map, key, ptex, u, v, shared, out);
                self.values(map, face, ptex, (u, v), &w, grid.values_mut(k));
            }
        }
        quad_cells(&grid, n, out);
    }

    /// An n-gon under a quad scheme: `n` ptex faces, sub-face `s` with `(0, 0)` at corner `s`,
    /// `(1, 0)` at the middle of the edge to corner `s + 1`, `(1, 1)` at the face's centre and
    /// `(0, 1)` at the middle of the edge from corner `s − 1`.
    fn ngon_face(
        &self,
        map: &PatchMap<'_>,
        face: &FaceRef<'_>,
        shared: &mut HashMap<Key, u32>,
        out: &mut Out,
    ) {
        let (n, m) = (self.n, self.n / 2);
        let k = face.fv.len();
        // Spokes (middle of edge s → centre, t = 0..=m from the middle) and the centre are the
        // face's own: `spokes[s][t]`, 1 ≤ t < m; the centre once.
        let mut spokes: Vec<Vec<u32>> = vec![vec![u32::MAX; m as usize + 1]; k];
        let mut centre = u32::MAX;
        let inv = 1.0 / k as f64;
        for s in 0..k {
            let ptex = face.first_ptex + s;
            let (prev, next) = ((s + k - 1) % k, (s + 1) % k);
            let mut grid = Grid::new(((m + 1) * (m + 1)) as usize, self.channels.len());
            for j in 0..=m {
                for i in 0..=m {
                    let (u, v) = (i as f32 / m as f32, j as f32 / m as f32);
                    let vertex = if i == m && j == m {
                        if centre == u32::MAX {
                            centre = self.new_vertex(map, ptex, u, v, out);
                        }
                        centre
                    } else if j == 0 && i == 0 {
                        self.vertex(map, Some(Key::Vertex(face.fv[s])), ptex, u, v, shared, out)
                    } else if j == 0 {
                        let key = edge_key(face.fv[s], face.fv[next], i, n);
                        self.vertex(map, Some(key), ptex, u, v, shared, out)
                    } else if i == 0 {
                        let key = edge_key(face.fv[s], face.fv[prev], j, n);
                        self.vertex(map, Some(key), ptex, u, v, shared, out)
                    } else if i == m || j == m {
                        // Spoke s (from the middle of edge s, t = j) or spoke s − 1 (t = i).
                        let (spoke, t) = if i == m { (s, j) } else { (prev, i) };
                        let slot = &mut spokes[spoke][t as usize];
                        if *slot == u32::MAX {
                            *slot = self.new_vertex(map, ptex, u, v, out);
                        }
                        *slot
                    } else {
                        self.new_vertex(map, ptex, u, v, out)
                    };
                    // Bilinear weights of the cage corners over the sub-face (varying data):
                    // its corners are corner s, the two edge middles and the centroid.
                    let [w00, w10, w11, w01] = bilinear(u, v);
                    let mut w: Vec<(usize, f64)> = (0..k).map(|c| (c, w11 * inv)).collect();
                    w[s].1 += w00 + 0.5 * (w10 + w01);
                    w[next].1 += 0.5 * w10;
                    w[prev].1 += 0.5 * w01;
                    let k = (j * (m + 1) + i) as usize;
                    grid.vertices[k] = vertex;
                    self.values(map, face, ptex, (u, v), &w, grid.values_mut(k));
                }
            }
            quad_cells(&grid, m, out);
        }
    }

    /// A triangle under Loop: one ptex face, `(u, v)` = (0, 0), (1, 0), (0, 1) at its corners,
    /// a triangular grid of `n` segments a side.
    fn triangle_face(
        &self,
        map: &PatchMap<'_>,
        face: &FaceRef<'_>,
        shared: &mut HashMap<Key, u32>,
        out: &mut Out,
    ) {
        let n = self.n;
        let ptex = face.first_ptex;
        let row = |j: u32| -> usize { (j * (n + 1) - j * (j.saturating_sub(1)) / 2) as usize };
        let at = |i: u32, j: u32| -> usize { row(j) + i as usize };
        let mut grid = Grid::new(((n + 1) * (n + 2) / 2) as usize, self.channels.len());
        for j in 0..=n {
            for i in 0..=n - j {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let key = match (i, j) {
                    (0, 0) => Some(Key::Vertex(face.fv[0])),
                    (i, 0) if i == n => Some(Key::Vertex(face.fv[1])),
                    (0, j) if j == n => Some(Key::Vertex(face.fv[2])),
                    (i, 0) => Some(edge_key(face.fv[0], face.fv[1], i, n)),
                    (i, j) if i + j == n => Some(edge_key(face.fv[1], face.fv[2], j, n)),
                    (0, j) => Some(edge_key(face.fv[2], face.fv[0], n - j, n)),
                    _ => None,
                };
                let (fu, fv) = (u as f64, v as f64);
                let w = [(0, 1.0 - fu - fv), (1, fu), (2, fv)];
                let k = at(i, j);
                grid.vertices[k] = self.vertex(map, key, ptex, u, v, shared, out);
                self.values(map, face, ptex, (u, v), &w, grid.values_mut(k));
            }
        }
        for j in 0..n {
            for i in 0..n - j {
                let (a, b, c) = (at(i, j), at(i + 1, j), at(i, j + 1));
                push_triangle(&grid, [a, b, c], out);
                if i + j + 1 < n {
                    push_triangle(&grid, [b, at(i + 1, j + 1), c], out);
                }
            }
        }
    }

    /// Triangles whose corners have no limit normal (degenerate tangents) take the mean of the
    /// normals of the triangles around the vertex, weighted by their areas.
    fn finish(self, out: Out) -> Refined {
        let Out {
            positions,
            mut normals,
            triangles,
            values,
        } = out;
        if normals.contains(&DVec3::ZERO) {
            let mut sum = vec![DVec3::ZERO; positions.len()];
            for t in &triangles {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                let g = (b - a).cross(c - a);
                for &i in t {
                    sum[i as usize] += g;
                }
            }
            for (n, s) in normals.iter_mut().zip(sum) {
                if *n == DVec3::ZERO {
                    *n = s.normalize_or_zero();
                }
            }
        }
        let corner_normals = triangles
            .iter()
            .map(|t| t.map(|i| normals[i as usize]))
            .collect();
        let (mut colors, mut uvs, mut primvars) = (None, None, Vec::new());
        for (role, v) in self.roles.iter().zip(values) {
            match *role {
                Role::Colors => colors = Some(v.iter().map(|c| c.map(|x| x.truncate())).collect()),
                Role::Uvs => {
                    uvs = Some(v.iter().map(|c| c.map(|x| DVec2::new(x.x, x.y))).collect())
                }
                Role::Named(k) => primvars.push(crate::CornerPrimvar {
                    name: self.cage.primvars[k].0.clone(),
                    values: v,
                }),
            }
        }
        Refined {
            colors,
            uvs,
            primvars,
            positions,
            normals: corner_normals,
            triangles,
            dropped_faces: self.dropped,
        }
    }
}

impl Channel<'_> {
    fn needs_patch(&self) -> bool {
        matches!(
            self.pv.interpolation,
            Interpolation::Vertex | Interpolation::FaceVarying
        )
    }
}

/// A face being tessellated.
struct FaceRef<'f> {
    /// Index in the cage.
    cage_face: usize,
    #[allow(dead_code)]
    start: usize,
    /// Its cage vertices, in winding order.
    fv: &'f [u32],
    /// Its first ptex face.
    first_ptex: usize,
}

/// The point `k` of `n` segments from `a` along the cage edge `a`–`b`.
fn edge_key(a: u32, b: u32, k: u32, n: u32) -> Key {
    if a < b {
        Key::Edge(a, b, k)
    } else {
        Key::Edge(b, a, n - k)
    }
}

/// `Σ wᵢ · values[indices[i]]`.
fn combine(indices: &[u32], weights: &[f32], values: &[[f64; 4]]) -> DVec4 {
    indices
        .iter()
        .zip(weights)
        .map(|(&i, &w)| DVec4::from(values[i as usize]) * w as f64)
        .sum()
}

/// The bilinear weights of a quad's corners `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)` at `(u, v)`.
fn bilinear(u: f32, v: f32) -> [f64; 4] {
    let (u, v) = (u as f64, v as f64);
    [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v]
}

/// The two triangles of every cell of an `(n + 1)²` grid (row-major, `u` along rows), split
/// along the shorter diagonal.
fn quad_cells(grid: &Grid, n: u32, out: &mut Out) {
    let w = (n + 1) as usize;
    for j in 0..n as usize {
        for i in 0..n as usize {
            let (a, b, c, d) = (
                j * w + i,
                j * w + i + 1,
                (j + 1) * w + i + 1,
                (j + 1) * w + i,
            );
            let p = |k: usize| out.positions[grid.vertices[k] as usize];
            if p(a).distance_squared(p(c)) <= p(b).distance_squared(p(d)) {
                push_triangle(grid, [a, b, c], out);
                push_triangle(grid, [a, c, d], out);
            } else {
                push_triangle(grid, [a, b, d], out);
                push_triangle(grid, [b, c, d], out);
            }
        }
    }
}

/// The triangle of grid points `k`: its vertices and its channels' corner values.
fn push_triangle(grid: &Grid, k: [usize; 3], out: &mut Out) {
    out.triangles.push(k.map(|k| grid.vertices[k]));
    for (c, values) in out.values.iter_mut().enumerate() {
        values.push(k.map(|k| grid.values[k * grid.channels + c]));
    }
}
