//! The instancing test scene and its flattened twin, with the brute-force reference queries
//! shared by `instancing.rs` and `instancing_render.rs`.
//!
//! Instanced geometry against the same geometry flattened into world-space meshes.
//!
//! The scene: a prototype of a single-sided quad (no binding of its own: the instance's material
//! applies) and a single-sided closed tetrahedron (its own material), a second prototype of a
//! double-sided triangle, eight instances (translated, rotated, non-uniformly scaled, sheared,
//! mirrored, mirrored and non-uniformly scaled, upside down), and world-space meshes around
//! them. Flattening maps each prototype mesh by its instance transform the way the loader
//! maps a world mesh (`lux_usd::mesh::to_world`: positions `M·v`, winding reversed when
//! `det M < 0`, corner normals `normalize(M⁻ᵀ·n)`, per-corner primvars reordered like the
//! triangles).
//!
//! **What must agree, and how exactly.** For a ray whose answer is not decided by `f32`
//! rounding ("robust" below), both BVHs must find the same triangle as an `f64` brute force
//! over the flattened triangles. The renderer then re-intersects that triangle in `f64` from
//! the same world vertices — flattening computes `M·v` with `DMat4::transform_point3` and the
//! instance path with `DAffine3::transform_point3`, the same operations in the same order — so
//! `t`, `p`, `ng`, `back` and the barycentrics are bit-identical (reversing a winding negates the
//! cross product exactly and swaps `b1`, `b2` exactly). `occluded` agrees exactly;
//! `first_occluder` returns the `f32` traversal distance, computed in prototype space for an
//! instance, so both agree with the exact distance within the `f32` error the renderer already
//! budgets for hit distances (`offset_scale`, 2⁻¹⁵ relative).
//!
//! A ray is robust when no triangle it passes is within `EPS_BARY` (barycentric) of an edge,
//! no hit is within `eps_t` of `tmin`/`tmax` or of another hit, and no plane is met at a grazing
//! angle (`|cos| < EPS_COS`): the `f32` errors (~10⁻⁶ here) are far below these margins.

#![allow(dead_code)]

use glam::{DMat3, DMat4, DQuat, DVec2, DVec3};
use lux_render::geometry::{Hit, offset_scale};
use lux_render::material::{Bsdf, SurfacePoint};
use lux_sample::SplitMix64;
use lux_usd::{Input, Instance, Material, Mesh, Prototype, Scene};
use std::sync::OnceLock;

/// The Lambertian albedo at a surface point.
pub fn albedo(p: &SurfacePoint) -> DVec3 {
    match &p.bsdf {
        Bsdf::Diffuse(b) => b.albedo,
        Bsdf::Graph(_) => panic!("the tests shade with Lambertian materials"),
    }
}

pub const EPS_BARY: f64 = 1e-4;
pub const EPS_COS: f64 = 1e-3;

pub fn eps_t(o: DVec3, t: f64) -> f64 {
    1e-4 * (1.0 + o.abs().max_element() + t.min(1e6))
}

/// The two materials of the test scenes, read by the loader from a small stage (so that the test
/// does not depend on every field of `lux_usd::Material`): `/Red` then `/Green`.
pub fn materials() -> Vec<Material> {
    static MATERIALS: OnceLock<Vec<Material>> = OnceLock::new();
    MATERIALS
        .get_or_init(|| {
            let mut usda = String::from("#usda 1.0\n");
            for (name, c) in [
                ("Red", "(0.75, 0.25, 0.1875)"),
                ("Green", "(0.1875, 0.6875, 0.3125)"),
            ] {
                usda += &format!(
                    r#"
def Material "{name}"
{{
    token outputs:surface.connect = </{name}/Surface.outputs:surface>
    def Shader "Surface"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = {c}
        token outputs:surface
    }}
}}
def Mesh "Uses{name}" (prepend apiSchemas = ["MaterialBindingAPI"])
{{
    rel material:binding = </{name}>
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
}}
"#
                );
            }
            let dir = std::env::temp_dir().join(format!("lux-instancing-{}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            let path = dir.join("materials.usda");
            std::fs::write(&path, usda).unwrap();
            let scene = lux_usd::load_stage(&path, 1.0).expect("material stage loads");
            std::fs::remove_dir_all(&dir).unwrap();
            let mut m = scene.materials;
            m.sort_by(|a, b| b.path.cmp(&a.path));
            assert_eq!(m.len(), 2);
            assert_eq!(m[0].diffuse, Input::Value(DVec3::new(0.75, 0.25, 0.1875)));
            assert_eq!(
                m[1].diffuse,
                Input::Value(DVec3::new(0.1875, 0.6875, 0.3125))
            );
            m
        })
        .clone()
}

