//! `lux info SCENE [--frame N] [--json]`: a summary of a USD stage as lux loads it.
//!
//! Per light: type, world position and axis (local −Z), sizeFactor and the emitted base
//! radiance `L = intensity · 2^exposure · color · blackbody / sizeFactor` (lux-math) in each
//! conformance profile, and a ShapingAPI summary; then the loader's warnings.

use clap::Args;
use lux_math::{Profile, emission, size_factor};
use lux_render::scene::{Scene, load_stage};
use serde_json::{Value, json};
use std::fmt::Write;
use std::path::PathBuf;

/// Arguments of `lux info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The USD stage (.usda, .usdc or .usdz).
    pub scene: PathBuf,
    /// Time code to evaluate (default 1).
    #[arg(long, default_value_t = 1.0)]
    pub frame: f64,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

fn v3(v: glam::DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// The report as a JSON value.
pub fn report_json(scene: &Scene) -> Value {
    let lights: Vec<Value> = scene
        .lights
        .iter()
        .map(|l| {
            let mut per_profile = serde_json::Map::new();
            for p in Profile::ALL {
                let sf = size_factor(&l.shape, &l.light_to_world, p);
                let rgb = emission(&l.params, l.kind, sf, p);
                per_profile.insert(
                    p.name().to_owned(),
                    json!({ "size_factor": sf, "luminance_rgb": v3(rgb) }),
                );
            }
            let shaping = l.shaping.as_ref().map(|s| {
                json!({
                    "focus": s.focus, "focus_tint": v3(s.focus_tint),
                    "cone_angle_deg": s.cone_angle_deg, "cone_softness": s.cone_softness,
                    "ies_file": s.ies_file.as_ref().map(|a| a.authored.clone()),
                    "ies_resolved": s.ies_file.as_ref().and_then(|a| a.resolved.as_ref()).map(|p| p.display().to_string()),
                    "ies_angle_scale": s.ies_angle_scale, "ies_normalize": s.ies_normalize,
                })
            });
            json!({
                "path": l.path, "type": l.type_name,
                "position": v3(l.position()), "axis": v3(l.axis()),
                "profiles": per_profile, "shaping": shaping,
            })
        })
        .collect();
    json!({
        "source": scene.source.display().to_string(),
        "frame": scene.frame,
        "prims": scene.prim_count,
        "meshes": scene.meshes.len(),
        "triangles": scene.meshes.iter().map(|m| m.triangles.len()).sum::<usize>(),
        "cameras": scene.cameras.iter().map(|c| c.path.clone()).collect::<Vec<_>>(),
        "lights": lights,
        "warnings": scene.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
    })
}

/// The report as text.
pub fn report_text(scene: &Scene) -> String {
    let j = report_json(scene);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "stage {} at frame {}",
        scene.source.display(),
        scene.frame
    );
    let _ = writeln!(
        s,
        "{} prims, {} meshes ({} triangles), {} cameras, {} lights",
        scene.prim_count,
        scene.meshes.len(),
        j["triangles"],
        scene.cameras.len(),
        scene.lights.len()
    );
    for (l, lj) in scene
        .lights
        .iter()
        .zip(j["lights"].as_array().into_iter().flatten())
    {
        let p = l.position();
        let a = l.axis();
        let _ = writeln!(s, "light {} ({})", l.path, l.type_name);
        let _ = writeln!(
            s,
            "  position ({:.6}, {:.6}, {:.6})  axis ({:.6}, {:.6}, {:.6})",
            p.x, p.y, p.z, a.x, a.y, a.z
        );
        for prof in Profile::ALL {
            let e = &lj["profiles"][prof.name()];
            let _ = writeln!(
                s,
                "  {:<9} sizeFactor {}  L = {}",
                prof.name(),
                e["size_factor"],
                e["luminance_rgb"]
            );
        }
        match &l.shaping {
            Some(sh) => {
                let _ = writeln!(
                    s,
                    "  shaping: focus {} tint {} cone {}° softness {} ies {} angleScale {} normalize {}",
                    sh.focus,
                    sh.focus_tint,
                    sh.cone_angle_deg,
                    sh.cone_softness,
                    sh.ies_file.as_ref().map_or("none", |a| a.authored.as_str()),
                    sh.ies_angle_scale,
                    sh.ies_normalize
                );
            }
            None => {
                let _ = writeln!(s, "  shaping: not applied");
            }
        }
    }
    for w in &scene.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    s
}

/// Loads the stage and renders the report (text or JSON) as a string.
pub fn report(args: &InfoArgs) -> Result<String, String> {
    let scene = load_stage(&args.scene, args.frame).map_err(|e| e.to_string())?;
    Ok(if args.json {
        serde_json::to_string_pretty(&report_json(&scene)).map_err(|e| e.to_string())?
    } else {
        report_text(&scene)
    })
}

/// Runs `lux info`: prints the report; a load error is returned (the binary exits non-zero).
pub fn run(args: &InfoArgs) -> Result<(), String> {
    println!("{}", report(args)?);
    Ok(())
}
