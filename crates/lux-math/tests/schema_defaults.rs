//! `LightParams::defaults_for` and `LightShape::default_for` against the attribute defaults written
//! in the UsdLux schema itself (tests/data/usdLux-schema-26.11.usda, OpenUSD 26.11; see the README
//! there): every `inputs:` default the emission formula and the size factor read, per light class,
//! with the class's own override (DistantLight's `inputs:intensity = 50000`) taking precedence over
//! the `LightAPI` default it inherits.

use glam::DVec3;
use lux_math::{LightKind, LightParams, LightShape};
use std::collections::HashMap;

const SCHEMA: &str = include_str!("data/usdLux-schema-26.11.usda");

/// `class <Type> "<Name>"` / `class "<Name>"` blocks → { attribute name → default value text }.
fn schema_defaults() -> HashMap<String, HashMap<String, String>> {
    let mut out: HashMap<String, HashMap<String, String>> = HashMap::new();
    let mut current: Option<String> = None;
    for line in SCHEMA.lines() {
        // Class headers start at column 0.
        if let Some(rest) = line.strip_prefix("class ") {
            // The quoted name is the last "..." of the header line.
            let name = rest.rsplit('"').nth(1).unwrap_or_default().to_owned();
            current = Some(name);
            continue;
        }
        let Some(class) = &current else { continue };
        // Attribute lines inside a class body are indented by 4 spaces exactly.
        let Some(body) = line.strip_prefix("    ") else {
            continue;
        };
        if body.starts_with(' ') {
            continue;
        }
        let body = body.trim_start_matches("uniform ");
        let mut it = body.splitn(2, ' ');
        let (Some(ty), Some(rest)) = (it.next(), it.next()) else {
            continue;
        };
        if !matches!(ty, "float" | "bool" | "color3f" | "token") {
            continue;
        }
        let Some((name, value)) = rest.split_once(" = ") else {
            continue;
        };
        let value = value.trim_end_matches(" (").trim_end_matches('(').trim();
        out.entry(class.clone())
            .or_default()
            .insert(name.trim().to_owned(), value.to_owned());
    }
    out
}

fn num(v: &str) -> f64 {
    v.parse().unwrap_or_else(|_| panic!("not a number: {v:?}"))
}

fn color(v: &str) -> DVec3 {
    let c: Vec<f64> = v
        .trim_matches(|c| c == '(' || c == ')')
        .split(',')
        .map(|x| num(x.trim()))
        .collect();
    DVec3::new(c[0], c[1], c[2])
}

fn flag(v: &str) -> bool {
    match v {
        "true" => true,
        "false" => false,
        _ => panic!("not a bool: {v:?}"),
    }
}

#[test]
fn light_params_follow_the_schema_defaults_of_every_kind() {
    let s = schema_defaults();
    let api = &s["LightAPI"];
    // The parser found the LightAPI block and its five emission inputs.
    for a in [
        "inputs:intensity",
        "inputs:exposure",
        "inputs:color",
        "inputs:enableColorTemperature",
        "inputs:colorTemperature",
        "inputs:normalize",
    ] {
        assert!(api.contains_key(a), "LightAPI {a} not found in the schema");
    }
    let classes = [
        (LightKind::Distant, "DistantLight"),
        (LightKind::Dome, "DomeLight"),
        (LightKind::Portal, "PortalLight"),
        (LightKind::Rect, "RectLight"),
        (LightKind::Disk, "DiskLight"),
        (LightKind::Sphere, "SphereLight"),
        (LightKind::Cylinder, "CylinderLight"),
        (LightKind::Mesh, "MeshLightAPI"),
    ];
    for (kind, class) in classes {
        let none = HashMap::new();
        let own = s.get(class).unwrap_or(&none);
        let get = |a: &str| own.get(a).or_else(|| api.get(a)).unwrap().as_str();
        let want = LightParams {
            intensity: num(get("inputs:intensity")),
            exposure: num(get("inputs:exposure")),
            color: color(get("inputs:color")),
            enable_color_temperature: flag(get("inputs:enableColorTemperature")),
            color_temperature: num(get("inputs:colorTemperature")),
            normalize: flag(get("inputs:normalize")),
        };
        assert_eq!(LightParams::defaults_for(kind), want, "{class}");
    }
    // The one per-class override of the schema, spelled out.
    assert_eq!(s["DistantLight"]["inputs:intensity"], "50000");
    assert_eq!(
        LightParams::default(),
        LightParams::defaults_for(LightKind::Rect)
    );
}

#[test]
fn light_shapes_follow_the_schema_defaults_of_every_kind() {
    let s = schema_defaults();
    let f = |class: &str, a: &str| num(&s[class][a]);
    assert_eq!(
        LightShape::default_for(LightKind::Distant),
        LightShape::Distant {
            angle_deg: f("DistantLight", "inputs:angle")
        }
    );
    assert_eq!(
        LightShape::default_for(LightKind::Rect),
        LightShape::Rect {
            width: f("RectLight", "inputs:width"),
            height: f("RectLight", "inputs:height")
        }
    );
    assert_eq!(
        LightShape::default_for(LightKind::Portal),
        LightShape::Portal {
            width: f("PortalLight", "inputs:width"),
            height: f("PortalLight", "inputs:height")
        }
    );
    assert_eq!(
        LightShape::default_for(LightKind::Disk),
        LightShape::Disk {
            radius: f("DiskLight", "inputs:radius")
        }
    );
    assert_eq!(
        LightShape::default_for(LightKind::Sphere),
        LightShape::Sphere {
            radius: f("SphereLight", "inputs:radius")
        }
    );
    assert_eq!(
        LightShape::default_for(LightKind::Cylinder),
        LightShape::Cylinder {
            radius: f("CylinderLight", "inputs:radius"),
            length: f("CylinderLight", "inputs:length")
        }
    );
    // The values the issue quotes, read from the schema (not from the code).
    assert_eq!(f("DistantLight", "inputs:angle"), 0.53);
    assert_eq!(f("SphereLight", "inputs:radius"), 0.5);
}
