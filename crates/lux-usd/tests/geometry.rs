//! Geometry, materials, cameras and render settings of `roundtrip.usda`, and inherited
//! visibility / purpose of `imageable.usda`.

use glam::{DVec2, DVec3, DVec4};
use lux_usd::{Input, Mesh, Projection, Scene, load_stage};
use std::path::PathBuf;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

fn roundtrip(frame: f64) -> Scene {
    load_stage(scenes().join("roundtrip.usda"), frame).unwrap()
}

fn mesh<'a>(s: &'a Scene, path: &str) -> &'a Mesh {
    s.meshes
        .iter()
        .find(|m| m.path == path)
        .unwrap_or_else(|| panic!("no mesh {path}"))
}

fn bounds(m: &Mesh) -> (DVec3, DVec3) {
    m.positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

#[track_caller]
fn assert_bounds(m: &Mesh, centre: DVec3, half: DVec3) {
    let (lo, hi) = bounds(m);
    let tol = 1e-9;
    assert!(
        (lo - (centre - half)).abs().max_element() < tol
            && (hi - (centre + half)).abs().max_element() < tol,
        "{}: bounds {lo} .. {hi}, want {} .. {}",
        m.path,
        centre - half,
        centre + half
    );
}

/// Front-side normal of a triangle (`(b − a) × (c − a)`).
fn face_normal(m: &Mesh, t: usize) -> DVec3 {
    let [a, b, c] = m.triangles[t].map(|k| m.positions[k as usize]);
    (b - a).cross(c - a).normalize()
}

#[test]
fn mesh_triangulation_orientation_and_primvars() {
    let s = roundtrip(1.0);
    let floor = mesh(&s, "/World/Floor");
    // A quad and a triangle → three triangles; leftHanded flips the winding so the front
    // faces −Z (the authored normals agree).
    assert_eq!(floor.triangles, vec![[0, 2, 1], [0, 3, 2], [1, 2, 4]]);
    for t in 0..2 {
        assert!((face_normal(floor, t) - DVec3::NEG_Z).length() < 1e-12);
    }
    assert!(floor.double_sided);
    // faceVarying normals through primvars:normals:indices [0,0,0,0,1,1,1].
    let n = floor.normals.as_ref().unwrap();
    let tilted = DVec3::new(0.0, 0.6, -0.8);
    assert_eq!(n.len(), 3);
    for c in &n[0..2] {
        assert_eq!(*c, [DVec3::NEG_Z; 3]);
    }
    for v in n[2] {
        assert!((v - tilted).length() < 1e-6, "{v}");
    }
    // uniform displayColor: face 0 red, face 1 green.
    let c = floor.colors.as_ref().unwrap();
    assert_eq!(c[0], [DVec3::X; 3]);
    assert_eq!(c[1], [DVec3::X; 3]);
    assert_eq!(c[2], [DVec3::Y; 3]);
    // vertex-interpolated st (named by the material's primvar reader: "uv"), per corner in
    // triangle order.
    let uv = floor.uvs.as_ref().unwrap();
    assert_eq!(
        uv[0],
        [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 0.0)
        ]
    );
    assert_eq!(
        uv[2],
        [
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(2.0, 0.5)
        ]
    );
    // Time-sampled points: z goes 0 → 1 over frames 1 → 4.
    let later = roundtrip(2.5);
    let z: Vec<f64> = mesh(&later, "/World/Floor")
        .positions
        .iter()
        .map(|p| p.z)
        .collect();
    assert_eq!(z, vec![0.5; 5]);
}

