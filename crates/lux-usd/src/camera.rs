//! `UsdGeomCamera`, `UsdRenderSettings` and `UsdRenderProduct` as plain data.

use crate::error::LoadError;
use crate::reader::Reader;
use glam::{DMat4, DVec2, DVec4};
use openusd::usd::Prim;

/// `UsdGeomCamera.projection`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// `"perspective"` (default).
    Perspective,
    /// `"orthographic"`.
    Orthographic,
}

/// A camera. Lengths are in the schema's units: apertures and focal length in tenths of a scene
/// unit ("mm" by convention), defaults from UsdGeomCamera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// The prim path.
    pub path: String,
    /// Camera-to-world transform; the camera looks down its local −Z with +Y up.
    pub camera_to_world: DMat4,
    /// `projection`.
    pub projection: Projection,
    /// `focalLength` (default 50).
    pub focal_length: f64,
    /// `horizontalAperture` (default 20.955).
    pub horizontal_aperture: f64,
    /// `verticalAperture` (default 15.2908).
    pub vertical_aperture: f64,
    /// `horizontalApertureOffset` (default 0).
    pub horizontal_aperture_offset: f64,
    /// `verticalApertureOffset` (default 0).
    pub vertical_aperture_offset: f64,
    /// `clippingRange` (near, far), default (1, 1 000 000).
    pub clipping_range: DVec2,
    /// `fStop` (default 0 = pinhole).
    pub f_stop: f64,
    /// `focusDistance` (default 0).
    pub focus_distance: f64,
    /// The photographic exposure terms: `exposure` (stops, default 0), `exposure:iso`
    /// (default 100), `exposure:time` (seconds, default 1), `exposure:fStop` (default 1) and
    /// `exposure:responsivity` (default 1); see [`Camera::linear_exposure_scale`].
    pub exposure: CameraExposure,
}

/// UsdGeomCamera's exposure attributes (schema defaults in `Default`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraExposure {
    /// `exposure`: compensation in stops.
    pub exposure: f64,
    /// `exposure:iso`.
    pub iso: f64,
    /// `exposure:time` in seconds.
    pub time: f64,
    /// `exposure:fStop`.
    pub f_stop: f64,
    /// `exposure:responsivity`.
    pub responsivity: f64,
}

impl Default for CameraExposure {
    fn default() -> CameraExposure {
        CameraExposure {
            exposure: 0.0,
            iso: 100.0,
            time: 1.0,
            f_stop: 1.0,
            responsivity: 1.0,
        }
    }
}

impl Camera {
    /// UsdGeomCamera `ComputeLinearExposureScale`: the factor from scene radiance to image
    /// values, `responsivity · time · (iso / 100) · 2^exposure / fStop²` (1 with every
    /// default); a non-finite or non-positive result is 1.
    pub fn linear_exposure_scale(&self) -> f64 {
        let e = &self.exposure;
        let s =
            e.responsivity * e.time * (e.iso / 100.0) * e.exposure.exp2() / (e.f_stop * e.f_stop);
        if s.is_finite() && s > 0.0 { s } else { 1.0 }
    }

    /// A perspective camera with the UsdGeomCamera defaults (focal length 50, aperture
    /// 20.955 × 15.2908, clipping 1 to 10⁶) at `camera_to_world`, for scenes built in code.
    pub fn with_defaults(path: impl Into<String>, camera_to_world: DMat4) -> Camera {
        Camera {
            path: path.into(),
            camera_to_world,
            projection: Projection::Perspective,
            focal_length: 50.0,
            horizontal_aperture: 20.955,
            vertical_aperture: 15.2908,
            horizontal_aperture_offset: 0.0,
            vertical_aperture_offset: 0.0,
            clipping_range: DVec2::new(1.0, 1.0e6),
            f_stop: 0.0,
            focus_distance: 0.0,
            exposure: CameraExposure::default(),
        }
    }
}

/// Reads a `Camera` prim.
pub fn read_camera(r: &mut Reader<'_>, prim: &Prim, world: DMat4) -> Result<Camera, LoadError> {
    let projection = match r.text(prim, "projection")?.as_deref() {
        Some("orthographic") => Projection::Orthographic,
        _ => Projection::Perspective,
    };
    Ok(Camera {
        path: prim.path().to_string(),
        camera_to_world: world,
        projection,
        focal_length: r.size_or(prim, "focalLength", 50.0)?,
        horizontal_aperture: r.size_or(prim, "horizontalAperture", 20.955)?,
        vertical_aperture: r.size_or(prim, "verticalAperture", 15.2908)?,
        horizontal_aperture_offset: r.f64_or(prim, "horizontalApertureOffset", 0.0)?,
        vertical_aperture_offset: r.f64_or(prim, "verticalApertureOffset", 0.0)?,
        clipping_range: r
            .vec2(prim, "clippingRange")?
            .filter(|v| v.is_finite())
            .unwrap_or(DVec2::new(1.0, 1.0e6)),
        f_stop: r.f64_or(prim, "fStop", 0.0)?,
        focus_distance: r.f64_or(prim, "focusDistance", 0.0)?,
        exposure: {
            let d = CameraExposure::default();
            CameraExposure {
                exposure: r.f64_or(prim, "exposure", d.exposure)?,
                iso: r.f64_or(prim, "exposure:iso", d.iso)?,
                time: r.f64_or(prim, "exposure:time", d.time)?,
                f_stop: r.f64_or(prim, "exposure:fStop", d.f_stop)?,
                responsivity: r.f64_or(prim, "exposure:responsivity", d.responsivity)?,
            }
        },
    })
}

