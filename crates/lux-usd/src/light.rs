//! UsdLux lights: `LightAPI` inputs with the schema defaults filled in, geometry, `ShapingAPI`,
//! `ShadowAPI`, physical-unit attributes, all at the load frame.

use crate::error::{LoadError, WarningKind};
use crate::linking::Linking;
use crate::reader::{AssetRef, Reader};
use crate::spectral::PhysicalLight;
use glam::{DMat4, DVec3};
use lux_math::{LightKind, LightParams, LightShape};
use lux_spectral::SpectralAttribute;
use openusd::usd::Prim;

/// `ShapingAPI` inputs (UsdLux 26.11 `ShapingAPI`), present on a [`Light`] only when the API is
/// applied. `Default` gives the schema defaults: focus 0, focusTint black, cone angle 90°,
/// softness 0, no IES file, angleScale 0, ies:normalize false.
///
/// (Stand-in for `lux_shaping::ShapingParams` until that crate lands; same fields.)
#[derive(Clone, Debug, PartialEq)]
pub struct ShapingInputs {
    /// `inputs:shaping:focus`: exponent of `|emissionDir · lightAxis|` (ignored when ≤ 0).
    pub focus: f64,
    /// `inputs:shaping:focusTint`: colour lerped towards off-axis.
    pub focus_tint: DVec3,
    /// `inputs:shaping:cone:angle` in degrees (half-angle from the axis).
    pub cone_angle_deg: f64,
    /// `inputs:shaping:cone:softness` (raw; the emission code clamps it to [0, 1]).
    pub cone_softness: f64,
    /// `inputs:shaping:ies:file`, resolved against its authoring layer.
    pub ies_file: Option<AssetRef>,
    /// `inputs:shaping:ies:angleScale`.
    pub ies_angle_scale: f64,
    /// `inputs:shaping:ies:normalize`.
    pub ies_normalize: bool,
}

impl Default for ShapingInputs {
    fn default() -> ShapingInputs {
        ShapingInputs {
            focus: 0.0,
            focus_tint: DVec3::ZERO,
            cone_angle_deg: 90.0,
            cone_softness: 0.0,
            ies_file: None,
            ies_angle_scale: 0.0,
            ies_normalize: false,
        }
    }
}

/// `ShadowAPI` inputs. `Default` = schema defaults: enabled, black, distance −1, falloff −1,
/// falloffGamma 1. `applied` says whether the API was applied (the values are defaults if not).
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowInputs {
    /// Whether `ShadowAPI` is in the prim's `apiSchemas`.
    pub applied: bool,
    /// `inputs:shadow:enable`.
    pub enable: bool,
    /// `inputs:shadow:color`.
    pub color: DVec3,
    /// `inputs:shadow:distance` (−1 = unlimited).
    pub distance: f64,
    /// `inputs:shadow:falloff` (−1 = none).
    pub falloff: f64,
    /// `inputs:shadow:falloffGamma`.
    pub falloff_gamma: f64,
}

impl Default for ShadowInputs {
    fn default() -> ShadowInputs {
        ShadowInputs {
            applied: false,
            enable: true,
            color: DVec3::ZERO,
            distance: -1.0,
            falloff: -1.0,
            falloff_gamma: 1.0,
        }
    }
}

/// `DomeLight_1.poleAxis` (and `DomeLight`, which is always `Scene`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoleAxis {
    /// `"scene"`: the stage's up axis.
    Scene,
    /// `"Y"`.
    Y,
    /// `"Z"`: the latlong frame rotated +90° about X.
    Z,
}