#[test]
fn implicit_gprims_are_tessellated_with_their_sizes_and_axes() {
    let s = roundtrip(1.0);
    let c = DVec3::new(0.0, 0.0, 3.0); // /World/Props translate
    assert_bounds(mesh(&s, "/World/Props/Ball"), c, DVec3::splat(0.5));
    assert_bounds(mesh(&s, "/World/Props/Box"), c, DVec3::splat(0.375));
    // Cylinder along X: height 1.5, radius 0.25.
    assert_bounds(
        mesh(&s, "/World/Props/Can"),
        c,
        DVec3::new(0.75, 0.25, 0.25),
    );
    // Cone along Y: height 1, radius 0.5.
    assert_bounds(mesh(&s, "/World/Props/Cone"), c, DVec3::new(0.5, 0.5, 0.5));
    // Capsule along Z: cylinder part 0.5 plus two caps of radius 0.2.
    assert_bounds(mesh(&s, "/World/Props/Pill"), c, DVec3::new(0.2, 0.2, 0.45));
    // Plane with axis X: width along Z, length along Y, double-sided by default.
    let card = mesh(&s, "/World/Props/Card");
    assert_bounds(card, c, DVec3::new(0.0, 1.5, 1.0));
    assert!(card.double_sided, "UsdGeomPlane is double-sided by default");
    assert!(face_normal(card, 0).x > 0.999);
    assert!(!mesh(&s, "/World/Props/Ball").double_sided);
    // Smooth shading normals on the sphere are radial; the constant displayColor applies.
    let ball = mesh(&s, "/World/Props/Ball");
    for (tri, n) in ball.triangles.iter().zip(ball.normals.as_ref().unwrap()) {
        for (k, v) in tri.iter().zip(n) {
            let radial = (ball.positions[*k as usize] - c).normalize();
            assert!(radial.dot(*v) > 0.99);
        }
    }
    let bx = mesh(&s, "/World/Props/Box");
    let grey = DVec3::new(0.2f32.into(), 0.4f32.into(), 0.6f32.into());
    assert!(bx.colors.as_ref().unwrap().iter().all(|c| *c == [grey; 3]));
}

#[test]
fn purpose_and_visibility_in_the_roundtrip_scene() {
    let s = roundtrip(1.0);
    let drawn: Vec<&str> = s.meshes.iter().map(|m| m.path.as_str()).collect();
    assert!(drawn.contains(&"/World/Props/RenderBall"));
    for hidden in ["ProxyBall", "GuideBall", "HiddenBall"] {
        assert!(
            !drawn.contains(&format!("/World/Props/{hidden}").as_str()),
            "{hidden} drawn"
        );
    }
}

#[test]
fn inherited_visibility_and_purpose() {
    let s = load_stage(scenes().join("imageable.usda"), 1.0).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let mut drawn: Vec<&str> = s.meshes.iter().map(|m| m.path.as_str()).collect();
    drawn.sort_unstable();
    assert_eq!(
        drawn,
        [
            "/ProxyGroup/OwnRender",
            "/RenderGroup/NoPurpose",
            "/Shown/Default",
            "/Shown/Render",
        ]
    );
    // A light under an invisible ancestor is not loaded either.
    assert!(s.lights.is_empty());
}

#[test]
fn materials_value_and_texture() {
    let s = roundtrip(1.0);
    let floor = mesh(&s, "/World/Floor");
    let m = &s.materials[floor.material.unwrap()];
    assert_eq!(m.path, "/World/Looks/Textured");
    let Input::Texture(t) = &m.diffuse else {
        panic!("{:?}", m.diffuse)
    };
    assert_eq!(t.shader, "/World/Looks/Textured/Tex");
    assert_eq!(t.file.as_ref().unwrap().authored, "assets/grid.png");
    // the primvar name reaches the reader through a Material interface input
    assert_eq!(t.st_primvar, "uv");
    assert_eq!(t.output, "rgb");
    assert_eq!(
        (t.wrap_s, t.wrap_t),
        (lux_usd::Wrap::Repeat, lux_usd::Wrap::Clamp)
    );
    assert_eq!(t.source_color_space, lux_usd::SourceColorSpace::Srgb);
    assert_eq!(t.scale, DVec4::new(2.0, 2.0, 2.0, 1.0));
    assert_eq!(t.bias, DVec4::new(0.1f32.into(), 0.0, 0.0, 0.0));
    assert_eq!(t.fallback, DVec4::new(0.0, 0.0, 0.0, 1.0));
    assert!(!t.fallback_authored);
    // The binding on /World/Props is inherited by every gprim under it.
    let ball = mesh(&s, "/World/Props/Ball");
    let red = &s.materials[ball.material.unwrap()];
    assert_eq!(red.path, "/World/Looks/Red");
    assert_eq!(
        red.diffuse,
        Input::Value(DVec3::new(0.8f32.into(), 0.1f32.into(), 0.05f32.into()))
    );
    assert_eq!(red.roughness, Input::Value(0.4f32.into()));
    assert!(red.other_inputs.is_empty(), "{:?}", red.other_inputs);
    assert_eq!(mesh(&s, "/World/Props/Card").material, ball.material);
    assert_eq!(s.materials.len(), 2, "each material read once");
}

