//! BasisCurves, NurbsCurves and Points drawn as triangles: closed forms on small inline stages,
//! bad input, and the real OpenUSD test stages against usd-core's bounds.

use glam::DVec3;
use lux_usd::curves::TUBE_SIDES;
use lux_usd::{Gprim, LoadOptions, Mesh, Scene, WarningKind, load_usda_str};

fn load(body: &str) -> Scene {
    load_usda_str(
        &format!("#usda 1.0\n{body}\n"),
        1.0,
        &LoadOptions::default(),
    )
    .unwrap()
}

fn mesh<'a>(s: &'a Scene, path: &str) -> &'a Mesh {
    s.meshes
        .iter()
        .find(|m| m.path == path)
        .unwrap_or_else(|| panic!("no mesh {path}: {:#?}", s.warnings))
}

fn bounds<'a>(points: impl IntoIterator<Item = &'a DVec3>) -> (DVec3, DVec3) {
    points.into_iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// The centres of a tube's rings: its vertices are rings of `TUBE_SIDES[0]` vertices, one ring
/// per sample along the curve, in order (the caps reuse the end rings); the centroid of a
/// regular (or mitred, symmetric) ring is its sample on the curve.
fn ring_centres(m: &Mesh) -> Vec<DVec3> {
    let sides = TUBE_SIDES[0];
    assert_eq!(m.positions.len() % sides, 0);
    m.positions
        .chunks(sides)
        .map(|r| r.iter().sum::<DVec3>() / sides as f64)
        .collect()
}

/// Smallest distance from `p` to the curve `f` over `t ∈ [0, 1]`, and the `t` where it is
/// reached (dense search, then golden-section refinement).
fn nearest(f: &dyn Fn(f64) -> DVec3, p: DVec3) -> (f64, f64) {
    let n = 2000;
    let mut best = 0;
    for k in 0..=n {
        if (f(k as f64 / n as f64) - p).length() < (f(best as f64 / n as f64) - p).length() {
            best = k;
        }
    }
    let (mut a, mut b) = (
        (best as f64 - 1.0).max(0.0) / n as f64,
        (best as f64 + 1.0).min(n as f64) / n as f64,
    );
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..100 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if (f(c) - p).length() < (f(d) - p).length() {
            b = d;
        } else {
            a = c;
        }
    }
    let t = 0.5 * (a + b);
    ((f(t) - p).length(), t)
}

fn bezier(p: [DVec3; 4]) -> impl Fn(f64) -> DVec3 {
    move |t| {
        let s = 1.0 - t;
        s * s * s * p[0] + 3.0 * t * s * s * p[1] + 3.0 * t * t * s * p[2] + t * t * t * p[3]
    }
}

fn bspline(p: [DVec3; 4]) -> impl Fn(f64) -> DVec3 {
    move |t| {
        let s = 1.0 - t;
        (s * s * s * p[0]
            + (3.0 * t.powi(3) - 6.0 * t * t + 4.0) * p[1]
            + (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) * p[2]
            + t.powi(3) * p[3])
            / 6.0
    }
}

fn catmull_rom(p: [DVec3; 4]) -> impl Fn(f64) -> DVec3 {
    move |t| {
        ((-t.powi(3) + 2.0 * t * t - t) * p[0]
            + (3.0 * t.powi(3) - 5.0 * t * t + 2.0) * p[1]
            + (-3.0 * t.powi(3) + 4.0 * t * t + t) * p[2]
            + (t.powi(3) - t * t) * p[3])
            / 2.0
    }
}

fn usda_points(p: &[DVec3]) -> String {
    p.iter()
        .map(|v| format!("({}, {}, {})", v.x, v.y, v.z))
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn linear_tube_has_the_width_and_ends_at_the_points() {
    let s = load(
        r#"def BasisCurves "C" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2]
    point3f[] points = [(1, 0, 0), (4, 0, 0)]
    float[] widths = [0.5] (interpolation = "constant")
}"#,
    );
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/C");
    assert_eq!(m.gprim, Gprim::BasisCurves);
    assert!(!m.double_sided);
    for p in &m.positions {
        assert!(((p.y * p.y + p.z * p.z).sqrt() - 0.25).abs() < 1e-15, "{p}");
    }
    let (lo, hi) = bounds(&m.positions);
    assert_eq!((lo.x, hi.x), (1.0, 4.0));
    // 12 sides, one segment: 24 side triangles and two 10-triangle caps, wound outward.
    assert_eq!(
        m.triangles.len(),
        2 * TUBE_SIDES[0] + 2 * (TUBE_SIDES[0] - 2)
    );
    for t in &m.triangles {
        let [a, b, c] = t.map(|k| m.positions[k as usize]);
        let n = (b - a).cross(c - a);
        let centre = (a + b + c) / 3.0;
        let outward = if centre.x == 1.0 || centre.x == 4.0 {
            DVec3::new(centre.x - 2.5, 0.0, 0.0)
        } else {
            DVec3::new(0.0, centre.y, centre.z)
        };
        assert!(n.dot(outward) > 0.0);
    }
    assert_eq!((s.gprims.curves, s.drawn.curves), (1, 1));
    assert_eq!(s.gprims.other_gprims(), 1);
}

