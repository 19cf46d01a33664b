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

use glam::{DAffine3, DMat3, DMat4, DQuat, DVec2, DVec3};
use lux_math::{LightShape, Profile};
use lux_render::conformance::{ProfileSource, ResolvedProfile};
use lux_render::geometry::{Geometry, Hit, offset_scale};
use lux_render::material::{Bsdf, Materials, SurfacePoint};
use lux_render::render::{RenderOptions, Renderer};

/// The Lambertian albedo at a surface point.
fn albedo(p: &SurfacePoint) -> DVec3 {
    match p.bsdf {
        Bsdf::Diffuse(b) => b.albedo,
    }
}
use lux_sample::SplitMix64;
use lux_usd::{Camera, Diffuse, Instance, Light, Material, Mesh, Prototype, Scene};
use std::sync::OnceLock;

const EPS_BARY: f64 = 1e-4;
const EPS_COS: f64 = 1e-3;

fn eps_t(o: DVec3, t: f64) -> f64 {
    1e-4 * (1.0 + o.abs().max_element() + t.min(1e6))
}

/// The two materials of the test scenes, read by the loader from a small stage (so that the test
/// does not depend on every field of `lux_usd::Material`): `/Red` then `/Green`.
fn materials() -> Vec<Material> {
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
            assert_eq!(m[0].diffuse, Diffuse::Color(DVec3::new(0.75, 0.25, 0.1875)));
            assert_eq!(
                m[1].diffuse,
                Diffuse::Color(DVec3::new(0.1875, 0.6875, 0.3125))
            );
            m
        })
        .clone()
}

/// Corner values of a triangle list from a per-vertex function.
fn corners<T: Copy>(tris: &[[u32; 3]], f: impl Fn(usize) -> T) -> Vec<[T; 3]> {
    tris.iter().map(|t| t.map(|i| f(i as usize))).collect()
}

