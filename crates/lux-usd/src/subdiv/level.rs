//! At which level a subdivision surface is refined: fixed, or by its size on screen.

use super::{Cage, MAX_REFINED_TRIANGLES, refine};
use crate::Scene;
use crate::camera::{Camera, Projection};
use crate::error::{Warning, WarningKind};
use glam::{DMat3, DMat4, DVec3};
use lux_math::LightShape;
use std::collections::HashMap;

/// The deepest refinement level (OpenSubdiv's isolation limit): `2^10` segments a cage edge.
pub const MAX_LEVEL: u32 = 10;

/// The screen rule's target ([`screen_level`]): refined facets within this many pixels of the
/// limit surface on screen.
pub const TARGET_SAGITTA_PIXELS: f64 = 0.25;

/// A subdivision surface [`Scene::refine_subdivision`] refined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Refinement {
    /// Index into `Scene::meshes`.
    pub mesh: usize,
    /// The level it was refined at.
    pub level: u32,
}

/// How [`Scene::refine_subdivision`] picks each subdivision surface's level.
#[derive(Clone, Copy, Debug)]
pub enum LevelRule<'c> {
    /// Every surface at this level; 0 keeps the cages' polygons (what hdEmbree draws at
    /// usdrecord's default complexity).
    Fixed(u32),
    /// By size on screen ([`screen_level`]), at most `max_level`.
    Screen {
        /// The render camera.
        camera: &'c Camera,
        /// The image width in pixels.
        width: u32,
        /// The deepest level the rule picks.
        max_level: u32,
    },
}

/// The screen rule: the smallest level `L ≥ 1` at which the refined facets stay within
/// [`TARGET_SAGITTA_PIXELS`] of the limit surface on screen, face by face, capped at
/// `max_level`.
///
/// A cage face whose longest edge is `e` pixels long on screen (at the face's nearest
/// distance) and whose normal turns by `θ` towards its neighbours (the largest angle between
/// its normal and an edge-neighbour's; an edge sharpened to infinity turns the surface
/// without curving it and does not count) bends the limit surface by about `κ = θ / e` per
/// pixel; a refined edge `e / 2^L` long then stands `(e / 2^L)² κ / 8` off the surface (the
/// sagitta of a chord). So
///
/// `L = clamp(max over faces ⌈log₄(e · θ / (8 · TARGET_SAGITTA_PIXELS))⌉, 1, max_level)`,
///
/// with `e` in pixels through `focalLength / horizontalAperture · width / d` per world unit
/// for a perspective camera (`d` the distance from the eye to the face's box, at least the
/// near clipping distance) and `width / (horizontalAperture / 10)` for an orthographic one
/// (whose aperture is in tenths of a scene unit). `to_world` places the cage (a prototype's,
/// by one of its instances): its edges are measured at their longest stretch and its
/// distances at their shortest.
pub fn screen_level(
    cage: &Cage,
    to_world: &DMat4,
    camera: &Camera,
    width: u32,
    max_level: u32,
) -> u32 {
    let max_level = max_level.clamp(1, MAX_LEVEL);
    let m = DMat3::from_mat4(*to_world);
    let svd = [m.x_axis, m.y_axis, m.z_axis].map(|a| a.length());
    let (stretch, shrink) = (
        svd.iter().copied().fold(0.0, f64::max),
        svd.iter().copied().fold(f64::INFINITY, f64::min),
    );
    // The eye in the cage's space; lengths there scale by at most `stretch` into the world,
    // distances by at least `shrink`.
    let eye = to_world
        .inverse()
        .transform_point3(camera.camera_to_world.transform_point3(DVec3::ZERO));
    let focal = camera.focal_length / camera.horizontal_aperture * width as f64;
    let pixels = |length: f64, distance: f64| -> f64 {
        match camera.projection {
            Projection::Orthographic => {
                length * stretch * width as f64 / (camera.horizontal_aperture / 10.0)
            }
            Projection::Perspective => {
                let d = (distance * shrink).max(camera.clipping_range.x).max(1e-12);
                length * stretch * focal / d
            }
        }
    };
    let turn = face_turns(cage);
    let mut level = 1u32;
    let mut start = 0usize;
    for (f, &n) in cage.face_sizes.iter().enumerate() {
        let fv = &cage.face_vertices[start..start + n as usize];
        start += n as usize;
        if turn[f] <= 0.0 {
            continue;
        }
        let (mut lo, mut hi, mut longest) = (DVec3::INFINITY, DVec3::NEG_INFINITY, 0.0f64);
        for k in 0..fv.len() {
            let (a, b) = (
                cage.points[fv[k] as usize],
                cage.points[fv[(k + 1) % fv.len()] as usize],
            );
            lo = lo.min(a);
            hi = hi.max(a);
            longest = longest.max(a.distance(b));
        }
        let e = pixels(longest, (eye.clamp(lo, hi) - eye).length());
        let ratio = e * turn[f] / (8.0 * TARGET_SAGITTA_PIXELS);
        let l = if ratio.is_nan() {
            continue;
        } else if ratio > 1.0 {
            (ratio.log2() / 2.0).ceil().min(max_level as f64) as u32
        } else {
            1
        };
        level = level.max(l);
        if level >= max_level {
            break;
        }
    }
    level.min(max_level)
}