#[test]
fn cubic_tube_axes_follow_the_closed_form_curves() {
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(3.0, 2.0, 1.0),
        DVec3::new(4.0, 0.0, 1.0),
        DVec3::new(6.0, -1.0, 0.0),
    ];
    let q = |i: usize| [p[i], p[i + 1], p[i + 2], p[i + 3]];
    type Curve = Box<dyn Fn(f64) -> DVec3>;
    let cases: [(&str, usize, Vec<Curve>); 3] = [
        ("bezier", 4, vec![Box::new(bezier(q(0)))]),
        (
            "bspline",
            5,
            vec![Box::new(bspline(q(0))), Box::new(bspline(q(1)))],
        ),
        (
            "catmullRom",
            5,
            vec![Box::new(catmull_rom(q(0))), Box::new(catmull_rom(q(1)))],
        ),
    ];
    for (basis, n, segments) in cases {
        let s = load(&format!(
            r#"def BasisCurves "C" {{
    uniform token basis = "{basis}"
    int[] curveVertexCounts = [{n}]
    point3f[] points = [{}]
    float[] widths = [0.1]
}}"#,
            usda_points(&p[..n])
        ));
        assert!(s.warnings.is_empty(), "{basis}: {:#?}", s.warnings);
        let centres = ring_centres(mesh(&s, "/C"));
        assert!(centres.len() > 10, "{basis}: {} rings", centres.len());
        // Every ring centre is on the curve; the first and last are its ends.
        for c in &centres {
            let d = segments
                .iter()
                .map(|f| nearest(f.as_ref(), *c).0)
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-12, "{basis}: {c} is {d} off the curve");
        }
        let first = segments[0](0.0);
        let last = segments[segments.len() - 1](1.0);
        assert!((centres[0] - first).length() < 1e-12, "{basis}");
        assert!(
            (centres[centres.len() - 1] - last).length() < 1e-12,
            "{basis}"
        );
        // The chords stay close to the curve: every pair of neighbours is near it midway.
        for w in centres.windows(2) {
            let mid = 0.5 * (w[0] + w[1]);
            let d = segments
                .iter()
                .map(|f| nearest(f.as_ref(), mid).0)
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-2, "{basis}: chord {d} off the curve");
        }
    }
}

#[test]
fn periodic_and_pinned_curves() {
    // A periodic linear square: 4 segments, a closed tube without caps (every edge shared
    // by two triangles), rings at the 4 corners.
    let s = load(
        r#"def BasisCurves "Square" {
    uniform token type = "linear"
    uniform token wrap = "periodic"
    int[] curveVertexCounts = [4]
    point3f[] points = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0)]
    float[] widths = [0.25]
}"#,
    );
    let m = mesh(&s, "/Square");
    assert_eq!(m.triangles.len(), 4 * 2 * TUBE_SIDES[0]);
    assert_eq!(ring_centres(m).len(), 4);
    let mut edges = std::collections::HashMap::new();
    for t in &m.triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    assert!(edges.keys().all(|&(a, b)| edges.get(&(b, a)) == Some(&1)));
    // Mitred corners: the tube keeps its radius around the sides meeting there (every ring
    // vertex is r from the axis line of a side).
    for p in &m.positions {
        let to_side = [p.y.abs(), (p.x - 2.0).abs(), (p.y - 2.0).abs(), p.x.abs()];
        let d = |k: usize| (to_side[k].powi(2) + p.z * p.z).sqrt();
        assert!((0..4).any(|k| (d(k) - 0.125).abs() < 1e-12), "{p}");
    }

    // A periodic bezier of 6 vertices: 2 segments, [0 1 2 3] and [3 4 5 0].
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(2.0, -1.0, 0.5),
        DVec3::new(1.0, -1.0, 0.5),
    ];
    let s = load(&format!(
        r#"def BasisCurves "Loop" {{
    uniform token wrap = "periodic"
    int[] curveVertexCounts = [6]
    point3f[] points = [{}]
    float[] widths = [0.05]
}}"#,
        usda_points(&p)
    ));
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/Loop");
    let centres = ring_centres(m);
    // Closed: quads only, one per ring.
    assert_eq!(m.triangles.len(), centres.len() * 2 * TUBE_SIDES[0]);
    let seg0 = bezier([p[0], p[1], p[2], p[3]]);
    let seg1 = bezier([p[3], p[4], p[5], p[0]]);
    let mut on = [0, 0];
    for c in &centres {
        let (d0, d1) = (nearest(&seg0, *c).0, nearest(&seg1, *c).0);
        assert!(d0.min(d1) < 1e-12, "{c}");
        on[usize::from(d1 < d0)] += 1;
    }
    assert!(on[0] > 3 && on[1] > 3, "{on:?}");

    // Pinned catmullRom and bspline pass through their first and last points.
    for basis in ["catmullRom", "bspline"] {
        let s = load(&format!(
            r#"def BasisCurves "Pinned" {{
    uniform token basis = "{basis}"
    uniform token wrap = "pinned"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 0, 1)]
    float[] widths = [0.05]
}}"#
        ));
        assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
        let c = ring_centres(mesh(&s, "/Pinned"));
        assert!(c[0].length() < 1e-15, "{basis}: {}", c[0]);
        assert!((c[c.len() - 1] - DVec3::new(2.0, 0.0, 1.0)).length() < 1e-15);
    }
}

