//! Light and shadow linking (LightAPI `collection:lightLink` / `collection:shadowLink`):
//! lux's resolution of `tests/data/scenes/linking.usda` against usd-core's membership, and
//! the linking of lights placed by native instances.

use lux_usd::{LoadOptions, Membership, Scene, WarningKind, load_stage, load_usda_str};
use std::path::PathBuf;

fn linking_scene() -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/linking.usda");
    load_stage(p, 1.0).unwrap()
}

/// The meshes of the stage (paths) a membership holds, in scene order.
fn members(scene: &Scene, m: &Membership) -> Vec<String> {
    scene
        .meshes
        .iter()
        .filter(|mesh| m.contains(&mesh.path))
        .map(|mesh| mesh.path.clone())
        .collect()
}

const ALL: &[&str] = &[
    "/World/A/m1",
    "/World/A/m2",
    "/World/A/Sub/m3",
    "/World/B/m4",
    "/World/B/m5",
    "/World/m6",
];

/// usd-core 26.11's members of each light's collections, printed by
///
/// ```text
/// /work/venv-usd/bin/python - <<'EOF'
/// from pxr import Usd, UsdGeom
/// s = Usd.Stage.Open('crates/lux-usd/tests/data/scenes/linking.usda')
/// meshes = [str(p.GetPath()) for p in s.Traverse() if p.IsA(UsdGeom.Mesh)]
/// for l in s.GetPrimAtPath('/World/Lights').GetChildren():
///     for c in ['lightLink', 'shadowLink']:
///         q = Usd.CollectionAPI(l, c).ComputeMembershipQuery()
///         inc = set(map(str, Usd.CollectionAPI.ComputeIncludedPaths(q, s)))
///         print(l.GetName(), c, [m for m in meshes if m in inc])
/// EOF
/// ```
///
/// (usd-core also warns "Found circular dependency involving the following collections:
/// [/World/Lights/CycleX.collection:lightLink, /World/Lights/CycleY.collection:lightLink]".)
/// `Pattern` is left out: its shadowLink is an expression-mode collection, which lux does not
/// evaluate (see `expression_mode_is_a_warning_and_links_everything`).
const USD_CORE: &[(&str, &[&str], &[&str])] = &[
    ("Default", ALL, ALL),
    (
        "OnlyA",
        &["/World/A/m2", "/World/A/Sub/m3"],
        &["/World/B/m4", "/World/B/m5", "/World/m6"],
    ),
    (
        "Explicit",
        &["/World/B/m4"],
        &["/World/A/m1", "/World/A/m2", "/World/A/Sub/m3", "/World/m6"],
    ),
    ("Borrow", &["/World/A/m1", "/World/A/m2", "/World/m6"], ALL),
    ("CycleX", &["/World/B/m4", "/World/B/m5", "/World/m6"], ALL),
    ("CycleY", &["/World/B/m4", "/World/B/m5", "/World/m6"], ALL),
    ("Nothing", &[], ALL),
];

#[test]
fn memberships_match_usd_core() {
    let s = linking_scene();
    assert_eq!(
        s.meshes.iter().map(|m| m.path.as_str()).collect::<Vec<_>>(),
        ALL
    );
    for (name, light_link, shadow_link) in USD_CORE {
        let path = format!("/World/Lights/{name}");
        let l = s.light(&path).unwrap_or_else(|| panic!("no light {path}"));
        assert_eq!(
            members(&s, &l.linking.light),
            *light_link,
            "{name} lightLink: {:?}",
            l.linking.light
        );
        assert_eq!(
            members(&s, &l.linking.shadow),
            *shadow_link,
            "{name} shadowLink: {:?}",
            l.linking.shadow
        );
    }
    // The default is `All` (no per-prim test), and so is an authored includeRoot alone.
    let d = &s.light("/World/Lights/Default").unwrap().linking;
    assert!(d.is_all());
    assert!(
        s.light("/World/Lights/Nothing")
            .unwrap()
            .linking
            .shadow
            .is_all()
    );
}