/// Corner values of a triangle list from a per-vertex function.
pub fn corners<T: Copy>(tris: &[[u32; 3]], f: impl Fn(usize) -> T) -> Vec<[T; 3]> {
    tris.iter().map(|t| t.map(|i| f(i as usize))).collect()
}

/// Prototype 0: a bent-normal quad (no material) and a tetrahedron (material 0).
pub fn quad_mesh() -> Mesh {
    let positions = vec![
        DVec3::new(-0.5, 0.0, -0.5),
        DVec3::new(-0.5, 0.0, 0.5),
        DVec3::new(0.5, 0.0, 0.5),
        DVec3::new(0.5, 0.0, -0.5),
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3]];
    let p = positions.clone();
    Mesh {
        normals: Some(corners(&triangles, |i| {
            DVec3::new(0.6 * p[i].x, 1.0, 0.4 * p[i].z).normalize()
        })),
        uvs: Some(corners(&triangles, |i| {
            DVec2::new(p[i].x + 0.5, p[i].z + 0.5)
        })),
        colors: Some(corners(&triangles, |i| {
            DVec3::new(0.2 + p[i].x.abs(), 0.5, 0.3 + p[i].z.abs())
        })),
        prototype: Some(0),
        ..Mesh::new("/Proto/Quad", positions, triangles)
    }
}