/// Radius of the ring around centre `c`: the nearest of its vertices (mitring only stretches).
fn ring_radii(m: &Mesh) -> Vec<(DVec3, f64)> {
    m.positions
        .chunks(TUBE_SIDES[0])
        .map(|r| {
            let c = r.iter().sum::<DVec3>() / r.len() as f64;
            let rad = r
                .iter()
                .map(|v| (*v - c).length())
                .fold(f64::INFINITY, f64::min);
            (c, rad)
        })
        .collect()
}

#[test]
fn widths_interpolation() {
    // One bezier segment (a bent curve, so it is sampled inside): constant, varying (linear in
    // t between the segment's ends) and vertex (the bezier basis on the four widths).
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(3.0, 2.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
    ];
    let curve = bezier(p);
    let w = [0.125, 0.5, 0.25, 0.375];
    type Width = Box<dyn Fn(f64) -> f64>;
    let cases: [(&str, &str, Width); 3] = [
        ("[0.375]", "constant", Box::new(|_| 0.375)),
        ("[0.125, 0.375]", "varying", Box::new(|t| 0.125 + 0.25 * t)),
        (
            "[0.125, 0.5, 0.25, 0.375]",
            "vertex",
            Box::new(move |t| {
                let s = 1.0 - t;
                s * s * s * w[0]
                    + 3.0 * t * s * s * w[1]
                    + 3.0 * t * t * s * w[2]
                    + t * t * t * w[3]
            }),
        ),
    ];
    for (values, interp, width) in cases {
        let s = load(&format!(
            r#"def BasisCurves "C" {{
    int[] curveVertexCounts = [4]
    point3f[] points = [{}]
    float[] widths = {values} (interpolation = "{interp}")
}}"#,
            usda_points(&p)
        ));
        assert!(s.warnings.is_empty(), "{interp}: {:#?}", s.warnings);
        let rings = ring_radii(mesh(&s, "/C"));
        assert!(rings.len() > 5);
        for (c, r) in rings {
            let (_, t) = nearest(&curve, c);
            // Within 1e-4: the rings are mitred by ~0.1 % along the bend.
            assert!(
                (r - width(t) / 2.0).abs() < 1e-4 * width(t),
                "{interp}: t {t} radius {r}, want {}",
                width(t) / 2.0
            );
        }
    }
    // Linear curves: varying and vertex are both per vertex, linear along each segment.
    let s = load(
        r#"def BasisCurves "L" {
    uniform token type = "linear"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (3, 0, 0)]
    float[] widths = [0.25, 0.5, 1.0] (interpolation = "varying")
}"#,
    );
    let r: Vec<f64> = ring_radii(mesh(&s, "/L")).iter().map(|x| x.1).collect();
    assert_eq!(r.len(), 3);
    for (got, want) in r.iter().zip([0.125, 0.25, 0.5]) {
        assert!((got - want).abs() < 1e-15, "{got} {want}");
    }
    // Unauthored widths: Hydra's fallback width 1.
    let s = load(
        r#"def BasisCurves "F" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2]
    point3f[] points = [(0, 0, 0), (1, 0, 0)]
}"#,
    );
    let (lo, hi) = bounds(&mesh(&s, "/F").positions);
    assert!((hi.y - 0.5).abs() < 1e-15 && (lo.y + 0.5).abs() < 1e-15);
}

