//! Instanced geometry queries against the same geometry flattened into world-space meshes
//! (the scene and what must agree: `instanced/mod.rs`): hits, shadows, shading, storage,
//! self-shadowing.

mod instanced;

use glam::{DAffine3, DMat3, DMat4, DQuat, DVec3};
use instanced::*;
use lux_render::geometry::{Geometry, offset_scale};
use lux_render::material::Materials;
use lux_render::settings::SurfaceModel;
use lux_sample::SplitMix64;
use lux_usd::{Instance, Mesh, Prototype, Scene};

#[test]
fn instanced_queries_equal_flattened_queries() {
    let s = instanced_scene();
    let (f, origin) = flatten(&s);
    let gi = Geometry::new(&s);
    let gf = Geometry::new(&f);
    let lambert = |s: &Scene| Materials::with_policy(s, false, SurfaceModel::Lambert).unwrap();
    let (si, sf) = (lambert(&s), lambert(&f));
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