/// The `UsdRenderSettingsBase` attributes shared by settings and products; `None` = unauthored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderBase {
    /// `camera` relationship target.
    pub camera: Option<String>,
    /// `resolution` (default 1920 × 1080 on settings).
    pub resolution: Option<[u32; 2]>,
    /// `pixelAspectRatio` (default 1).
    pub pixel_aspect_ratio: Option<f64>,
    /// `dataWindowNDC` (xmin, ymin, xmax, ymax), default (0, 0, 1, 1).
    pub data_window_ndc: Option<DVec4>,
}

/// A `RenderProduct` (an output image) of a [`RenderSettings`].
#[derive(Clone, Debug, PartialEq)]
pub struct RenderProduct {
    /// The prim path.
    pub path: String,
    /// `productName` (the output file name), if authored.
    pub product_name: Option<String>,
    /// The product's own overrides of the settings' values.
    pub base: RenderBase,
}

/// A `RenderSettings` prim.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// The prim path.
    pub path: String,
    /// Authored base attributes.
    pub base: RenderBase,
    /// `includedPurposes` (default `["default", "render"]`).
    pub included_purposes: Vec<String>,
    /// The products named by the `products` relationship, in order.
    pub products: Vec<RenderProduct>,
    /// The custom `lux:conformanceProfile` attribute (`"spec"` or `"hdembree"`), as authored:
    /// the stage-level step of the conformance-profile chain (spec README §5).
    pub conformance_profile: Option<String>,
}

impl RenderSettings {
    /// Effective resolution (settings value or 1920 × 1080).
    pub fn resolution(&self) -> [u32; 2] {
        self.base.resolution.unwrap_or([1920, 1080])
    }

    /// Effective pixel aspect ratio (default 1).
    pub fn pixel_aspect_ratio(&self) -> f64 {
        self.base.pixel_aspect_ratio.unwrap_or(1.0)
    }

    /// Effective data window (default the full frame).
    pub fn data_window_ndc(&self) -> DVec4 {
        self.base
            .data_window_ndc
            .unwrap_or(DVec4::new(0.0, 0.0, 1.0, 1.0))
    }
}

/// Reads the `UsdRenderSettingsBase` attributes of `prim`.
pub fn read_render_base(r: &mut Reader<'_>, prim: &Prim) -> Result<RenderBase, LoadError> {
    let resolution = match r.vec2(prim, "resolution")? {
        Some(v) if v.x >= 1.0 && v.y >= 1.0 && v.x <= 65536.0 && v.y <= 65536.0 => {
            Some([v.x as u32, v.y as u32])
        }
        Some(v) => {
            r.warn(
                prim,
                crate::error::WarningKind::InvalidValue,
                format!("resolution {v} outside 1..=65536; ignored"),
            );
            None
        }
        None => None,
    };
    Ok(RenderBase {
        camera: r.targets(prim, "camera")?.into_iter().next(),
        resolution,
        pixel_aspect_ratio: r
            .f64(prim, "pixelAspectRatio")?
            .filter(|x| x.is_finite() && *x > 0.0),
        data_window_ndc: r.vec4(prim, "dataWindowNDC")?.filter(|v| v.is_finite()),
    })
}

/// Reads a `RenderSettings` prim and the products it names.
pub fn read_render_settings(r: &mut Reader<'_>, prim: &Prim) -> Result<RenderSettings, LoadError> {
    let base = read_render_base(r, prim)?;
    let included_purposes = match r.raw_default(prim, "includedPurposes")? {
        Some(openusd::sdf::Value::TokenVec(t)) => t.iter().map(|t| t.as_str().to_owned()).collect(),
        _ => vec!["default".to_owned(), "render".to_owned()],
    };
    let mut products = Vec::new();
    for target in r.targets(prim, "products")? {
        let p = r.stage.prim(target.as_str());
        let base = read_render_base(r, &p)?;
        products.push(RenderProduct {
            path: target.clone(),
            product_name: r.text(&p, "productName")?,
            base,
        });
    }
    let conformance_profile = r.text(prim, "lux:conformanceProfile")?;
    Ok(RenderSettings {
        path: prim.path().to_string(),
        base,
        included_purposes,
        products,
        conformance_profile,
    })
}