#[test]
fn nurbs_circle_axis_is_exactly_round() {
    let r = 2.0;
    let s = load(&format!(
        r#"def NurbsCurves "Circle" {{
    int[] curveVertexCounts = [9]
    int[] order = [3]
    double[] knots = [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1]
    double[] pointWeights = [1, {h}, 1, {h}, 1, {h}, 1, {h}, 1]
    point3f[] points = [({r}, 0, 0), ({r}, {r}, 0), (0, {r}, 0), (-{r}, {r}, 0), (-{r}, 0, 0), (-{r}, -{r}, 0), (0, -{r}, 0), ({r}, -{r}, 0), ({r}, 0, 0)]
    float[] widths = [0.1]
    color3f[] primvars:displayColor = [(1, 0, 0)]
}}"#,
        h = std::f64::consts::FRAC_1_SQRT_2
    ));
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/Circle");
    assert_eq!(m.gprim, Gprim::NurbsCurves);
    let centres = ring_centres(m);
    assert!(centres.len() >= 40, "{}", centres.len());
    for c in &centres {
        assert!((c.length() - r).abs() < 1e-12 * r, "{c}");
        assert!(c.z.abs() < 1e-15);
    }
    // The curve ends where it starts: one seamless closed tube (no caps).
    assert_eq!(m.triangles.len(), centres.len() * 2 * TUBE_SIDES[0]);
    assert!(
        m.colors
            .as_ref()
            .unwrap()
            .iter()
            .flatten()
            .all(|c| *c == DVec3::X)
    );
    assert_eq!((s.gprims.curves, s.drawn.curves), (1, 1));
}

#[test]
fn points_are_spheres_of_their_width() {
    let s = load(
        r#"def Points "P" {
    point3f[] points = [(0, 0, 0), (3, 1, 0)]
    float[] widths = [0.5, 2] (interpolation = "vertex")
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 0, 1)] (interpolation = "vertex")
}"#,
    );
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/P");
    assert_eq!(m.gprim, Gprim::Points);
    assert!(!m.double_sided);
    let half = m.positions.len() / 2;
    for (i, p) in m.positions.iter().enumerate() {
        let (c, r) = if i < half {
            (DVec3::ZERO, 0.25)
        } else {
            (DVec3::new(3.0, 1.0, 0.0), 1.0)
        };
        assert!(((*p - c).length() - r).abs() < 1e-15, "{i} {p}");
    }
    let (lo, hi) = bounds(&m.positions);
    assert_eq!(
        (lo, hi),
        (DVec3::new(-0.25, -0.25, -1.0), DVec3::new(4.0, 2.0, 1.0))
    );
    let colors = m.colors.as_ref().unwrap();
    let t = m.triangles.len();
    assert!(colors[..t / 2].iter().flatten().all(|c| *c == DVec3::X));
    assert!(colors[t / 2..].iter().flatten().all(|c| *c == DVec3::Z));
    assert_eq!((s.gprims.points, s.drawn.points), (1, 1));
}

#[test]
fn ribbons_face_the_authored_normals() {
    let s = load(
        r#"def BasisCurves "R" {
    uniform token type = "linear"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 1, 0)]
    normal3f[] normals = [(0, 0, 1), (0, 0, 1), (0, 0, 1)] (interpolation = "vertex")
    float[] widths = [0.25] (interpolation = "constant")
}"#,
    );
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/R");
    assert!(m.double_sided);
    assert_eq!(m.triangles.len(), 4);
    for (t, n) in m.triangles.iter().zip(m.normals.as_ref().unwrap()) {
        let [a, b, c] = t.map(|k| m.positions[k as usize]);
        assert!(((b - a).cross(c - a).normalize() - DVec3::Z).length() < 1e-12);
        assert!(n.iter().all(|n| (*n - DVec3::Z).length() < 1e-12));
    }
    // Flat, and as wide as authored at the end points.
    assert!(m.positions.iter().all(|p| p.z == 0.0));
    assert_eq!((m.positions[0] - m.positions[1]).length(), 0.25);
}

#[test]
fn displaycolor_interpolations_on_curves() {
    // uniform: one colour per curve; vertex on a linear curve: linear along it.
    let s = load(
        r#"def BasisCurves "C" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 2, 0), (1, 2, 0)]
    float[] widths = [0.1]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0)] (interpolation = "uniform")
}
def BasisCurves "V" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2]
    point3f[] points = [(0, 0, 0), (1, 0, 0)]
    float[] widths = [0.1]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 0, 1)] (interpolation = "vertex")
}"#,
    );
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    let m = mesh(&s, "/C");
    let colors = m.colors.as_ref().unwrap();
    for (t, c) in m.triangles.iter().zip(colors) {
        for (k, c) in t.iter().zip(c) {
            let want = if m.positions[*k as usize].y < 1.0 {
                DVec3::X
            } else {
                DVec3::Y
            };
            assert_eq!(*c, want);
        }
    }
    let m = mesh(&s, "/V");
    for (t, c) in m.triangles.iter().zip(m.colors.as_ref().unwrap()) {
        for (k, c) in t.iter().zip(c) {
            let x = m.positions[*k as usize].x;
            assert!((*c - DVec3::new(1.0 - x, 0.0, x)).length() < 1e-15);
        }
    }
}