/// A light of the scene, in plain data: everything a renderer needs, nothing from `openusd`.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// The prim path.
    pub path: String,
    /// The prim type as authored (`"DomeLight_1"`, `"Mesh"` for a `MeshLightAPI` mesh…).
    pub type_name: String,
    /// The light family.
    pub kind: LightKind,
    /// Geometric inputs in light space (`inputs:width`, `inputs:radius`, …; local-space
    /// triangles for mesh lights), schema defaults when unauthored.
    pub shape: LightShape,
    /// Light-to-world transform (glam column form; see `lux_math::usd_matrix`).
    pub light_to_world: DMat4,
    /// `LightAPI` emission inputs with schema defaults (intensity 1, distant 50000, …).
    pub params: LightParams,
    /// `inputs:diffuse` (default 1).
    pub diffuse: f64,
    /// `inputs:specular` (default 1).
    pub specular: f64,
    /// `ShapingAPI` inputs, only when the API is applied.
    pub shaping: Option<ShapingInputs>,
    /// `ShadowAPI` inputs.
    pub shadow: ShadowInputs,
    /// The custom `inputs:visibility:camera` (default false): whether a camera ray sees the
    /// light's surface (RectLight in the reference).
    pub visible_to_camera: bool,
    /// `inputs:texture:file` (RectLight, DomeLight).
    pub texture: Option<AssetRef>,
    /// `inputs:texture:format` (DomeLight; default `automatic`).
    pub texture_format: DomeTextureFormat,
    /// `poleAxis` (DomeLight_1; `Scene` otherwise).
    pub pole_axis: PoleAxis,
    /// `treatAsPoint` (SphereLight).
    pub treat_as_point: bool,
    /// `treatAsLine` (CylinderLight).
    pub treat_as_line: bool,
    /// `portals` targets (DomeLight).
    pub portals: Vec<String>,
    /// `light:materialSyncMode` (MeshLightAPI default `materialGlowTintsLight`, else
    /// `noMaterialResponse`).
    pub material_sync_mode: MaterialSyncMode,
    /// The prim's applied API schemas as composed.
    pub api_schemas: Vec<String>,
    /// Physical light units ([`PhysicalLight`]), when a Photometric*/Radiometric* light API or
    /// `PhysicalLightIlluminantAPI` is applied.
    pub physical: Option<PhysicalLight>,
    /// LTESpectralAPI `wavelength:emission` (values and/or `illuminantPreset`), if authored.
    pub emission_spectrum: Option<SpectralAttribute>,
    /// LightAPI `collection:lightLink` / `collection:shadowLink` membership ([`Linking`];
    /// both [`crate::Membership::All`] unless authored).
    pub linking: Linking,
}

/// `DomeLight.inputs:texture:format`: how the texture maps to directions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DomeTextureFormat {
    /// `automatic` (default): latlong for the 2:1 textures lux reads.
    #[default]
    Automatic,
    /// `latlong`.
    Latlong,
    /// `mirroredBall`.
    MirroredBall,
    /// `angular`.
    Angular,
    /// `cubeMapVerticalCross`.
    CubeMapVerticalCross,
}

impl DomeTextureFormat {
    /// The schema token.
    pub fn token(self) -> &'static str {
        match self {
            DomeTextureFormat::Automatic => "automatic",
            DomeTextureFormat::Latlong => "latlong",
            DomeTextureFormat::MirroredBall => "mirroredBall",
            DomeTextureFormat::Angular => "angular",
            DomeTextureFormat::CubeMapVerticalCross => "cubeMapVerticalCross",
        }
    }

    /// The schema token's format; `None` for an unknown token.
    pub fn parse(token: &str) -> Option<DomeTextureFormat> {
        Some(match token {
            "automatic" => DomeTextureFormat::Automatic,
            "latlong" => DomeTextureFormat::Latlong,
            "mirroredBall" => DomeTextureFormat::MirroredBall,
            "angular" => DomeTextureFormat::Angular,
            "cubeMapVerticalCross" => DomeTextureFormat::CubeMapVerticalCross,
            _ => return None,
        })
    }
}

/// `light:materialSyncMode` (geometry-lights proposal, `MeshLightAPI` / `VolumeLightAPI`): how
/// the geometry's material and the light's emission relate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialSyncMode {
    /// `materialGlowTintsLight` (MeshLightAPI's default): the material's emission tints the
    /// light's.
    MaterialGlowTintsLight,
    /// `independent`: the light emits as authored; the material shades independently.
    Independent,
    /// `noMaterialResponse` (the default of other lights): the geometry has no material
    /// response of its own.
    NoMaterialResponse,
}

