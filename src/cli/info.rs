//! `lux info SCENE [--frame N] [--json]`: a summary of a USD stage as lux loads it.
//!
//! The conformance profile the renderer would use and which source decided it; then per light:
//! type, world position and axis (local −Z), sizeFactor and the emitted base radiance in each
//! conformance profile — exactly what the renderer emits before shaping (lux-math's
//! `intensity · 2^exposure · color · blackbody / sizeFactor`, or lux-spectral's conversion when
//! physical units or spectra are authored) — a ShapingAPI summary, the physical-unit and
//! spectral attributes as authored; then every warning of the loader and of the light set-up.

use clap::Args;
use lux_math::{Profile, size_factor};
use lux_render::conformance::{
    PROFILE_ENV, ResolvedProfile, default_config_paths, resolve_profile,
};
use lux_render::lights::{LightOptions, LightSelection, LightSet};
use lux_usd::{RawValue, Scene, load_stage};
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

fn raw_json(v: &RawValue) -> Value {
    match v {
        RawValue::Bool(b) => json!(b),
        RawValue::Number(x) => json!(x),
        RawValue::Numbers(xs) => json!(xs),
        RawValue::Text(t) => json!(t),
        RawValue::Asset(a) => json!(a.authored),
    }
}

/// The report as a JSON value. `profile` is the resolved profile (or the error resolving it).
pub fn report_json(scene: &Scene, profile: &Result<ResolvedProfile, String>) -> Value {
    // The renderer's light set-up in each profile (IES and textures loaded, physical units
    // converted); a failure is reported instead of the values.
    let sets: Vec<(Profile, Result<LightSet, String>)> = Profile::ALL
        .iter()
        .map(|&p| {
            let opts = LightOptions {
                profile: p,
                selection: LightSelection::All,
            };
            (p, LightSet::new(scene, opts).map_err(|e| e.to_string()))
        })
        .collect();
    let lights: Vec<Value> = scene
        .lights
        .iter()
        .map(|l| {
            let mut per_profile = serde_json::Map::new();
            for (p, set) in &sets {
                let sf = size_factor(&l.shape, &l.light_to_world, *p);
                let entry = match set {
                    Ok(s) => match s.lights.iter().find(|r| r.path == l.path) {
                        Some(r) => json!({ "size_factor": sf, "luminance_rgb": v3(r.radiance) }),
                        None => json!({ "size_factor": sf, "luminance_rgb": null,
                                        "note": "not rendered (see warnings)" }),
                    },
                    Err(e) => json!({ "size_factor": sf, "luminance_rgb": null, "error": e }),
                };
                per_profile.insert(p.name().to_owned(), entry);
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
            let physical: serde_json::Map<String, Value> = l
                .physical
                .values
                .iter()
                .map(|(k, v)| (k.clone(), raw_json(v)))
                .collect();
            json!({
                "path": l.path, "type": l.type_name,
                "position": v3(l.position()), "axis": v3(l.axis()),
                "api_schemas": l.api_schemas,
                "profiles": per_profile, "shaping": shaping,
                "physical": physical, "physical_metadata": l.physical.metadata,
            })
        })
        .collect();
    let mut warnings: Vec<String> = scene.warnings.iter().map(|w| w.to_string()).collect();
    for (p, set) in &sets {
        if let Ok(s) = set {
            warnings.extend(
                s.warnings
                    .iter()
                    .map(|w| format!("{} profile: {w}", p.name())),
            );
        }
    }
    json!({
        "source": scene.source.display().to_string(),
        "frame": scene.frame,
        "profile": match profile {
            Ok(r) => json!({ "name": r.profile.name(), "source": r.source.to_string() }),
            Err(e) => json!({ "error": e }),
        },
        "prims": scene.prim_count,
        "meshes": scene.meshes.len(),
        "triangles": scene.meshes.iter().map(|m| m.triangles.len()).sum::<usize>(),
        "cameras": scene.cameras.iter().map(|c| c.path.clone()).collect::<Vec<_>>(),
        "unit_for_wavelength": scene.unit_for_wavelength,
        "lights": lights,
        "warnings": warnings,
    })
}

/// The report as text (the same facts as [`report_json`]).
pub fn report_text(scene: &Scene, profile: &Result<ResolvedProfile, String>) -> String {
    let j = report_json(scene, profile);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "stage {} at frame {}",
        scene.source.display(),
        scene.frame
    );
    let _ = match profile {
        Ok(r) => writeln!(s, "conformance profile {} (from {})", r.profile, r.source),
        Err(e) => writeln!(s, "conformance profile: {e}"),
    };
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
                "  {:<9} sizeFactor {}  L = {}{}",
                prof.name(),
                e["size_factor"],
                e["luminance_rgb"],
                e.get("error")
                    .map(|x| format!("  ({x})"))
                    .unwrap_or_default()
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
        for (k, v) in &l.physical.values {
            let meta = l
                .physical
                .metadata
                .get(k)
                .map(|m| format!("  {m:?}"))
                .unwrap_or_default();
            let _ = writeln!(s, "  {k} = {}{meta}", raw_json(v));
        }
        for (k, m) in &l.physical.metadata {
            if !l.physical.values.contains_key(k) {
                let _ = writeln!(s, "  {k} (no value)  {m:?}");
            }
        }
    }
    for w in j["warnings"].as_array().into_iter().flatten() {
        let _ = writeln!(s, "warning: {}", w.as_str().unwrap_or_default());
    }
    s
}

/// Loads the stage and renders the report (text or JSON) as a string.
pub fn report(args: &InfoArgs) -> Result<String, String> {
    let scene = load_stage(&args.scene, args.frame).map_err(|e| e.to_string())?;
    let env = std::env::var(PROFILE_ENV).ok();
    let profile = resolve_profile(None, &scene, env.as_deref(), &default_config_paths())
        .map_err(|e| e.to_string());
    Ok(if args.json {
        serde_json::to_string_pretty(&report_json(&scene, &profile)).map_err(|e| e.to_string())?
    } else {
        report_text(&scene, &profile)
    })
}

/// Runs `lux info`: prints the report; a load error is returned (the binary exits non-zero).
pub fn run(args: &InfoArgs) -> Result<(), String> {
    println!("{}", report(args)?);
    Ok(())
}