#[test]
fn material_and_instancing() {
    let s = load(
        r#"def Material "M" {
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S" {
        uniform token info:id = "UsdPreviewSurface"
        token outputs:surface
    }
}
class Xform "Proto" {
    def BasisCurves "Hair" (prepend apiSchemas = ["MaterialBindingAPI"]) {
        rel material:binding = </M>
        uniform token type = "linear"
        int[] curveVertexCounts = [2]
        point3f[] points = [(0, 0, 0), (0, 1, 0)]
        float[] widths = [0.1]
    }
    def Points "Dots" { point3f[] points = [(0, 0, 0)] }
}
def Xform "A" (instanceable = true references = </Proto>) {}
def Xform "B" (instanceable = true references = </Proto>) { double3 xformOp:translate = (5, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"] }"#,
    );
    assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
    // Counted per instance (as usd-core's traversal counts instance proxies), drawn once in
    // the prototype.
    assert_eq!((s.gprims.curves, s.gprims.points), (2, 2));
    assert_eq!((s.drawn.curves, s.drawn.points), (1, 1));
    assert_eq!(s.gprims.other_gprims(), 4);
    let hair: Vec<&Mesh> = s
        .meshes
        .iter()
        .filter(|m| m.path.ends_with("/Hair"))
        .collect();
    assert_eq!(hair.len(), 1);
    assert!(hair[0].prototype.is_some() && hair[0].material.is_some());
    assert_eq!(s.instances.len(), 2);
}

#[test]
fn bad_input_is_warned_and_never_panics() {
    let s = load(
        r#"def BasisCurves "Counts" {
    int[] curveVertexCounts = [4, 4]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]
}
def BasisCurves "Negative" {
    int[] curveVertexCounts = [-4]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]
}
def BasisCurves "Widths" {
    uniform token type = "linear"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 1, 0)]
    float[] widths = [-0.5, 0.2] (interpolation = "vertex")
}
def BasisCurves "NaN" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 2]
    point3f[] points = [(0, 0, 0), (nan, 0, 0), (0, 1, 0), (1, 1, 0)]
    float[] widths = [-0.5]
}
def BasisCurves "Basis" {
    uniform token basis = "hermite"
    uniform token wrap = "sideways"
    int[] curveVertexCounts = [4]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 1, 0), (3, 0, 0)]
}
def BasisCurves "Degenerate" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 1]
    point3f[] points = [(1, 1, 1), (1, 1, 1), (0, 0, 0)]
}
def BasisCurves "Colors" {
    uniform token type = "linear"
    int[] curveVertexCounts = [2]
    point3f[] points = [(0, 0, 0), (1, 0, 0)]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0), (0, 0, 1)] (interpolation = "vertex")
    int[] primvars:displayColor:indices = [0, 7]
}
def NurbsCurves "Knots" {
    int[] curveVertexCounts = [3]
    int[] order = [3]
    double[] knots = [0, 0, 1, 0, 1, 1]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 0, 0)]
}
def NurbsCurves "Order" {
    int[] curveVertexCounts = [3]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 0, 0)]
}
def NurbsCurves "Weights" {
    int[] curveVertexCounts = [3]
    int[] order = [3]
    double[] knots = [0, 0, 0, 1, 1, 1]
    double[] pointWeights = [1, 0, 1]
    double2[] ranges = [(0.5, 7)]
    point3f[] points = [(0, 0, 0), (1, 1, 0), (2, 0, 0)]
}
def Points "P" {
    point3f[] points = [(0, 0, 0), (inf, 0, 0), (1, 0, 0)]
    float[] widths = [1, 1, 0, 1]
    normal3f[] normals = [(0, 0, 1)]
}
def Points "Empty" {}"#,
    );
    let warned = |prim: &str, text: &str| {
        assert!(
            s.warnings
                .iter()
                .any(|w| w.prim == prim && w.message.contains(text)),
            "no warning on {prim} containing {text:?}: {:#?}",
            s.warnings
        );
    };
    warned("/Counts", "curveVertexCounts sum to 8");
    warned("/Negative", "negative count");
    warned("/Widths", "1 values are negative");
    warned("/Widths", "2 values for vertex interpolation (3 expected)");
    warned("/NaN", "curve 0 of 2: a point is not finite");
    warned("/NaN", "negative");
    warned("/Basis", "basis \"hermite\"");
    warned("/Basis", "wrap \"sideways\"");
    warned("/Degenerate", "zero length");
    warned("/Degenerate", "too few vertices");
    warned("/Colors", "an index is out of range");
    warned("/Knots", "knots are not finite and non-decreasing");
    warned("/Order", "order has 0 entries for 1 curves");
    warned("/Weights", "pointWeights");
    warned("/Weights", "range reaches outside");
    warned("/P", "1 of 3 points are not finite");
    warned("/P", "widths: 4 values for vertex interpolation");
    warned("/P", "normals");
    warned("/Empty", "no points");
    for w in &s.warnings {
        assert_ne!(w.kind, WarningKind::Composition, "{w}");
    }
    // What could be drawn is drawn: the widths fall back to 1, the finite curve of /NaN, the
    // bezier fallback of /Basis, the colours ignored, the weights ignored.
    for path in ["/Widths", "/NaN", "/Basis", "/Colors", "/Weights", "/P"] {
        mesh(&s, path);
    }
    for path in [
        "/Counts",
        "/Negative",
        "/Degenerate",
        "/Knots",
        "/Order",
        "/Empty",
    ] {
        assert!(s.meshes.iter().all(|m| m.path != path), "{path} drawn");
    }
    let w = mesh(&s, "/Widths");
    let (lo, hi) = bounds(&w.positions);
    assert_eq!((lo.y, hi.z), (-0.5, 0.5), "fallback width 1: {lo} {hi}");
    assert!(mesh(&s, "/Colors").colors.is_none());
    assert!(
        s.meshes
            .iter()
            .all(|m| m.positions.iter().all(|p| p.is_finite()))
    );
    assert_eq!(s.gprims.curves, 10);
    assert_eq!(s.gprims.points, 2);
    assert!(
        !s.warnings
            .iter()
            .any(|w| w.message.contains("not drawn (lux draws"))
    );
}