impl MaterialSyncMode {
    /// The schema token.
    pub fn token(self) -> &'static str {
        match self {
            MaterialSyncMode::MaterialGlowTintsLight => "materialGlowTintsLight",
            MaterialSyncMode::Independent => "independent",
            MaterialSyncMode::NoMaterialResponse => "noMaterialResponse",
        }
    }

    /// The schema token's mode; `None` for an unknown token.
    pub fn parse(token: &str) -> Option<MaterialSyncMode> {
        Some(match token {
            "materialGlowTintsLight" => MaterialSyncMode::MaterialGlowTintsLight,
            "independent" => MaterialSyncMode::Independent,
            "noMaterialResponse" => MaterialSyncMode::NoMaterialResponse,
            _ => return None,
        })
    }
}

impl Light {
    /// A light with every input at its schema default (LightAPI, no ShapingAPI, ShadowAPI
    /// not applied, invisible to the camera), for scenes built in code rather than loaded.
    pub fn with_defaults(
        path: impl Into<String>,
        shape: LightShape,
        light_to_world: DMat4,
    ) -> Light {
        let kind = shape.kind();
        Light {
            path: path.into(),
            type_name: kind.usd_type_name().to_owned(),
            kind,
            shape,
            light_to_world,
            params: LightParams::defaults_for(kind),
            diffuse: 1.0,
            specular: 1.0,
            shaping: None,
            shadow: ShadowInputs::default(),
            visible_to_camera: false,
            texture: None,
            texture_format: DomeTextureFormat::Automatic,
            pole_axis: PoleAxis::Scene,
            treat_as_point: false,
            treat_as_line: false,
            portals: Vec::new(),
            material_sync_mode: if kind == LightKind::Mesh {
                MaterialSyncMode::MaterialGlowTintsLight
            } else {
                MaterialSyncMode::NoMaterialResponse
            },
            api_schemas: Vec::new(),
            physical: None,
            emission_spectrum: None,
            linking: Linking::default(),
        }
    }

    /// World-space position: the image of the local origin.
    pub fn position(&self) -> DVec3 {
        self.light_to_world.transform_point3(DVec3::ZERO)
    }

    /// World-space emission axis: the image of local −Z, normalised (zero if degenerate).
    pub fn axis(&self) -> DVec3 {
        self.light_to_world
            .transform_vector3(DVec3::NEG_Z)
            .normalize_or_zero()
    }
}

/// LightAPI inputs that UsdLux before 21.05 authored without the `inputs:` prefix.
const LEGACY_INPUTS: [&str; 14] = [
    "intensity",
    "exposure",
    "color",
    "diffuse",
    "specular",
    "normalize",
    "enableColorTemperature",
    "colorTemperature",
    "radius",
    "width",
    "height",
    "length",
    "angle",
    "texture:file",
];

/// One warning each for what a light authors that lux does not honour yet: light filters
/// (`light:filters`), and pre-21.05 inputs without the `inputs:` prefix (usd-core ignores those
/// too; the schema defaults are used). Light and shadow linking are read by
/// [`crate::linking::read_linking`].
fn warn_unsupported_authoring(
    r: &mut Reader<'_>,
    prim: &Prim,
    names: &[openusd::tf::Token],
) -> Result<(), LoadError> {
    if !r.targets(prim, "light:filters")?.is_empty() {
        r.warn(
            prim,
            WarningKind::Unsupported,
            "light:filters are not supported yet: ignored",
        );
    }
    let legacy: Vec<&str> = names
        .iter()
        .map(|n| n.as_str())
        .filter(|n| {
            LEGACY_INPUTS.contains(n) || n.starts_with("shaping:") || n.starts_with("shadow:")
        })
        .collect();
    if !legacy.is_empty() {
        r.warn(
            prim,
            WarningKind::Ignored,
            format!(
                "{} authored without the inputs: prefix (UsdLux before 21.05); ignored as \
                 usd-core does, the schema defaults are used",
                legacy.join(", ")
            ),
        );
    }
    Ok(())
}

