//! `lux info SCENE [--frame N] [--json]`: a summary of a USD stage as lux loads it.
//!
//! The conformance profile the renderer would use and which source decided it; then per light:
//! type, world position and axis (local −Z), sizeFactor and the emitted base radiance in each
//! conformance profile — exactly what the renderer emits before shaping (lux-math's
//! `intensity · 2^exposure · color · blackbody / sizeFactor`, or lux-spectral's conversion when
//! physical units or spectra are authored) — a ShapingAPI summary, the physical-unit and
//! spectral attributes as authored, light and shadow links when authored
//! (`collection:lightLink` / `collection:shadowLink`); then per bound material its shading
//! model (the MaterialX graph's surface nodedef) and the graph's notes (inputs it could not
//! honour); then every warning of the loader and of the light set-up.

use clap::Args;
use lux_math::{Profile, size_factor};
use lux_render::conformance::{
    PROFILE_ENV, ResolvedProfile, default_config_paths, resolve_profile,
};
use lux_render::light::{LightOptions, LightSelection, LightSet};
use lux_spectral::SpectralAttribute;
use lux_usd::defaults::{CAMERA_LIGHT_PATH, FRAMING_CAMERA_PATH, geometry_bounds};
use lux_usd::{LoadOptions, PhysicalLight, Scene, Time, load_stage_with};
use serde_json::{Value, json};
use std::fmt::Write;
use std::path::PathBuf;

/// Arguments of `lux info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The USD stage (.usda, .usdc or .usdz).
    pub scene: PathBuf,
    /// Time code to evaluate (default: the stage's startTimeCode, as usdrecord).
    #[arg(long, allow_hyphen_values = true)]
    pub frame: Option<f64>,
    /// Turn composition warnings into errors (as `lux render --strict`).
    #[arg(long)]
    pub strict: bool,
    /// Report without usdrecord's camera light (as `lux render --disable-camera-light`).
    #[arg(long)]
    pub disable_camera_light: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Refine subdivision surfaces at this level, 0 to 10 (default: as `lux render` in the
    /// profile: by size on screen in spec, the cages' polygons in hdembree).
    #[arg(long)]
    pub subdiv_level: Option<u32>,
}