#[test]
fn a_budget_cuts_detail_with_a_warning() {
    // 40,000 bent bezier curves need 40,000 × (15 steps × 24 + 20) ≈ 15 M triangles at full
    // detail: drawn within the budget, with a warning saying so.
    let n = 40_000;
    let mut pts = String::new();
    for i in 0..n {
        let x = i as f64;
        pts.push_str(&format!(
            "({x}, 0, 0), ({x}, 1, 0), ({}, 1, 0), ({}, 0, 0), ",
            x + 0.5,
            x + 0.5
        ));
    }
    let s = load(&format!(
        r#"def BasisCurves "Fur" {{
    int[] curveVertexCounts = [{}]
    point3f[] points = [{pts}]
    float[] widths = [0.01]
}}"#,
        vec!["4"; n].join(", ")
    ));
    let m = mesh(&s, "/Fur");
    assert!(m.triangles.len() <= lux_usd::curves::TRIANGLE_BUDGET);
    assert!(m.triangles.len() > lux_usd::curves::TRIANGLE_BUDGET / 2);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.prim == "/Fur" && w.message.contains("past the budget")),
        "{:#?}",
        s.warnings
    );
}

/// usd-core 26.11's numbers for the curves and points of the OpenUSD test stages, from
/// `crates/lux-usd/tests/oracle/curves_bounds.py` (run it from the workspace root with
/// usd-core's Python): per prim (instance-proxy paths), the world bound usd-core's
/// `UsdGeom.BBoxCache` gives with extents computed by usd-core (`ComputeExtentFromPlugins`:
/// for curves the points' box padded by half the *largest* width, for points each point padded
/// by its own half width; the files' authored extents are stale and blocked), and for curves the
/// box of the segment ends (points the curve passes through by definition) and the box of the
/// exact tube (the schema's formulas at 400 parameters per segment, extreme of each circle
/// `C·e ± r·√(1 − (T·e)²)`) with its largest world radius.
struct Oracle {
    path: &'static str,
    bbox: [[f64; 3]; 2],
    curve: Option<OracleCurve>,
}

struct OracleCurve {
    ends: [[f64; 3]; 2],
    tube: [[f64; 3]; 2],
    rmax: f64,
}

const fn curve(
    path: &'static str,
    bbox: [[f64; 3]; 2],
    ends: [[f64; 3]; 2],
    tube: [[f64; 3]; 2],
    rmax: f64,
) -> Oracle {
    Oracle {
        path,
        bbox,
        curve: Some(OracleCurve { ends, tube, rmax }),
    }
}

const fn points(path: &'static str, bbox: [[f64; 3]; 2]) -> Oracle {
    Oracle {
        path,
        bbox,
        curve: None,
    }
}