#[test]
fn flattened_rules_and_descriptions() {
    let s = linking_scene();
    let only_a = &s.light("/World/Lights/OnlyA").unwrap().linking;
    assert_eq!(
        only_a.light.describe(),
        "includes /World/A, excludes /World/A/m1 (expandPrims)"
    );
    assert_eq!(
        only_a.shadow.describe(),
        "includes /World/B, /World/m6 (expandPrims)"
    );
    // The included collection's rules are merged, later includes win (/World/A/m1), the
    // excludes come last.
    let borrow = &s.light("/World/Lights/Borrow").unwrap().linking;
    assert_eq!(
        borrow.light.describe(),
        "includes /World/A, /World/A/m1, /World/m6, excludes /World/A/Sub (expandPrims)"
    );
    // An included collection's rules keep their own expansion rule (explicitOnly there,
    // which also ignored its includeRoot); this one's includeRoot (LightAPI fallback true)
    // adds `/`.
    assert_eq!(
        borrow.shadow.describe(),
        "includes / (expandPrims), /World/A (explicitOnly), /World/B/m4 (explicitOnly)"
    );
    assert_eq!(
        s.light("/World/Lights/Explicit")
            .unwrap()
            .linking
            .shadow
            .describe(),
        "includes /, excludes /World/B (expandPrims)"
    );
    assert_eq!(
        s.light("/World/Lights/Nothing")
            .unwrap()
            .linking
            .light
            .describe(),
        "nothing"
    );
    // The cycle is a warning naming the light, the collection is skipped.
    let cycle: Vec<_> = s
        .warnings
        .iter()
        .filter(|w| w.message.contains("cycle"))
        .collect();
    assert_eq!(cycle.len(), 2, "{:?}", s.warnings);
    assert_eq!(cycle[0].prim, "/World/Lights/CycleX");
    // Linking is honoured now: no "not supported" warning for it.
    assert!(
        !s.warnings
            .iter()
            .any(|w| w.message.contains("linking") && w.kind == WarningKind::Unsupported),
        "{:?}",
        s.warnings
    );
}

#[test]
fn expression_mode_is_a_warning_and_links_everything() {
    let s = linking_scene();
    let p = s.light("/World/Lights/Pattern").unwrap();
    assert!(p.linking.light.is_all() && p.linking.shadow.is_all());
    let w: Vec<_> = s
        .warnings
        .iter()
        .filter(|w| w.prim == "/World/Lights/Pattern")
        .collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].kind, WarningKind::Unsupported);
    assert!(
        w[0].message
            .contains("collection:shadowLink:membershipExpression"),
        "{}",
        w[0].message
    );
}

#[test]
fn bad_targets_and_tokens_are_warnings() {
    let s = load_usda_str(
        r#"#usda 1.0
def Xform "G" {
    def Mesh "m" {
    }
}
def RectLight "L" {
    uniform bool collection:lightLink:includeRoot = 0
    uniform token collection:lightLink:expansionRule = "sometimes"
    rel collection:lightLink:includes = [</G>, </Missing.collection:lightLink>, </G/m.visibility>]
    rel collection:shadowLink:excludes = </L.collection:lightLink>
}
"#,
        1.0,
        &LoadOptions::default(),
    )
    .unwrap();
    let l = s.light("/L").unwrap();
    assert!(l.linking.light.contains("/G/m"));
    assert!(l.linking.shadow.is_all());
    let msgs: Vec<&str> = s.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(msgs.len(), 4, "{msgs:?}");
    assert!(s.warnings.iter().all(|w| w.prim == "/L"));
    assert!(msgs[0].contains("expansionRule \"sometimes\""), "{msgs:?}");
    assert!(msgs.iter().any(|m| m.contains("no prim </Missing>")));
    assert!(msgs.iter().any(|m| m.contains("</G/m.visibility>")));
    assert!(msgs.iter().any(|m| m.contains("excludes cannot target")));
}

#[test]
fn instanced_lights_and_geometry_paths() {
    // A light inside an instanced prototype links the prototype's geometry of its own
    // instance; the geometry of an instance is judged by its instance-proxy path.
    let s = load_usda_str(
        r#"#usda 1.0
def Xform "Asset" {
    def Mesh "body" {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    }
    def Mesh "trim" {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    }
    def RectLight "Lamp" {
        rel collection:lightLink:excludes = </Asset/trim>
    }
}
def Xform "I1" (instanceable = true references = </Asset>) {
}
def Xform "I2" (instanceable = true references = </Asset>) {
}
def RectLight "Key" {
    uniform bool collection:lightLink:includeRoot = 0
    rel collection:lightLink:includes = </I2/body>
}
"#,
        1.0,
        &LoadOptions::default(),
    )
    .unwrap();
    let key = &s.light("/Key").unwrap().linking.light;
    let drawn: Vec<(String, bool)> = s
        .instances
        .iter()
        .enumerate()
        .flat_map(|(i, inst)| {
            s.prototypes[inst.prototype]
                .meshes
                .iter()
                .map(move |&m| (i, m))
        })
        .map(|(i, m)| {
            let p = s.geometry_path(m, Some(i)).into_owned();
            let k = key.contains(&p);
            (p, k)
        })
        .collect();
    assert!(
        drawn.contains(&("/I2/body".to_owned(), true))
            && drawn.contains(&("/I1/body".to_owned(), false))
            && drawn.contains(&("/I2/trim".to_owned(), false)),
        "{drawn:?}"
    );
    // The lamp of /I2 excludes /I2/trim (and /Asset/Lamp's own exclusion stays /Asset/trim).
    let lamp2 = &s.light("/I2/Lamp").unwrap().linking.light;
    assert!(!lamp2.contains("/I2/trim") && lamp2.contains("/I2/body"));
    assert!(lamp2.contains("/I1/trim"));
    let lamp0 = &s.light("/Asset/Lamp").unwrap().linking.light;
    assert!(!lamp0.contains("/Asset/trim"));
}