#[test]
fn camera_render_settings_and_products() {
    let s = roundtrip(1.0);
    let cam = s.render_camera().unwrap();
    assert_eq!(cam.path, "/World/Cam");
    assert_eq!(cam.projection, Projection::Perspective);
    assert_eq!(cam.focal_length, 35.0);
    assert_eq!(
        (cam.horizontal_aperture, cam.vertical_aperture),
        (36.0, 24.0)
    );
    assert_eq!(
        (cam.horizontal_aperture_offset, cam.vertical_aperture_offset),
        (1.5, -0.5)
    );
    assert_eq!(cam.clipping_range, DVec2::new(0.5, 5000.0));
    assert_eq!(cam.f_stop, f64::from(2.8f32));
    assert_eq!(cam.focus_distance, 12.0);
    assert_eq!(
        cam.camera_to_world.transform_point3(DVec3::ZERO),
        DVec3::new(0.0, -10.0, 2.0)
    );
    // focalLength 35 → 50 over frames 1 → 4
    assert_eq!(roundtrip(2.0).cameras[0].focal_length, 40.0);
    let rs = &s.render_settings[0];
    assert_eq!(rs.path, "/World/Render/Settings");
    assert_eq!(rs.base.camera.as_deref(), Some("/World/Cam"));
    assert_eq!(rs.resolution(), [640, 360]);
    assert_eq!(rs.pixel_aspect_ratio(), 2.0);
    assert_eq!(rs.data_window_ndc(), DVec4::new(0.0, 0.125, 1.0, 0.875));
    assert_eq!(rs.included_purposes, ["default", "render"]);
    assert_eq!(rs.conformance_profile.as_deref(), Some("hdembree"));
    let p = &rs.products[0];
    assert_eq!(p.path, "/World/Render/Product");
    assert_eq!(p.product_name.as_deref(), Some("out.exr"));
    assert_eq!(p.base.resolution, Some([320, 180]));
    assert_eq!(p.base.camera.as_deref(), Some("/World/Cam"));
    assert_eq!(p.base.pixel_aspect_ratio, None);
}

#[test]
fn camera_schema_defaults() {
    let s = load_stage(scenes().join("xforms.usda"), 1.0).unwrap();
    let c = &s.cameras[0];
    assert_eq!(c.projection, Projection::Perspective);
    assert_eq!(c.focal_length, 50.0);
    assert_eq!(c.horizontal_aperture, 20.955);
    assert_eq!(c.vertical_aperture, 15.2908);
    assert_eq!(
        (c.horizontal_aperture_offset, c.vertical_aperture_offset),
        (0.0, 0.0)
    );
    assert_eq!(c.clipping_range, DVec2::new(1.0, 1_000_000.0));
    assert_eq!((c.f_stop, c.focus_distance), (0.0, 0.0));
    assert!(s.render_settings.is_empty());
}

#[test]
fn normals_interpolation_and_precedence() {
    use lux_usd::{LoadOptions, load_usda_str};
    // `normals` defaults to vertex interpolation; `primvars:normals` (constant by default)
    // wins over it when both are authored; a right-handed quad keeps its winding.
    let quad = |extra: &str| {
        format!(
            "#usda 1.0\ndef Mesh \"Q\"\n{{\n    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n{extra}}}\n"
        )
    };
    let s = load_usda_str(
        &quad("    normal3f[] normals = [(0, 0, 1), (1, 0, 0), (0, 1, 0), (0, 0, 1)]\n"),
        1.0,
        &LoadOptions::default(),
    )
    .unwrap();
    let m = &s.meshes[0];
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!((face_normal(m, 0) - DVec3::Z).length() < 1e-12);
    let n = m.normals.as_ref().unwrap();
    assert_eq!(n[0], [DVec3::Z, DVec3::X, DVec3::Y]);
    assert_eq!(n[1], [DVec3::Z, DVec3::Y, DVec3::Z]);
    let s = load_usda_str(
        &quad(
            "    normal3f[] normals = [(0, 0, 1), (1, 0, 0), (0, 1, 0), (0, 0, 1)]\n    normal3f[] primvars:normals = [(0, 0, 2)]\n",
        ),
        1.0,
        &LoadOptions::default(),
    )
    .unwrap();
    // constant, normalised
    assert!(
        s.meshes[0]
            .normals
            .as_ref()
            .unwrap()
            .iter()
            .all(|c| *c == [DVec3::Z; 3])
    );
    // a primvar with too few values for its interpolation is dropped with a warning
    let s = load_usda_str(
        &quad("    color3f[] primvars:displayColor = [(1, 0, 0)] (\n        interpolation = \"vertex\"\n    )\n"),
        1.0,
        &LoadOptions::default(),
    )
    .unwrap();
    assert!(s.meshes[0].colors.is_none());
    assert_eq!(s.warnings[0].kind, lux_usd::WarningKind::InvalidGeometry);
}