const BASIC_DRAWING: [Oracle; 3] = [
    curve(
        "/BasisCurves/Tree/Trunk",
        [
            [321.2435302734375, -650.0104370117188, -75.34774780273438],
            [1868.0584716796875, 613.1294555664062, 1885.1573486328125],
        ],
        [
            [417.33099365234375, -553.9229736328125, 20.739700317382812],
            [1554.4349975585938, 517.0419921875, 1789.0699462890625],
        ],
        [
            [413.36724455605406, -558.6936357234997, 17.13587694905114],
            [1556.809730178433, 520.4059727665127, 1789.255883494427],
        ],
        96.08744812011719,
    ),
    curve(
        "/BasisCurves/Tree2/Trunk2",
        [
            [-1678.7564697265625, -650.0104370117188, -75.34774780273438],
            [-131.9415283203125, 613.1294555664062, 1885.1573486328125],
        ],
        [
            [-1582.6690063476562, -553.9229736328125, 20.739700317382812],
            [-445.56500244140625, 517.0419921875, 1789.0699462890625],
        ],
        [
            [-1586.6327554439458, -558.6936357234997, 17.13587694905114],
            [-443.1902698215669, 520.4059727665127, 1789.255883494427],
        ],
        96.08744812011719,
    ),
    curve(
        "/BasisCurves/Loop",
        [
            [
                -291.38186627905276,
                -210.51996340441895,
                -10.999999940395355,
            ],
            [267.5831252904663, 568.9470470936279, 10.999999940395355],
        ],
        [
            [-267.9200436103414, -153.06362400539905, 0.0],
            [243.17679947335816, 482.8013659508209, 0.0],
        ],
        [
            [
                -282.64346469972537,
                -195.43813896677213,
                -10.999999940395355,
            ],
            [254.96602304829514, 521.7244862194274, 10.999999940395355],
        ],
        10.999999940395355,
    ),
];

/// `instance.usda` (and `nestedInstance.usda` under `/NestedInstance`): one instance of
/// `/Parent`, whose curve and points are drawn from the prototype.
const INSTANCE: [Oracle; 3] = [
    curve(
        "/Curves/Loop",
        [
            [-7.440104961395264, -2.004999999701976, 2.4672200679779057],
            [-4.6452800035476685, -1.8950000002980218, 6.36455512046814],
        ],
        [
            [-7.322795848051706, -1.9499999999999995, 2.7545017649730053],
            [-4.767311632633209, -1.949999999999999, 4.911920314033827],
        ],
        [
            [-7.377765803672069, -2.004999999701976, 2.5426291901661395],
            [-4.708365514758524, -1.8950000002980223, 4.914659926978693],
        ],
        0.054999999701976776,
    ),
    points(
        "/Points/Points_Primvar",
        [
            [-3.5629239082336426, -3.8600741624832153, 2.4370760917663574],
            [-0.13992583751678467, -0.7483137845993042, 5.860074162483215],
        ],
    ),
    points(
        "/Points/Points_Uv",
        [
            [-3.5629239082336426, -3.8600741624832153, 6.437076091766357],
            [-0.13992583751678467, -0.7483137845993042, 9.860074162483215],
        ],
    ),
];

/// World boxes of the curves and points meshes, by (instance-proxy) path.
fn world_boxes(s: &Scene) -> std::collections::HashMap<String, (DVec3, DVec3)> {
    let mut out = std::collections::HashMap::new();
    for (i, m) in s.meshes.iter().enumerate() {
        if !matches!(
            m.gprim,
            Gprim::BasisCurves | Gprim::NurbsCurves | Gprim::Points
        ) {
            continue;
        }
        match m.prototype {
            None => {
                out.insert(m.path.clone(), bounds(&m.positions));
            }
            Some(p) => {
                for (k, inst) in s.instances.iter().enumerate() {
                    if inst.prototype == p {
                        let w: Vec<DVec3> = m
                            .positions
                            .iter()
                            .map(|q| inst.to_world.transform_point3(*q))
                            .collect();
                        out.insert(s.geometry_path(i, Some(k)).into_owned(), bounds(&w));
                    }
                }
            }
        }
    }
    out
}

fn realusd(rel: &str) -> Option<std::path::PathBuf> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv")
        .join(rel);
    if !p.exists() {
        // The published crate leaves the workspace's real-world stages out.
        eprintln!("{} is not here; skipped", p.display());
        return None;
    }
    Some(p)
}

fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// lux's box against usd-core's, for one prim.
///
/// - Points: the spheres' box equals usd-core's bound (every sphere has vertices at its poles
///   and on its equator on the axes) up to float rounding: usd-core computes extents in
///   `float`, lux in `f64` from the same `float` inputs (≤ 1e-6 of the box size).
/// - Curves: usd-core's bound is conservative (the control points' box padded by half the
///   largest width), so lux's box lies inside it, and contains the segment ends the curve must
///   pass through. Against the exact tube, each face is within `0.035·rmax + 1e-3·size`: the
///   12-sided rings are inscribed in the circle (at most `r·(1 − cos 15°) = 0.0341·r` inside
///   it along an axis), the chords within `FLATNESS` = 1e-3 of a span's control-polygon length
///   from the curve, the mitres stretch rings by ~0.1 % along bends.
fn check_against_usd_core(lux: (DVec3, DVec3), o: &Oracle, path: &str) {
    let (lo, hi) = lux;
    let (blo, bhi) = (v(o.bbox[0]), v(o.bbox[1]));
    let size = (bhi - blo).max_element();
    let eps = 1e-6 * size;
    match &o.curve {
        None => {
            assert!(
                (lo - blo).abs().max_element() < eps && (hi - bhi).abs().max_element() < eps,
                "{path}: lux {lo} .. {hi}, usd-core {blo} .. {bhi}"
            );
        }
        Some(c) => {
            assert!(
                lo.cmpge(blo - eps).all() && hi.cmple(bhi + eps).all(),
                "{path}: lux {lo} .. {hi} is not inside usd-core's {blo} .. {bhi}"
            );
            let (elo, ehi) = (v(c.ends[0]), v(c.ends[1]));
            assert!(
                lo.cmple(elo + eps).all() && hi.cmpge(ehi - eps).all(),
                "{path}: lux {lo} .. {hi} misses segment ends {elo} .. {ehi}"
            );
            let (tlo, thi) = (v(c.tube[0]), v(c.tube[1]));
            let tol = 0.035 * c.rmax + 1e-3 * size;
            let err = (lo - tlo).abs().max((hi - thi).abs()).max_element();
            eprintln!(
                "{path}: lux vs exact tube {err:.4} (tolerance {tol:.4}); usd-core's bound is \
                 {:.4} wider",
                (lo - blo).abs().max((hi - bhi).abs()).max_element()
            );
            assert!(
                err <= tol,
                "{path}: lux {lo} .. {hi}, exact tube {tlo} .. {thi}: {err} > {tol}"
            );
        }
    }
}

#[test]
fn openusd_test_stages_match_usd_core_bounds() {
    use lux_usd::{Time, load_stage_with};
    let not_drawn = |s: &Scene| {
        s.warnings
            .iter()
            .filter(|w| w.message.starts_with("not drawn"))
            .any(|w| {
                ["BasisCurves", "NurbsCurves", "Points"]
                    .iter()
                    .any(|t| w.message.contains(t))
            })
    };
    // Nothing about the curves and points is reported: they are drawn as authored.
    let quiet = |s: &Scene| {
        !s.warnings.iter().any(|w| {
            w.prim.contains("Curves") || w.prim.contains("Points") || w.prim.contains("Trunk")
        })
    };
    if let Some(f) = realusd("testUsdImagingGLBasicLighting/basicDrawing.usda") {
        let s = load_stage_with(&f, Time::Start, &LoadOptions::default()).unwrap();
        assert!(!not_drawn(&s) && quiet(&s), "{:#?}", s.warnings);
        assert_eq!((s.drawn.curves, s.drawn.points), (3, 0));
        assert_eq!((s.gprims.curves, s.gprims.other_gprims()), (3, 6));
        let boxes = world_boxes(&s);
        assert_eq!(boxes.len(), 3);
        for o in &BASIC_DRAWING {
            check_against_usd_core(boxes[o.path], o, o.path);
        }
    }
    for (file, root) in [
        ("testUsdImagingGLInstancing/instance.usda", "/Instance"),
        (
            "testUsdImagingGLInstancing/nestedInstance.usda",
            "/NestedInstance",
        ),
    ] {
        let Some(f) = realusd(file) else { continue };
        let s = load_stage_with(&f, Time::Start, &LoadOptions::default()).unwrap();
        assert!(!not_drawn(&s) && quiet(&s), "{file}: {:#?}", s.warnings);
        assert_eq!((s.drawn.curves, s.drawn.points), (1, 2), "{file}");
        assert_eq!((s.gprims.curves, s.gprims.points), (1, 2), "{file}");
        let boxes = world_boxes(&s);
        for o in &INSTANCE {
            let path = format!("{root}{}", o.path);
            let lux = *boxes
                .get(&path)
                .unwrap_or_else(|| panic!("{file}: no {path} in {:?}", boxes.keys()));
            check_against_usd_core(lux, o, &path);
        }
    }
}