/// The placements of a prototype's cage that look largest from the camera (its box's
/// diagonal over the distance to the box, times the placement's stretch; the 4 largest):
/// the screen rule judges the prototype by them alone, so that its cost does not grow with
/// the instance count.
fn nearest_placements<'m>(
    cage: &Cage,
    placements: &'m [DMat4],
    camera: &Camera,
) -> impl Iterator<Item = &'m DMat4> {
    const KEEP: usize = 4;
    let (lo, hi) = cage
        .points
        .iter()
        .filter(|p| p.is_finite())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
            (l.min(*p), h.max(*p))
        });
    let eye = camera.camera_to_world.transform_point3(DVec3::ZERO);
    let mut scored: Vec<(f64, usize)> = placements
        .iter()
        .enumerate()
        .map(|(i, m)| {
            if lo.x > hi.x {
                return (0.0, i);
            }
            let (mut wlo, mut whi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for k in 0..8 {
                let c = DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let w = m.transform_point3(c);
                wlo = wlo.min(w);
                whi = whi.max(w);
            }
            let d = (eye.clamp(wlo, whi) - eye).length().max(1e-12);
            let size = (whi - wlo).length();
            let score = if camera.projection == Projection::Orthographic {
                size
            } else {
                size / d
            };
            (if score.is_nan() { 0.0 } else { score }, i)
        })
        .collect();
    // Largest first; ties by placement order (deterministic).
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    scored.truncate(KEEP);
    scored.into_iter().map(move |(_, i)| &placements[i])
}

/// Per face, the largest angle (radians) between its normal (Newell's) and the normal of a
/// face across one of its edges; edges sharpened to infinity and boundary edges do not count.
fn face_turns(cage: &Cage) -> Vec<f64> {
    let mut normals = Vec::with_capacity(cage.face_sizes.len());
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    let mut start = 0usize;
    for (f, &n) in cage.face_sizes.iter().enumerate() {
        let fv = &cage.face_vertices[start..start + n as usize];
        start += n as usize;
        let mut normal = DVec3::ZERO;
        for k in 0..fv.len() {
            let (a, b) = (fv[k], fv[(k + 1) % fv.len()]);
            let (p, q) = (cage.points[a as usize], cage.points[b as usize]);
            normal += DVec3::new(
                (p.y - q.y) * (p.z + q.z),
                (p.z - q.z) * (p.x + q.x),
                (p.x - q.x) * (p.y + q.y),
            );
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(f as u32);
        }
        normals.push(normal.normalize_or_zero());
    }
    for c in &cage.creases {
        if c.sharpness >= 10.0 {
            edges.remove(&(c.edge[0].min(c.edge[1]), c.edge[0].max(c.edge[1])));
        }
    }
    let mut turn = vec![0.0f64; normals.len()];
    for faces in edges.values() {
        for (i, &f) in faces.iter().enumerate() {
            for &g in &faces[i + 1..] {
                let (a, b) = (normals[f as usize], normals[g as usize]);
                if a == DVec3::ZERO || b == DVec3::ZERO {
                    continue;
                }
                let angle = a.dot(b).clamp(-1.0, 1.0).acos();
                turn[f as usize] = turn[f as usize].max(angle);
                turn[g as usize] = turn[g as usize].max(angle);
            }
        }
    }
    turn
}