fn v3(v: glam::DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// A spectral attribute as JSON: its pairs and metadata.
fn spectrum_json(a: &SpectralAttribute) -> Value {
    json!({
        "values": a.values,
        "unit_for_wavelength": a.unit_for_wavelength.map(|u| format!("{u:?}")),
        "interpolation": format!("{:?}", a.interpolation),
        "illuminant_preset": a.illuminant_preset.map(|p| format!("{p:?}")),
    })
}

/// A light's physical-unit inputs as JSON.
fn physical_json(p: &PhysicalLight) -> Value {
    json!({
        "quantity": p.quantity.map(|q| json!({ "attribute": q.attribute(), "value": q.value() })),
        "illuminant": format!("{:?}", p.illuminant),
        "custom_illuminant": p.custom_illuminant,
    })
}

/// A bound material as JSON: its path, whether its `outputs:surface` is a UsdPreviewSurface,
/// the shading model of its MaterialX graph (`ND_standard_surface_surfaceshader`,
/// `UsdPreviewSurface`, …; `null` without a graph) and every input it could not honour
/// ([`material_notes`]).
fn material_json(m: &lux_usd::Material) -> Value {
    json!({
        "path": m.path,
        "preview_surface": m.preview,
        "model": m.graph.as_ref().map(|g| g.model.clone()),
        "graph_nodes": m.graph.as_ref().map(|g| g.nodes.len()),
        "notes": material_notes(m),
    })
}

/// What lux cannot honour of a material's MaterialX graph as authored: the notes of its
/// flattening (lux-usd: unknown nodedefs, inputs the nodedef lacks, converted types) and of its
/// compilation for the renderer (`GraphShader::unsupported`: object-space quantities read in
/// world space, texture coordinate sets other than 0, cubic filtering read as linear, textures
/// that do not load), each once.
fn material_notes(m: &lux_usd::Material) -> Vec<String> {
    let Some(g) = &m.graph else {
        return Vec::new();
    };
    let mut notes = g.notes.clone();
    if g.surface.is_some() {
        let mut textures = lux_render::material::graph::TextureCache::new();
        let shader =
            lux_render::material::graph::GraphShader::compile(g, &mut textures, &mut Vec::new());
        for n in shader.unsupported() {
            if !notes.contains(n) {
                notes.push(n.clone());
            }
        }
    }
    notes
}

/// The report as a JSON value. `profile` is the resolved profile (or the error resolving it);
/// `defaults` the usdrecord defaults added to the stage ([`Scene::add_usdrecord_defaults`]).
pub fn report_json(
    scene: &Scene,
    profile: &Result<ResolvedProfile, String>,
    defaults: &[String],
) -> Value {
    // The renderer's light set-up in each profile (IES and textures loaded, physical units
    // converted); a failure is reported instead of the values.
    let sets: Vec<(Profile, Result<LightSet, String>)> = Profile::ALL
        .iter()
        .map(|&p| {
            let opts = LightOptions {
                cone_clipping: true,
                profile: p,
                selection: LightSelection::All,
                strict: false,
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
                    Ok(s) => match s.lights.iter().find(|r| r.base().path == l.path) {
                        Some(r) => json!({ "size_factor": sf, "luminance_rgb": v3(r.base().radiance) }),
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
            json!({
                "path": l.path, "type": l.type_name,
                "position": v3(l.position()), "axis": v3(l.axis()),
                "api_schemas": l.api_schemas,
                "profiles": per_profile, "shaping": shaping,
                "physical": l.physical.as_ref().map(physical_json),
                "emission_spectrum": l.emission_spectrum.as_ref().map(spectrum_json),
                "light_link": l.linking.light.describe(),
                "shadow_link": l.linking.shadow.describe(),
            })
        })
        .collect();
    let materials: Vec<Value> = scene.materials.iter().map(material_json).collect();
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
        "counts": {
            "meshes": scene.gprims.meshes,
            "other_gprims": scene.gprims.other_gprims(),
            "implicit_gprims": scene.gprims.implicit,
            "not_drawn": scene.gprims.skipped,
            "native_instances": scene.gprims.native_instances,
            "point_instances": scene.gprims.point_instances,
            "cameras": scene.cameras.iter().filter(|c| c.path != FRAMING_CAMERA_PATH).count(),
            "lights": scene.lights.iter().filter(|l| l.path != CAMERA_LIGHT_PATH).count()
                + scene.gprims.unsupported_lights,
            "lights_not_rendered": scene.gprims.unsupported_lights,
            "refined_meshes": scene.drawn.refined_meshes,
            "posed_meshes": scene.drawn.posed_meshes,
            "curves": scene.drawn.curves,
            "points": scene.drawn.points,
        },
        "bounds": geometry_bounds(scene).map(|(lo, hi)| json!({ "min": v3(lo), "max": v3(hi) })),
        "unique_meshes": scene.meshes.len(),
        "prototypes": scene.prototypes.len(),
        "instances": scene.instances.len(),
        "triangles": scene.meshes.iter().map(|m| m.triangles.len()).sum::<usize>(),
        "cameras": scene.cameras.iter().map(|c| c.path.clone()).collect::<Vec<_>>(),
        "defaults": defaults,
        "unit_for_wavelength": format!("{:?}", scene.unit_for_wavelength),
        "lights": lights,
        "materials": materials,
        "warnings": warnings,
    })
}

/// A float for the text report. Lights' inputs are authored as `float` (f32): the value is
/// shown as the shortest text that reads back as the same f32 (`0.3`, not the f64 widening
/// `0.30000001192092896`), and values derived from them in f64 at that precision. Scientific
/// notation outside 1e-4 to 1e9.
fn num(x: f64) -> String {
    let f = x as f32;
    if x == 0.0 {
        "0".to_owned()
    } else if !f.is_finite() {
        format!("{x}")
    } else if (1e-4..1e9).contains(&f.abs()) {
        format!("{f}")
    } else {
        format!("{f:e}")
    }
}

/// A value computed from authored floats (sizeFactor, radiance, axis) to 6 significant
/// digits: `5.4`, not the f32 neighbour `5.3999996`.
fn approx(x: f64) -> String {
    match format!("{x:.5e}").parse::<f64>() {
        Ok(r) if x.is_finite() => num(r),
        _ => format!("{x}"),
    }
}

/// A vector as `(x, y, z)` with `f` ([`num`] or [`approx`]); components below 1e-12 of the
/// largest (rounding in transforms) show as 0.
fn vec3_with(v: glam::DVec3, f: fn(f64) -> String) -> String {
    let m = v.abs().max_element();
    let c = |x: f64| f(if x.abs() <= m * 1e-12 { 0.0 } else { x });
    format!("({}, {}, {})", c(v.x), c(v.y), c(v.z))
}

/// The unit of a physical-light quantity.
fn quantity_unit(q: lux_spectral::PhysicalQuantity) -> &'static str {
    use lux_spectral::PhysicalQuantity as Q;
    match q {
        Q::PhotometricPower(_) => "lm",
        Q::RadiometricPower(_) => "W",
        Q::PhotometricIlluminance(_) => "lx",
        Q::RadiometricIrradiance(_) => "W/m²",
    }
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The report as text (the same facts as [`report_json`]).
pub fn report_text(
    scene: &Scene,
    profile: &Result<ResolvedProfile, String>,
    defaults: &[String],
) -> String {
    let j = report_json(scene, profile, defaults);
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
    let g = &scene.gprims;
    let not_drawn: Vec<String> = g.skipped.iter().map(|(t, n)| format!("{n} {t}")).collect();
    let _ = writeln!(
        s,
        "{}: {}, {} ({} implicit{}), {}, {}, {}, {}",
        plural(scene.prim_count, "prim", "prims"),
        plural(g.meshes, "mesh", "meshes"),
        plural(g.other_gprims(), "other gprim", "other gprims"),
        g.implicit,
        if not_drawn.is_empty() {
            String::new()
        } else {
            format!(", not drawn: {}", not_drawn.join(", "))
        },
        plural(g.native_instances, "native instance", "native instances"),
        plural(g.point_instances, "point instance", "point instances"),
        plural(
            j["counts"]["cameras"].as_u64().unwrap_or(0) as usize,
            "camera",
            "cameras"
        ),
        plural(
            j["counts"]["lights"].as_u64().unwrap_or(0) as usize,
            "light",
            "lights"
        ),
    );
    let _ = writeln!(
        s,
        "geometry: {} ({}) stored once, {} drawn through {}",
        plural(scene.meshes.len(), "mesh", "meshes"),
        plural(
            j["triangles"].as_u64().unwrap_or(0) as usize,
            "triangle",
            "triangles"
        ),
        plural(scene.prototypes.len(), "prototype", "prototypes"),
        plural(scene.instances.len(), "instance", "instances"),
    );
    let d = &scene.drawn;
    if d.refined_meshes + d.posed_meshes + d.curves + d.points > 0 {
        let _ = writeln!(
            s,
            "drawn: {} refined, {} posed, {}, {}",
            plural(
                d.refined_meshes,
                "subdivision surface",
                "subdivision surfaces"
            ),
            plural(d.posed_meshes, "skinned mesh", "skinned meshes"),
            plural(d.curves, "curve prim", "curve prims"),
            plural(d.points, "points prim", "points prims"),
        );
    }
    if let Some((lo, hi)) = geometry_bounds(scene) {
        let _ = writeln!(
            s,
            "bounds: {}..{}",
            vec3_with(lo, approx),
            vec3_with(hi, approx)
        );
    }
    for d in defaults {
        let _ = writeln!(s, "default: {d}");
    }
    for (l, lj) in scene
        .lights
        .iter()
        .zip(j["lights"].as_array().into_iter().flatten())
    {
        let p = l.position();
        let a = l.axis();
        let _ = writeln!(s, "light {} ({})", l.path, l.type_name);
        let unit = if scene.meters_per_unit == 1.0 {
            " m".to_owned()
        } else {
            format!(" × {} m", num(scene.meters_per_unit))
        };
        let _ = writeln!(
            s,
            "  position {}{unit}  axis {}",
            vec3_with(p, num),
            vec3_with(a, approx)
        );
        for prof in Profile::ALL {
            let e = &lj["profiles"][prof.name()];
            let rgb = e["luminance_rgb"].as_array().map(|c| {
                let c: Vec<f64> = c.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect();
                format!(
                    "{} nits",
                    vec3_with(glam::DVec3::new(c[0], c[1], c[2]), approx)
                )
            });
            let _ = writeln!(
                s,
                "  {:<9} sizeFactor {}  L = {}{}",
                prof.name(),
                approx(e["size_factor"].as_f64().unwrap_or(f64::NAN)),
                rgb.as_deref().unwrap_or("none"),
                e.get("error")
                    .or_else(|| e.get("note"))
                    .and_then(|x| x.as_str())
                    .map(|x| format!("  ({x})"))
                    .unwrap_or_default()
            );
        }
        match &l.shaping {
            Some(sh) => {
                let _ = writeln!(
                    s,
                    "  shaping: focus {} tint {} cone {}° softness {} ies {} angleScale {} normalize {}",
                    num(sh.focus),
                    vec3_with(sh.focus_tint, num),
                    num(sh.cone_angle_deg),
                    num(sh.cone_softness),
                    sh.ies_file.as_ref().map_or("none", |a| a.authored.as_str()),
                    num(sh.ies_angle_scale),
                    sh.ies_normalize
                );
            }
            None => {
                let _ = writeln!(s, "  shaping: not applied");
            }
        }
        if let Some(p) = &l.physical {
            match p.quantity {
                Some(q) => {
                    let _ = writeln!(
                        s,
                        "  {} = {} {}",
                        q.attribute(),
                        num(q.value()),
                        quantity_unit(q)
                    );
                }
                None => {
                    let _ = writeln!(s, "  PhysicalLightIlluminantAPI");
                }
            }
            let _ = writeln!(
                s,
                "  physical:illuminant = {:?}{}",
                p.illuminant,
                if p.custom_illuminant.is_empty() {
                    String::new()
                } else {
                    format!(
                        " ({})",
                        plural(p.custom_illuminant.len(), "custom pair", "custom pairs")
                    )
                }
            );
        }
        // LightAPI collection:lightLink / collection:shadowLink, when either is authored.
        if !l.linking.is_all() {
            let _ = writeln!(s, "  lightLink: {}", l.linking.light.describe());
            let _ = writeln!(s, "  shadowLink: {}", l.linking.shadow.describe());
        }
        if let Some(e) = &l.emission_spectrum {
            let _ = writeln!(
                s,
                "  wavelength:emission = {}, preset {:?}, unit {:?}, {:?}",
                plural(e.values.len(), "pair", "pairs"),
                e.illuminant_preset,
                e.unit_for_wavelength,
                e.interpolation
            );
        }
    }
    for m in &scene.materials {
        let model = match &m.graph {
            Some(g) if !g.model.is_empty() => g.model.clone(),
            Some(_) => "shading graph without a model".to_owned(),
            None if m.preview => "UsdPreviewSurface fields only".to_owned(),
            None => "no shading graph".to_owned(),
        };
        let _ = writeln!(s, "material {} ({model})", m.path);
        for n in material_notes(m) {
            let _ = writeln!(s, "  note: {n}");
        }
    }
    for w in j["warnings"].as_array().into_iter().flatten() {
        let _ = writeln!(s, "warning: {}", w.as_str().unwrap_or_default());
    }
    s
}

/// Loads the stage and renders the report (text or JSON) as a string.
pub fn report(args: &InfoArgs) -> Result<String, String> {
    let mut options = LoadOptions::default();
    options.strict = args.strict;
    let time = args.frame.map_or(Time::Start, Time::Code);
    let mut scene = load_stage_with(&args.scene, time, &options).map_err(|e| e.to_string())?;
    let defaults = scene.add_usdrecord_defaults(!args.disable_camera_light);
    let env = std::env::var(PROFILE_ENV).ok();
    let profile = resolve_profile(None, &scene, env.as_deref(), &default_config_paths())
        .map_err(|e| e.to_string());
    // Subdivision surfaces as a render in that profile draws them (its rule for the render
    // camera at the default resolution), so that the counts and bounds are what is drawn.
    let mut refined = Vec::new();
    if let Ok(p) = &profile {
        let mut options = lux_render::render::RenderOptions::new(p.clone());
        options.subdiv_level = args.subdiv_level;
        if let Some(l) = args.subdiv_level
            && l > lux_usd::subdiv::MAX_LEVEL
        {
            return Err(format!(
                "subdivision level {l}: expected 0 to {}",
                lux_usd::subdiv::MAX_LEVEL
            ));
        }
        refined = lux_render::settings::refine_subdivision(&mut scene, &options)
            .map_err(|e| e.to_string())?;
    }
    Ok(if args.json {
        let mut j = report_json(&scene, &profile, &defaults);
        j["refined"] = Value::Array(
            refined
                .iter()
                .map(|r| {
                    let m = &scene.meshes[r.mesh];
                    json!({ "path": m.path, "level": r.level, "triangles": m.triangles.len() })
                })
                .collect(),
        );
        serde_json::to_string_pretty(&j).map_err(|e| e.to_string())?
    } else {
        let mut t = report_text(&scene, &profile, &defaults);
        if !refined.is_empty() {
            let (lo, hi) = refined
                .iter()
                .fold((u32::MAX, 0), |(l, h), r| (l.min(r.level), h.max(r.level)));
            let _ = writeln!(
                t,
                "subdivision: {} refined at level {}",
                plural(refined.len(), "surface", "surfaces"),
                if lo == hi {
                    lo.to_string()
                } else {
                    format!("{lo} to {hi}")
                }
            );
        }
        t
    })
}

/// Runs `lux info`: prints the report; a load error is returned (the binary exits non-zero).
/// A reader closing stdout early (`lux info … | head`) ends the report quietly (exit 0), as
/// `cli/out.rs` does for the other commands; this file stays self-contained for the tests that
/// include it.
pub fn run(args: &InfoArgs) -> Result<(), String> {
    use std::io::Write as _;
    let text = report(args)?;
    let mut out = std::io::stdout().lock();
    match out
        .write_all(text.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush())
    {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write to stdout: {e}"))
        }
        _ => Ok(()),
    }
}