/// The light kind of a concrete light prim type, `None` for anything else.
pub fn kind_of_type(type_name: &str) -> Option<LightKind> {
    Some(match type_name {
        "DistantLight" => LightKind::Distant,
        "DiskLight" => LightKind::Disk,
        "RectLight" => LightKind::Rect,
        "SphereLight" => LightKind::Sphere,
        "CylinderLight" => LightKind::Cylinder,
        "DomeLight" | "DomeLight_1" => LightKind::Dome,
        "PortalLight" => LightKind::Portal,
        _ => return None,
    })
}

/// Light prim types lux recognises but does not render.
pub fn is_unsupported_light_type(type_name: &str) -> bool {
    matches!(type_name, "PluginLight" | "GeometryLight")
}

/// Reads a light prim. `mesh_triangles` supplies local-space triangles for `MeshLightAPI` gprims.
pub fn read_light(
    r: &mut Reader<'_>,
    prim: &Prim,
    type_name: &str,
    kind: LightKind,
    light_to_world: DMat4,
    api_schemas: &[String],
    mesh_triangles: Option<Vec<[DVec3; 3]>>,
) -> Result<Light, LoadError> {
    let d = LightParams::defaults_for(kind);
    let params = LightParams {
        intensity: r.f64_or(prim, "inputs:intensity", d.intensity)?,
        exposure: r.f64_or(prim, "inputs:exposure", d.exposure)?,
        color: r.vec3_or(prim, "inputs:color", d.color)?,
        enable_color_temperature: r.bool_or(
            prim,
            "inputs:enableColorTemperature",
            d.enable_color_temperature,
        )?,
        color_temperature: r.f64_or(prim, "inputs:colorTemperature", d.color_temperature)?,
        normalize: r.bool_or(prim, "inputs:normalize", d.normalize)?,
    };
    let shape = match LightShape::default_for(kind) {
        LightShape::Distant { angle_deg } => LightShape::Distant {
            angle_deg: r.f64_or(prim, "inputs:angle", angle_deg)?,
        },
        LightShape::Dome => LightShape::Dome,
        LightShape::Portal { width, height } => LightShape::Portal {
            width: r.size_or(prim, "inputs:width", width)?,
            height: r.size_or(prim, "inputs:height", height)?,
        },
        LightShape::Rect { width, height } => LightShape::Rect {
            width: r.size_or(prim, "inputs:width", width)?,
            height: r.size_or(prim, "inputs:height", height)?,
        },
        LightShape::Disk { radius } => LightShape::Disk {
            radius: r.size_or(prim, "inputs:radius", radius)?,
        },
        LightShape::Sphere { radius } => LightShape::Sphere {
            radius: r.size_or(prim, "inputs:radius", radius)?,
        },
        LightShape::Cylinder { radius, length } => LightShape::Cylinder {
            radius: r.size_or(prim, "inputs:radius", radius)?,
            length: r.size_or(prim, "inputs:length", length)?,
        },
        LightShape::Mesh { .. } => LightShape::Mesh {
            triangles: mesh_triangles.unwrap_or_default(),
        },
    };
    let has_api = |n: &str| api_schemas.iter().any(|a| a == n);
    let shaping = if has_api("ShapingAPI") {
        let sd = ShapingInputs::default();
        let ies_file = r.asset(prim, "inputs:shaping:ies:file")?;
        if let Some(a) = &ies_file
            && a.resolved.is_none()
        {
            r.warn(
                prim,
                WarningKind::UnresolvedAsset,
                format!("IES file @{}@ does not resolve to a file", a.authored),
            );
        }
        Some(ShapingInputs {
            focus: r.f64_or(prim, "inputs:shaping:focus", sd.focus)?,
            focus_tint: r.vec3_or(prim, "inputs:shaping:focusTint", sd.focus_tint)?,
            cone_angle_deg: r.f64_or(prim, "inputs:shaping:cone:angle", sd.cone_angle_deg)?,
            cone_softness: r.f64_or(prim, "inputs:shaping:cone:softness", sd.cone_softness)?,
            ies_file,
            ies_angle_scale: r.f64_or(prim, "inputs:shaping:ies:angleScale", sd.ies_angle_scale)?,
            ies_normalize: r.bool_or(prim, "inputs:shaping:ies:normalize", sd.ies_normalize)?,
        })
    } else {
        None
    };
    let shadow = if has_api("ShadowAPI") {
        let s = ShadowInputs::default();
        ShadowInputs {
            applied: true,
            enable: r.bool_or(prim, "inputs:shadow:enable", s.enable)?,
            color: r.vec3_or(prim, "inputs:shadow:color", s.color)?,
            distance: r.f64_or(prim, "inputs:shadow:distance", s.distance)?,
            falloff: r.f64_or(prim, "inputs:shadow:falloff", s.falloff)?,
            falloff_gamma: r.f64_or(prim, "inputs:shadow:falloffGamma", s.falloff_gamma)?,
        }
    } else {
        ShadowInputs::default()
    };
    let names = prim.property_names().map_err(|e| r.usd_error(prim, e))?;
    let shaping_authored = names
        .iter()
        .any(|n| n.as_str().starts_with("inputs:shaping:"));
    let physical = crate::spectral::read_physical_light(r, prim, api_schemas)?;
    let emission_spectrum = crate::spectral::read_emission(r, prim)?;
    warn_unsupported_authoring(r, prim, &names)?;
    let linking = crate::linking::read_linking(r, prim)?;
    if shaping.is_none() && shaping_authored {
        r.warn(
            prim,
            WarningKind::ShapingNotApplied,
            "inputs:shaping:* authored but ShapingAPI is not applied: ignored",
        );
    }
    let texture = if matches!(kind, LightKind::Rect | LightKind::Dome) {
        let t = r.asset(prim, "inputs:texture:file")?;
        if let Some(a) = &t
            && a.resolved.is_none()
        {
            r.warn(
                prim,
                WarningKind::UnresolvedAsset,
                format!("texture @{}@ does not resolve to a file", a.authored),
            );
        }
        t
    } else {
        None
    };
    let pole_axis = if type_name == "DomeLight_1" {
        match r.text(prim, "poleAxis")?.as_deref() {
            None | Some("scene") => PoleAxis::Scene,
            Some("Y") => PoleAxis::Y,
            Some("Z") => PoleAxis::Z,
            Some(other) => {
                r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("poleAxis {other:?} is not scene/Y/Z; using scene"),
                );
                PoleAxis::Scene
            }
        }
    } else {
        PoleAxis::Scene
    };
    let default_sync = if kind == LightKind::Mesh {
        MaterialSyncMode::MaterialGlowTintsLight
    } else {
        MaterialSyncMode::NoMaterialResponse
    };
    let texture_format = match r.text(prim, "inputs:texture:format")? {
        None => DomeTextureFormat::Automatic,
        Some(t) => DomeTextureFormat::parse(&t).unwrap_or_else(|| {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!("inputs:texture:format {t:?} is not a DomeLight format; using automatic"),
            );
            DomeTextureFormat::Automatic
        }),
    };
    let material_sync_mode = match r.text(prim, "light:materialSyncMode")? {
        None => default_sync,
        Some(t) => MaterialSyncMode::parse(&t).unwrap_or_else(|| {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "light:materialSyncMode {t:?} is not materialGlowTintsLight, independent or \
                     noMaterialResponse; using the default"
                ),
            );
            default_sync
        }),
    };
    Ok(Light {
        path: prim.path().to_string(),
        type_name: type_name.to_owned(),
        kind,
        shape,
        light_to_world,
        params,
        diffuse: r.f64_or(prim, "inputs:diffuse", 1.0)?,
        specular: r.f64_or(prim, "inputs:specular", 1.0)?,
        shaping,
        shadow,
        visible_to_camera: r.bool_or(prim, "inputs:visibility:camera", false)?,
        texture,
        texture_format,
        pole_axis,
        treat_as_point: r.bool_or(prim, "treatAsPoint", false)?,
        treat_as_line: r.bool_or(prim, "treatAsLine", false)?,
        portals: if kind == LightKind::Dome {
            r.targets(prim, "portals")?
        } else {
            Vec::new()
        },
        material_sync_mode,
        api_schemas: api_schemas.to_vec(),
        physical,
        emission_spectrum,
        linking,
    })
}