impl Scene {
    /// Refines every subdivision surface ([`crate::Mesh::subdivision`]) into triangles on its
    /// limit surface at the level `rule` gives (a prototype's once, at the deepest level any of
    /// its instances needs), and drops the cages: level 0 keeps a cage's polygons. A level
    /// whose triangles would pass [`MAX_REFINED_TRIANGLES`] is lowered, and a cage OpenSubdiv
    /// cannot refine is drawn as its polygons, each with a warning naming the prim. A
    /// `MeshLightAPI` light's emitting triangles follow its refined mesh. Returns the meshes
    /// refined and their levels (their number is also added to [`Scene::drawn`]).
    pub fn refine_subdivision(&mut self, rule: &LevelRule<'_>) -> Vec<Refinement> {
        let mut refined = Vec::new();
        let mut by_prototype: Vec<Vec<DMat4>> = vec![Vec::new(); self.prototypes.len()];
        if matches!(rule, LevelRule::Screen { .. }) {
            for i in &self.instances {
                if let Some(v) = by_prototype.get_mut(i.prototype) {
                    v.push(i.to_world);
                }
            }
        }
        for mi in 0..self.meshes.len() {
            let Some(cage) = self.meshes[mi].subdivision.clone() else {
                continue;
            };
            let mut level = match *rule {
                LevelRule::Fixed(l) => l.min(MAX_LEVEL),
                LevelRule::Screen {
                    camera,
                    width,
                    max_level,
                } => match self.meshes[mi].prototype {
                    None => screen_level(&cage, &DMat4::IDENTITY, camera, width, max_level),
                    Some(p) => {
                        let placements = by_prototype.get(p).map_or(&[][..], |v| &v[..]);
                        nearest_placements(&cage, placements, camera)
                            .map(|m| screen_level(&cage, m, camera, width, max_level))
                            .max()
                            .unwrap_or(0)
                    }
                },
            };
            let wanted = level;
            while level > 0 && cage.refined_triangles(level) > MAX_REFINED_TRIANGLES {
                level -= 1;
            }
            let path = self.meshes[mi].path.clone();
            if level < wanted {
                self.warnings.push(Warning {
                    prim: path.clone(),
                    kind: WarningKind::Unsupported,
                    message: format!(
                        "subdivision level {wanted} would make {} triangles (at most {} a \
                         mesh); refined at level {level}",
                        cage.refined_triangles(wanted),
                        MAX_REFINED_TRIANGLES
                    ),
                });
            }
            let mesh = &mut self.meshes[mi];
            mesh.subdivision = None;
            if level == 0 {
                continue;
            }
            match refine(&cage, level) {
                Ok(r) => {
                    if r.dropped_faces > 0 {
                        self.warnings.push(Warning {
                            prim: path.clone(),
                            kind: WarningKind::InvalidGeometry,
                            message: format!(
                                "{} faces repeat a vertex and are left out of the {} surface",
                                r.dropped_faces,
                                cage.scheme.token()
                            ),
                        });
                    }
                    mesh.positions = r.positions;
                    mesh.triangles = r.triangles;
                    mesh.normals = Some(r.normals);
                    mesh.colors = r.colors;
                    mesh.uvs = r.uvs;
                    mesh.primvars = r.primvars;
                    if let Some(li) = mesh.light
                        && let Some(light) = self.lights.get_mut(li)
                        && let LightShape::Mesh { triangles } = &mut light.shape
                    {
                        let to_light = light.light_to_world.inverse();
                        *triangles = mesh
                            .triangles
                            .iter()
                            .map(|t| {
                                t.map(|i| to_light.transform_point3(mesh.positions[i as usize]))
                            })
                            .collect();
                    }
                    refined.push(Refinement { mesh: mi, level });
                }
                Err(e) => self.warnings.push(Warning {
                    prim: path,
                    kind: WarningKind::InvalidGeometry,
                    message: format!(
                        "the {} surface cannot be refined ({e}); drawn as its polygons",
                        cage.scheme.token()
                    ),
                }),
            }
        }
        self.drawn.refined_meshes += refined.len();
        refined
    }
}
