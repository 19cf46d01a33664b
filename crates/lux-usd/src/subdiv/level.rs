//! At which level a subdivision surface is refined: fixed, or by its size on screen.

use super::{Cage, MAX_REFINED_TRIANGLES, refine};
use crate::Scene;
use crate::camera::{Camera, Projection};
use crate::error::{Warning, WarningKind};
use glam::{DMat3, DMat4, DVec3};
use lux_math::LightShape;

/// The deepest refinement level (OpenSubdiv's isolation limit): `2^10` segments a cage edge.
pub const MAX_LEVEL: u32 = 10;

/// The screen rule's target: refined edges about this many pixels long where the mesh comes
/// nearest the camera.
pub const TARGET_EDGE_PIXELS: f64 = 4.0;

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

/// The screen rule: the smallest level `L ≥ 1` whose refined edges, `ē / 2^L` with `ē` the
/// cage's mean edge length in world units, are at most [`TARGET_EDGE_PIXELS`] long on screen
/// where the cage comes nearest the camera, capped at `max_level`:
///
/// `L = clamp(⌈log₂(ē · s / TARGET_EDGE_PIXELS)⌉, 1, max_level)`, with `s` the pixels per world
/// unit at the cage's world box: `focalLength / horizontalAperture · width / d` for a
/// perspective camera (`d` the distance from the eye to the box, at least the near clipping
/// distance), `width / (horizontalAperture / 10)` for an orthographic one (its aperture is in
/// tenths of a scene unit).
pub fn screen_level(
    cage: &Cage,
    to_world: &DMat4,
    camera: &Camera,
    width: u32,
    max_level: u32,
) -> u32 {
    let (lo, hi) = cage
        .points
        .iter()
        .filter(|p| p.is_finite())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
            (l.min(*p), h.max(*p))
        });
    if lo.x > hi.x {
        return 1;
    }
    // The world box of the cage's box under `to_world`.
    let (mut wlo, mut whi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for k in 0..8 {
        let c = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let w = to_world.transform_point3(c);
        wlo = wlo.min(w);
        whi = whi.max(w);
    }
    let m = DMat3::from_mat4(*to_world);
    let stretch = m
        .x_axis
        .length()
        .max(m.y_axis.length())
        .max(m.z_axis.length());
    let edge = cage.mean_edge() * stretch;
    let pixels_per_unit = match camera.projection {
        Projection::Orthographic => width as f64 / (camera.horizontal_aperture / 10.0),
        Projection::Perspective => {
            let eye = camera.camera_to_world.transform_point3(DVec3::ZERO);
            let d = (eye.clamp(wlo, whi) - eye)
                .length()
                .max(camera.clipping_range.x)
                .max(1e-9);
            camera.focal_length / camera.horizontal_aperture * width as f64 / d
        }
    };
    let ratio = edge * pixels_per_unit / TARGET_EDGE_PIXELS;
    let level = if ratio.is_finite() && ratio > 1.0 {
        ratio.log2().ceil().min(MAX_LEVEL as f64) as u32
    } else if ratio.is_finite() {
        1
    } else {
        max_level
    };
    level.clamp(1, max_level.max(1))
}

impl Scene {
    /// Refines every subdivision surface ([`crate::Mesh::subdivision`]) into triangles on its
    /// limit surface at the level `rule` gives (a prototype's once, at the deepest level any of
    /// its instances needs), and drops the cages: level 0 keeps a cage's polygons. A level
    /// whose triangles would pass [`MAX_REFINED_TRIANGLES`] is lowered, and a cage OpenSubdiv
    /// cannot refine is drawn as its polygons, each with a warning naming the prim. A
    /// `MeshLightAPI` light's emitting triangles follow its refined mesh. Returns the number of
    /// meshes refined (also added to [`Scene::drawn`]).
    pub fn refine_subdivision(&mut self, rule: &LevelRule<'_>) -> usize {
        let mut refined = 0usize;
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
                    Some(p) => self
                        .instances
                        .iter()
                        .filter(|i| i.prototype == p)
                        .map(|i| screen_level(&cage, &i.to_world, camera, width, max_level))
                        .max()
                        .unwrap_or(0),
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
                    refined += 1;
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
        self.drawn.refined_meshes += refined;
        refined
    }
}