pub fn tetra_mesh() -> Mesh {
    let v = vec![
        DVec3::new(0.0, 0.2, 0.3),
        DVec3::new(0.3, 0.2, -0.2),
        DVec3::new(-0.3, 0.2, -0.2),
        DVec3::new(0.05, 0.7, 0.0),
    ];
    let centroid = v.iter().copied().sum::<DVec3>() / 4.0;
    // Wind each face so (b − a) × (c − a) points away from the opposite vertex (outwards).
    let triangles: Vec<[u32; 3]> = [[0, 1, 2, 3], [0, 1, 3, 2], [0, 2, 3, 1], [1, 2, 3, 0]]
        .iter()
        .map(|&[a, b, c, o]| {
            let n = (v[b as usize] - v[a as usize]).cross(v[c as usize] - v[a as usize]);
            if n.dot(v[o as usize] - v[a as usize]) > 0.0 {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .collect();
    let normals = corners(&triangles, |i| (v[i] - centroid).normalize());
    Mesh {
        normals: Some(normals),
        material: Some(0),
        prototype: Some(0),
        ..Mesh::new("/Proto/Tetra", v, triangles)
    }
}

pub fn triangle_mesh() -> Mesh {
    let positions = vec![
        DVec3::new(-0.4, -0.3, 0.0),
        DVec3::new(0.5, -0.2, 0.1),
        DVec3::new(0.0, 0.6, -0.1),
    ];
    Mesh {
        double_sided: true,
        colors: Some(vec![[
            DVec3::new(0.9, 0.1, 0.1),
            DVec3::new(0.1, 0.9, 0.1),
            DVec3::new(0.1, 0.1, 0.9),
        ]]),
        prototype: Some(1),
        ..Mesh::new("/Proto2/Tri", positions, vec![[0, 1, 2]])
    }
}

pub fn world_quad(path: &str, y: f64, half: f64, double_sided: bool) -> Mesh {
    Mesh {
        double_sided,
        ..Mesh::new(
            path,
            vec![
                DVec3::new(-half, y, -half),
                DVec3::new(-half, y, half),
                DVec3::new(half, y, half),
                DVec3::new(half, y, -half),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }
}

pub fn trs(t: DVec3, r: DQuat, s: DVec3) -> DMat4 {
    DMat4::from_scale_rotation_translation(s, r, t)
}

/// The instanced test scene (no lights or camera).
pub fn instanced_scene() -> Scene {
    let mut s = Scene::empty("instancing.usda");
    s.materials = materials();
    s.meshes = vec![
        world_quad("/Floor", -1.0, 6.0, false),
        quad_mesh(),
        tetra_mesh(),
        triangle_mesh(),
        Mesh {
            material: Some(1),
            ..world_quad("/Shelf", 2.5, 0.8, true)
        },
    ];
    s.prototypes = vec![
        Prototype {
            path: "/Proto".into(),
            meshes: vec![1, 2],
        },
        Prototype {
            path: "/Proto2".into(),
            meshes: vec![3],
        },
    ];
    let axis =
        |x: f64, y: f64, z: f64, a: f64| DQuat::from_axis_angle(DVec3::new(x, y, z).normalize(), a);
    let shear = DMat4::from_cols(
        glam::DVec4::new(1.0, 0.3, 0.0, 0.0),
        glam::DVec4::new(0.0, 1.0, 0.2, 0.0),
        glam::DVec4::new(0.1, 0.0, 1.0, 0.0),
        glam::DVec4::new(3.0, 1.0, -1.0, 1.0),
    );
    let placements = [
        (
            0,
            DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)),
            Some(1),
        ),
        (
            0,
            trs(
                DVec3::new(-2.0, 0.5, 1.0),
                axis(1.0, 2.0, 3.0, 0.7),
                DVec3::ONE,
            ),
            None,
        ),
        (
            0,
            trs(
                DVec3::new(0.0, 0.0, -2.0),
                axis(0.0, 1.0, 0.0, 0.3),
                DVec3::new(2.0, 0.5, 1.3),
            ),
            Some(1),
        ),
        (
            0,
            trs(
                DVec3::new(0.0, 1.5, 2.0),
                DQuat::IDENTITY,
                DVec3::new(-1.0, 1.0, 1.0),
            ),
            Some(0),
        ),
        (
            0,
            trs(
                DVec3::new(-3.0, 1.0, -2.0),
                axis(0.2, 1.0, -0.4, 1.1),
                DVec3::new(1.5, -0.7, 1.2),
            ),
            Some(1),
        ),
        (1, shear, None),
        (
            1,
            trs(
                DVec3::new(1.0, 2.0, 1.0),
                axis(1.0, 0.0, 1.0, 0.5),
                DVec3::new(-2.0, 1.0, 1.0),
            ),
            None,
        ),
        (
            0,
            trs(
                DVec3::new(-1.0, -0.5, 3.0),
                axis(1.0, 0.0, 0.0, std::f64::consts::PI),
                DVec3::ONE,
            ),
            None,
        ),
    ];
    s.instances = placements
        .iter()
        .enumerate()
        .map(|(i, &(prototype, to_world, material))| Instance {
            path: format!("/Inst{i}"),
            prototype,
            to_world,
            material,
        })
        .collect();
    s
}

/// Where a flattened mesh came from: the instance (`None` for a world mesh), the source mesh
/// index, and whether the instance mirrors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Origin {
    pub instance: Option<usize>,
    pub mesh: usize,
    pub mirror: bool,
}

/// Reverses a triangle's corner order when `mirror` (the loader's winding flip).
pub fn swap<T: Copy>(c: [T; 3], mirror: bool) -> [T; 3] {
    if mirror { [c[0], c[2], c[1]] } else { c }
}

/// The scene with every instance flattened into world meshes, and per flattened mesh where it
/// came from.
pub fn flatten(s: &Scene) -> (Scene, Vec<Origin>) {
    let mut f = Scene {
        prototypes: Vec::new(),
        instances: Vec::new(),
        meshes: Vec::new(),
        ..s.clone()
    };
    let mut origin = Vec::new();
    for (mi, m) in s.meshes.iter().enumerate() {
        if m.prototype.is_none() {
            f.meshes.push(m.clone());
            origin.push(Origin {
                instance: None,
                mesh: mi,
                mirror: false,
            });
        }
    }
    for (ii, inst) in s.instances.iter().enumerate() {
        let w = inst.to_world;
        let mirror = DMat3::from_mat4(w).determinant() < 0.0;
        let nm = DMat3::from_mat4(w).inverse().transpose();
        for (mi, m) in s.meshes.iter().enumerate() {
            if m.prototype != Some(inst.prototype) {
                continue;
            }
            f.meshes.push(Mesh {
                positions: m.positions.iter().map(|p| w.transform_point3(*p)).collect(),
                triangles: m.triangles.iter().map(|&t| swap(t, mirror)).collect(),
                normals: m.normals.as_ref().map(|n| {
                    n.iter()
                        .map(|c| swap(c.map(|v| (nm * v).normalize_or_zero()), mirror))
                        .collect()
                }),
                colors: m
                    .colors
                    .as_ref()
                    .map(|c| c.iter().map(|&c| swap(c, mirror)).collect()),
                uvs: m
                    .uvs
                    .as_ref()
                    .map(|c| c.iter().map(|&c| swap(c, mirror)).collect()),
                material: m.material.or(inst.material),
                prototype: None,
                ..m.clone()
            });
            origin.push(Origin {
                instance: Some(ii),
                mesh: mi,
                mirror,
            });
        }
    }
    (f, origin)
}

/// `f64` brute force over a scene without instances.
pub struct Brute {
    /// Closest front-or-double-sided hit: (t, mesh, tri).
    pub closest: Option<(f64, usize, usize)>,
    /// Closest hit, either side.
    pub nearest: Option<(f64, usize, usize)>,
    /// Whether `f32` rounding cannot change any answer for this ray.
    pub robust: bool,
}

pub fn brute(s: &Scene, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Brute {
    let mut robust = true;
    let mut hits = Vec::new();
    for (mi, m) in s.meshes.iter().enumerate() {
        for (ti, t) in m.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a);
            let denom = n.dot(d);
            if denom == 0.0 {
                continue;
            }
            let th = n.dot(a - o) / denom;
            let e = eps_t(o, th);
            if !(th > tmin - e && th < tmax + e) {
                continue;
            }
            let p = o + th * d;
            let inv = 1.0 / n.length_squared();
            let b1 = -(c - a).cross(p - a).dot(n) * inv;
            let b2 = (b - a).cross(p - a).dot(n) * inv;
            let margin = b1.min(b2).min(1.0 - b1 - b2);
            if margin < -EPS_BARY {
                continue;
            }
            if margin < EPS_BARY
                || (th - tmin).abs() < e
                || (th - tmax).abs() < e
                || denom.abs() < EPS_COS * n.length()
            {
                robust = false;
            }
            if margin > 0.0 && th > tmin && th < tmax {
                hits.push((th, mi, ti, m.double_sided || denom < 0.0));
            }
        }
    }
    hits.sort_by(|x, y| x.0.total_cmp(&y.0));
    for w in hits.windows(2) {
        if w[1].0 - w[0].0 < eps_t(o, w[0].0) {
            robust = false;
        }
    }
    Brute {
        closest: hits.iter().find(|h| h.3).map(|h| (h.0, h.1, h.2)),
        nearest: hits.first().map(|h| (h.0, h.1, h.2)),
        robust,
    }
}

/// Random rays: origins in a box around the scene; directions aimed near a random instance's
/// origin, into the scene's region, or uniform; `tmax` either infinite or random.
pub fn rays(s: &Scene, n: usize, seed: u64) -> Vec<(DVec3, DVec3, f64)> {
    let mut rng = SplitMix64::new(seed);
    let box_point = |half: f64, rng: &mut SplitMix64| {
        let [a, b] = rng.next_2d();
        let c = rng.next_f64();
        DVec3::new(2.0 * a - 1.0, 2.0 * b - 1.0, 2.0 * c - 1.0) * half
    };
    (0..n)
        .map(|i| {
            let o = box_point(7.0, &mut rng);
            let d = if i % 3 == 0 {
                let k = (rng.next_u64() % s.instances.len() as u64) as usize;
                let at = s.instances[k]
                    .to_world
                    .transform_point3(DVec3::new(0.0, 0.3, 0.0));
                (at + box_point(0.6, &mut rng) - o).normalize()
            } else if i % 3 == 2 {
                let [u, v] = rng.next_2d();
                let z = 2.0 * u - 1.0;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = std::f64::consts::TAU * v;
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            } else {
                (box_point(3.5, &mut rng) - o).normalize()
            };
            let tmax = if i % 4 == 0 {
                1.0 + 14.0 * rng.next_f64()
            } else {
                f64::INFINITY
            };
            (o, d, tmax)
        })
        .collect()
}

/// The flattened hit of an instanced one (mesh index and corner order mapped), for comparison.
pub fn as_flat(h: &Hit, origin: &[Origin]) -> Hit {
    let (fi, o) = origin
        .iter()
        .enumerate()
        .find(|(_, o)| o.instance == h.instance && o.mesh == h.mesh)
        .expect("every drawn mesh is flattened");
    Hit {
        mesh: fi,
        instance: None,
        bary: if o.mirror {
            DVec2::new(h.bary.y, h.bary.x)
        } else {
            h.bary
        },
        offset: offset_scale(h.p),
        ..*h
    }
}