/// Prototype 0: a bent-normal quad (no material) and a tetrahedron (material 0).
fn quad_mesh() -> Mesh {
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

fn tetra_mesh() -> Mesh {
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

fn triangle_mesh() -> Mesh {
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

fn world_quad(path: &str, y: f64, half: f64, double_sided: bool) -> Mesh {
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

fn trs(t: DVec3, r: DQuat, s: DVec3) -> DMat4 {
    DMat4::from_scale_rotation_translation(s, r, t)
}

/// The instanced test scene (no lights or camera).
fn instanced_scene() -> Scene {
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
struct Origin {
    instance: Option<usize>,
    mesh: usize,
    mirror: bool,
}

/// Reverses a triangle's corner order when `mirror` (the loader's winding flip).
fn swap<T: Copy>(c: [T; 3], mirror: bool) -> [T; 3] {
    if mirror { [c[0], c[2], c[1]] } else { c }
}

/// The scene with every instance flattened into world meshes, and per flattened mesh where it
/// came from.
fn flatten(s: &Scene) -> (Scene, Vec<Origin>) {
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
struct Brute {
    /// Closest front-or-double-sided hit: (t, mesh, tri).
    closest: Option<(f64, usize, usize)>,
    /// Closest hit, either side.
    nearest: Option<(f64, usize, usize)>,
    /// Whether `f32` rounding cannot change any answer for this ray.
    robust: bool,
}

fn brute(s: &Scene, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Brute {
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
fn rays(s: &Scene, n: usize, seed: u64) -> Vec<(DVec3, DVec3, f64)> {
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
fn as_flat(h: &Hit, origin: &[Origin]) -> Hit {
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

#[test]
fn instanced_queries_equal_flattened_queries() {
    let s = instanced_scene();
    let (f, origin) = flatten(&s);
    let gi = Geometry::new(&s);
    let gf = Geometry::new(&f);
    let (si, sf) = (Materials::new(&s).unwrap(), Materials::new(&f).unwrap());
    // Storage: world triangles plus each prototype once; drawn: every instance's.
    let world_tris = 2 + 2;
    let proto_tris = [2 + 4, 1];
    assert_eq!(gi.instance_count(), 8);
    assert_eq!(
        gi.triangle_count(),
        world_tris + proto_tris[0] + proto_tris[1]
    );
    assert_eq!(
        gf.triangle_count(),
        world_tris + 6 * proto_tris[0] + 2 * proto_tris[1]
    );
    assert_eq!(gi.drawn_triangle_count(), gf.triangle_count() as u64);
    assert_eq!(gf.instance_count(), 0);
    // Bounds: the flattened scene's exact box lies inside the instanced one (each instance
    // contributes its prototype's box mapped by its transform); here the floor decides x and z
    // exactly, and the instances' boxes are at most a few tenths larger in y.
    let (li, hi) = gi.world_bounds().unwrap();
    let (lf, hf) = gf.world_bounds().unwrap();
    assert!(
        li.cmple(lf).all() && hi.cmpge(hf).all(),
        "{li} {hi} vs {lf} {hf}"
    );
    assert_eq!((li.x, li.z, hi.x, hi.z), (lf.x, lf.z, hf.x, hf.z));
    assert!(
        lf.y - li.y < 0.5 && hi.y - hf.y < 0.5,
        "{li} {hi} vs {lf} {hf}"
    );
    let (mut robust, mut hits, mut instanced, mut mirrored, mut occluded) = (0, 0, 0, 0, 0);
    let mut worst_occluder_error = 0.0f64;
    let mut shading_error = 0.0f64;
    let all = rays(&s, 6000, 11);
    for &(o, d, tmax) in &all {
        let b = brute(&f, o, d, 0.0, tmax);
        if !b.robust {
            continue;
        }
        robust += 1;
        let hi = gi.intersect(&s, o, d, 0.0, tmax);
        let hf = gf.intersect(&f, o, d, 0.0, tmax);
        assert_eq!(
            hf.map(|h| (h.mesh, h.tri)),
            b.closest.map(|c| (c.1, c.2)),
            "flattened vs brute force, ray {o} {d} {tmax}"
        );
        match (hi, hf) {
            (None, None) => {}
            (Some(hi), Some(hf)) => {
                hits += 1;
                if let Some(ii) = hi.instance {
                    instanced += 1;
                    mirrored +=
                        usize::from(DMat3::from_mat4(s.instances[ii].to_world).determinant() < 0.0);
                    assert!(hi.offset >= hf.offset);
                }
                // Bit-identical after mapping mesh index and corner order.
                assert_eq!(as_flat(&hi, &origin), hf, "ray {o} {d} {tmax}");
                // Shading: the same point, facing normal, shading normal and albedo (the
                // instance's material where the prototype mesh has none, else the mesh's;
                // displayColor otherwise), the same bits — or, for a mirroring instance, whose
                // corner values (normals, colours) are summed in the other order, within a few
                // f64 ulps.
                let (pi, pf) = (si.at(&s, &hi, d), sf.at(&f, &hf, d));
                assert_eq!((pi.p, pi.ng, pi.offset), (pf.p, pf.ng, hi.offset));
                let mirror = hi.instance.is_some_and(|ii| {
                    DMat3::from_mat4(s.instances[ii].to_world).determinant() < 0.0
                });
                if mirror {
                    let e = (pi.ns - pf.ns)
                        .length()
                        .max((albedo(&pi) - albedo(&pf)).length());
                    shading_error = shading_error.max(e);
                    assert!(e < 1e-15, "{e}");
                } else {
                    assert_eq!((pi.ns, albedo(&pi)), (pf.ns, albedo(&pf)));
                }
            }
            (a, b) => panic!("instanced {a:?} vs flattened {b:?}, ray {o} {d} {tmax}"),
        }
        let occ = gi.occluded(o, d, 0.0, tmax);
        assert_eq!(occ, gf.occluded(o, d, 0.0, tmax));
        assert_eq!(occ, b.nearest.is_some());
        occluded += usize::from(occ);
        let (ti, tf) = (
            gi.first_occluder(o, d, 0.0, tmax),
            gf.first_occluder(o, d, 0.0, tmax),
        );
        assert_eq!(ti.is_some(), tf.is_some());
        if let (Some(ti), Some(tf), Some((t, _, _))) = (ti, tf, b.nearest) {
            let tol = offset_scale(o + t * d);
            let err = (ti - t).abs().max((tf - t).abs());
            worst_occluder_error = worst_occluder_error.max(err / tol);
            assert!(err <= tol, "first_occluder {ti} / {tf} vs exact {t}");
        }
    }
    println!(
        "{} rays: {robust} robust, {hits} hits ({instanced} on instances, {mirrored} mirrored), \
         {occluded} occluded; worst first_occluder error {worst_occluder_error:.3} of the tolerance, \
         mirrored shading (normals, albedo) within {shading_error:e}",
        all.len()
    );
    // Non-robust rays are rare, and every kind of hit was exercised.
    assert!(robust as f64 >= 0.97 * all.len() as f64, "{robust}");
    assert!(instanced > 500 && mirrored > 150 && hits - instanced > 500);
}

#[test]
fn mirrored_instance_keeps_its_front_side() {
    // A single-sided quad facing +Y, mirrored in Y by its instance: its front now faces −Y
    // (the normal M⁻ᵀ·n), although the world-space winding of its vertices points +Y.
    let mut s = Scene::empty("mirror.usda");
    s.meshes.push(Mesh {
        prototype: Some(0),
        ..world_quad("/P/Q", 0.0, 1.0, false)
    });
    s.prototypes.push(Prototype {
        path: "/P".into(),
        meshes: vec![0],
    });
    s.instances.push(Instance {
        path: "/I".into(),
        prototype: 0,
        to_world: DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)),
        material: None,
    });
    let g = Geometry::new(&s);
    assert_eq!((g.triangle_count(), g.instance_count()), (2, 1));
    let (o, oi) = (DVec3::new(0.2, -3.0, 0.1), Some(0));
    let h = g.intersect(&s, o, DVec3::Y, 0.0, f64::INFINITY).unwrap();
    assert_eq!(
        (h.t, h.p, h.ng, h.back, h.instance),
        (3.0, DVec3::new(0.2, 0.0, 0.1), DVec3::NEG_Y, false, oi)
    );
    // From above it is its back: culled for closest hits, still an occluder.
    let above = DVec3::new(0.2, 3.0, 0.1);
    assert!(
        g.intersect(&s, above, DVec3::NEG_Y, 0.0, f64::INFINITY)
            .is_none()
    );
    assert!(g.occluded(above, DVec3::NEG_Y, 0.0, 5.0));
    let t = g.first_occluder(above, DVec3::NEG_Y, 0.0, 5.0).unwrap();
    assert!((t - 3.0).abs() < 1e-6, "{t}");
    assert!(!g.occluded(above, DVec3::NEG_Y, 0.0, 2.5));
    // Barycentrics are on the prototype triangle's own corners.
    let m = &s.meshes[0];
    let [a, b, c] =
        m.triangles[h.tri].map(|i| DVec3::new(1.0, -1.0, 1.0) * m.positions[i as usize]);
    let q = (1.0 - h.bary.x - h.bary.y) * a + h.bary.x * b + h.bary.y * c;
    assert!((q - h.p).length() < 1e-15);
}

#[test]
fn storage_grows_with_unique_geometry_not_instances() {
    // One prototype of a 100 × 100 grid (20 000 triangles) placed 10 000 times: flattened,
    // 2 × 10⁸ triangles (≥ 12 GB of f32 triangles alone); instanced, the grid once.
    let n = 100;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            positions.push(DVec3::new(x, 0.05 * (7.0 * x).sin() * (5.0 * z).cos(), z));
        }
    }
    let mut triangles = Vec::new();
    let v = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            triangles.push([v(i, j), v(i, j + 1), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i + 1, j)]);
        }
    }
    let mut s = Scene::empty("many.usda");
    s.meshes.push(Mesh {
        prototype: Some(0),
        ..Mesh::new("/P/Grid", positions, triangles)
    });
    s.prototypes.push(Prototype {
        path: "/P".into(),
        meshes: vec![0],
    });
    let side = 100;
    for k in 0..side * side {
        let (i, j) = ((k % side) as f64, (k / side) as f64);
        s.instances.push(Instance {
            path: format!("/I[{k}]"),
            prototype: 0,
            to_world: DMat4::from_scale_rotation_translation(
                DVec3::splat(0.8 + 0.001 * (k % 7) as f64),
                DQuat::from_rotation_y(0.01 * (k % 13) as f64),
                DVec3::new(2.0 * i, 0.0, 2.0 * j),
            ),
            material: None,
        });
    }
    let g = Geometry::new(&s);
    assert_eq!(g.triangle_count(), 2 * n * n);
    assert_eq!(g.instance_count(), side * side);
    assert_eq!(g.drawn_triangle_count(), (2 * n * n * side * side) as u64);
    // The grid's BVH (≈ 100 bytes per triangle) plus ≈ 250 bytes per instance.
    // Memory: the grid once (≈ 72 bytes per stored triangle: f32 triangle, provenance, BVH)
    // plus ≈ 230 bytes per instance (placement and top-level BVH share).
    let bytes = g.heap_bytes();
    let one = {
        let mut single = s.clone();
        single.instances.truncate(1);
        Geometry::new(&single).heap_bytes()
    };
    let per_instance = (bytes - one) as f64 / (side * side - 1) as f64;
    let per_triangle = one as f64 / (2 * n * n) as f64;
    println!(
        "{bytes} bytes: {per_triangle:.1} per stored triangle, {per_instance:.1} per instance"
    );
    assert!(per_triangle < 90.0 && per_instance < 260.0);
    // Rays straight down onto instance centres hit that instance at the grid's height.
    for k in [0usize, 1, 57, 4321, 9999] {
        let (i, j) = ((k % side) as f64, (k / side) as f64);
        let o = DVec3::new(2.0 * i + 0.013, 5.0, 2.0 * j + 0.007);
        let h = g
            .intersect(&s, o, DVec3::NEG_Y, 0.0, f64::INFINITY)
            .unwrap();
        assert_eq!(h.instance, Some(k));
        assert!(h.p.y.abs() < 0.05 && (h.t - (5.0 - h.p.y)).abs() < 1e-12);
    }
    let (lo, hi) = g.world_bounds().unwrap();
    assert!(
        lo.x < -0.39 && lo.x > -0.5 && hi.x > 198.39 && hi.x < 198.5,
        "{lo} {hi}"
    );
}

#[test]
fn instanced_surfaces_do_not_shadow_themselves() {
    // A prototype modelled far from its origin — an oblique quad around c ≈ (3000, −2500, 3500),
    // where f32 rounds coordinates by up to 1.2e-4 — placed back around the world origin. The
    // rounding of the quad's vertices and of the ray origin mapped into prototype space moves
    // points off the plane by ~1e-4, while the world clearance offset_scale(p) is only 3e-5:
    // Hit::offset (s · offset_scale(p')) must clear it.
    let c = DVec3::new(3000.0, -2500.0, 3500.0);
    let n = DVec3::new(0.4, 1.0, 0.7).normalize();
    let u = n.cross(DVec3::X).normalize();
    let v = n.cross(u);
    let mut s = Scene::empty("far.usda");
    s.meshes.push(Mesh {
        prototype: Some(0),
        ..Mesh::new(
            "/P/Q",
            vec![c - u - v, c + u - v, c + u + v, c - u + v],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    });
    s.prototypes.push(Prototype {
        path: "/P".into(),
        meshes: vec![0],
    });
    let rot = DQuat::from_axis_angle(DVec3::new(1.0, -0.5, 0.2).normalize(), 0.4);
    s.instances.push(Instance {
        path: "/I".into(),
        prototype: 0,
        // p_w = R·(p' − c): world coordinates within 1.5 of the origin.
        to_world: DMat4::from_quat(rot) * DMat4::from_translation(-c),
        material: None,
    });
    let g = Geometry::new(&s);
    let to_world = DAffine3::from_mat4(s.instances[0].to_world);
    let mut rng = SplitMix64::new(3);
    let (mut tested, mut naive_self_hits) = (0, 0);
    for _ in 0..2000 {
        let [a, b] = rng.next_2d();
        let target = to_world.transform_point3(c + (1.8 * a - 0.9) * u + (1.8 * b - 0.9) * v);
        let nw = rot * n;
        let o = target + 3.0 * nw + DVec3::new(0.3 * a, 0.1, -0.2 * b);
        let d = (target - o).normalize();
        let Some(h) = g.intersect(&s, o, d, 0.0, f64::INFINITY) else {
            continue;
        };
        assert_eq!(h.instance, Some(0));
        assert!(h.offset > offset_scale(h.p));
        tested += 1;
        for w in [h.ng, (h.ng + 0.9 * d.cross(h.ng)).normalize(), -d] {
            assert!(
                !g.occluded(h.p + h.ng * h.offset, w, 0.0, f64::INFINITY),
                "self-shadow at {}",
                h.p
            );
            naive_self_hits +=
                usize::from(g.occluded(h.p + h.ng * offset_scale(h.p), w, 0.0, f64::INFINITY));
        }
    }
    println!(
        "{tested} hits; the world clearance alone would self-shadow {naive_self_hits} of {} rays",
        3 * tested
    );
    assert!(tested > 1900, "{tested}");
    // The test is sharp: without the prototype-space term rays would re-hit their surface.
    assert!(naive_self_hits > 100, "{naive_self_hits}");
}

fn render_scene(mut s: Scene) -> Scene {
    // Camera at `eye` looking at `target` (camera looks down its −Z, +Y up).
    let (eye, target) = (DVec3::new(1.0, 5.0, 11.0), DVec3::new(0.0, 0.5, 0.0));
    let back = (eye - target).normalize();
    let right = DVec3::Y.cross(back).normalize();
    let up = back.cross(right);
    s.cameras.push(Camera::with_defaults(
        "/Cam",
        DMat4::from_cols(
            right.extend(0.0),
            up.extend(0.0),
            back.extend(0.0),
            eye.extend(1.0),
        ),
    ));
    let mut key = Light::with_defaults(
        "/Key",
        LightShape::Sphere { radius: 0.4 },
        DMat4::from_translation(DVec3::new(2.5, 5.0, 3.0)),
    );
    key.params.intensity = 60.0;
    s.lights.push(key);
    // A ShadowAPI light whose shadows are tinted by distance: exercises first_occluder.
    let mut tinted = Light::with_defaults(
        "/Tinted",
        LightShape::Sphere { radius: 0.2 },
        DMat4::from_translation(DVec3::new(-3.0, 4.0, 1.0)),
    );
    tinted.params.intensity = 30.0;
    tinted.shadow.applied = true;
    tinted.shadow.color = DVec3::new(0.3, 0.0, 0.1);
    tinted.shadow.distance = 2.0;
    tinted.shadow.falloff = 1.0;
    s.lights.push(tinted);
    let mut sun = Light::with_defaults(
        "/Sun",
        LightShape::Distant { angle_deg: 2.0 },
        DMat4::from_rotation_x(-1.0),
    );
    sun.params.intensity = 1.5;
    s.lights.push(sun);
    // A world-space mesh light (the shelf's underside glows downwards): MeshLightAPI next to
    // instances.
    let mut glow = world_quad("/Glow", 3.0, 0.6, false);
    glow.triangles = glow.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let local: Vec<[DVec3; 3]> = glow
        .triangles
        .iter()
        .map(|t| t.map(|i| glow.positions[i as usize]))
        .collect();
    let mut ml = Light::with_defaults(
        "/Glow",
        LightShape::Mesh { triangles: local },
        DMat4::IDENTITY,
    );
    ml.params.intensity = 3.0;
    glow.light = Some(s.lights.len());
    s.lights.push(ml);
    s.meshes.push(glow);
    s
}

fn render(s: &Scene, threads: usize) -> Vec<[f32; 4]> {
    let mut o = RenderOptions::new(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::CommandLine,
    });
    o.spp = 8;
    o.resolution = Some([80, 60]);
    let r = Renderer::new(s, o).expect("scene prepares");
    assert!(r.lights().warnings.is_empty(), "{:?}", r.lights().warnings);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let (img, stats) = pool.install(|| r.render(&|_| {}));
    assert_eq!(stats.non_finite_samples, 0);
    img.pixels
}

/// Renders `s` and its flattened copy: (pixels that differ, worst relative difference).
fn render_difference(s: &Scene) -> (usize, f64) {
    let (f, _) = flatten(s);
    let a = render(s, 2);
    let b = render(&f, 2);
    let covered = a.iter().filter(|p| p[3] > 0.0).count();
    let lit = a.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
    assert!(
        covered > a.len() / 2 && lit > a.len() / 2,
        "{covered} {lit}"
    );
    let (mut differ, mut worst) = (0, 0.0f64);
    for (p, q) in a.iter().zip(&b) {
        differ += usize::from(p != q);
        for k in 0..4 {
            let e = (p[k] as f64 - q[k] as f64).abs() / (q[k] as f64).abs().max(1e-3);
            worst = worst.max(e);
        }
    }
    println!(
        "{differ} of {} pixels differ; worst relative difference {worst:e}",
        a.len()
    );
    (differ, worst)
}

#[test]
fn instanced_render_equals_flattened_render() {
    let s = render_scene(instanced_scene());
    // Determinism: the same bits for any thread count.
    assert_eq!(render(&s, 2), render(&s, 1));
    // Without mirroring instances and without the ShadowAPI falloff (which reads the f32
    // first-occluder distance), every hit, normal, albedo and light sample is the same f64
    // value as in the flattened scene (see the module doc), and so is every pixel. (The
    // instances' larger ray clearance moves secondary ray origins, which changes no
    // visibility here and no emission: the lights' emission does not depend on the point.)
    let mut exact = s.clone();
    exact
        .instances
        .retain(|i| DMat3::from_mat4(i.to_world).determinant() > 0.0);
    assert_eq!(exact.instances.len(), 5);
    let tinted = exact
        .lights
        .iter_mut()
        .find(|l| l.path == "/Tinted")
        .unwrap();
    tinted.shadow.color = DVec3::ZERO;
    tinted.shadow.distance = -1.0;
    assert_eq!(render_difference(&exact), (0, 0.0));
    // The full scene differs by rounding only:
    // - the ShadowAPI falloff of /Tinted reads first_occluder's f32 distance, which for an
    //   instance is computed in prototype space: the same distance up to f32 rounding
    //   (~1e-7 relative), so its shadow strength differs at that level;
    // - a mirroring instance interpolates its corner normals, colours and uvs in the
    //   prototype's corner order (b0 = 1 − b1 − b2 and the sum in that order), flattening in
    //   the reversed order: the same up to f64 rounding.
    // Pixels (f32) therefore differ by at most a few ulps (2⁻²³ ≈ 1.2e-7 relative).
    let (_, worst) = render_difference(&s);
    assert!(worst < 1e-6, "{worst}");
}
