//! Physical light units and the LTESpectralAPI, read into lux-spectral's types at load time.
//!
//! - `PhysicalLightIlluminantAPI` (physical-light-units proposal §3): `physical:illuminant`
//!   (`white` | `blackbody` | `custom`) and `physical:customIlluminant` (`float2[]` pairs of
//!   wavelength, relative power).
//! - `Photometric{Area,Dome,Distant}LightAPI` / `Radiometric{…}LightAPI` (§4):
//!   `photometric:power` (lm, default 1600), `radiometric:power` (W, default 1600/683),
//!   `photometric:illuminance` (lx, default 100 000), `radiometric:irradiance` (W/m², default
//!   100 000/683) — the applied API decides which; its schema default when unauthored.
//! - LTESpectralAPI (spectral-API proposal): `wavelength:emission` on lights,
//!   `wavelength:reflectance`, `wavelength:ior` and `ior` on surfaces, as `float2[]`
//!   (wavelength, value) pairs with the attribute metadata `unitForWavelength`,
//!   `emissionInterpolation` / `iorInterpolation` and `illuminantPreset`.
//!
//! Every attribute may be authored with or without the `inputs:` prefix (the `inputs:` form
//! wins). A token lux-spectral does not know (an unknown illuminant, interpolation or unit) is
//! a [`WarningKind::InvalidValue`] warning naming the prim and attribute, and the schema
//! default is used; the values themselves (sorted wavelengths, reflectance ≤ 1…) are validated
//! by lux-spectral when the renderer converts them.

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use crate::value;
use lux_spectral::{
    Illuminant, IlluminantKind, Interpolation, IorAttribute, IorInterpolation, PhysicalQuantity,
    SpectralAttribute, WavelengthUnit,
};
use openusd::usd::Prim;

/// The physical-light-unit inputs of a light: present when a Photometric*/Radiometric* light
/// API or `PhysicalLightIlluminantAPI` is applied.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalLight {
    /// The quantity the applied Photometric*/Radiometric* API authors (its schema default when
    /// unauthored); `None` when only `PhysicalLightIlluminantAPI` is applied.
    pub quantity: Option<PhysicalQuantity>,
    /// `physical:illuminant` (default `white`).
    pub illuminant: IlluminantKind,
    /// `physical:customIlluminant` pairs (wavelength, relative power).
    pub custom_illuminant: Vec<[f32; 2]>,
}

/// LTESpectralAPI inputs of a surface (a gprim, or its material's surface shader).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceSpectral {
    /// `wavelength:reflectance` (replaces `diffuseColor` when present).
    pub reflectance: Option<SpectralAttribute>,
    /// `wavelength:ior` with `iorInterpolation` (including `sellmeier`).
    pub ior: Option<IorAttribute>,
    /// The scalar `ior`.
    pub scalar_ior: Option<f64>,
}

impl SurfaceSpectral {
    /// Nothing authored.
    pub fn is_empty(&self) -> bool {
        self.reflectance.is_none() && self.ior.is_none() && self.scalar_ior.is_none()
    }
}

/// A physical-quantity API: its name, the attribute it authors, the quantity it makes and the
/// attribute's schema default.
type QuantityApi = (&'static str, &'static str, fn(f64) -> PhysicalQuantity, f64);

/// The physical-quantity APIs in the order the loader looks for them.
const QUANTITY_APIS: [QuantityApi; 6] = [
    (
        "PhotometricAreaLightAPI",
        "photometric:power",
        PhysicalQuantity::PhotometricPower,
        PhysicalQuantity::DEFAULT_PHOTOMETRIC_POWER,
    ),
    (
        "RadiometricAreaLightAPI",
        "radiometric:power",
        PhysicalQuantity::RadiometricPower,
        PhysicalQuantity::DEFAULT_RADIOMETRIC_POWER,
    ),
    (
        "PhotometricDomeLightAPI",
        "photometric:illuminance",
        PhysicalQuantity::PhotometricIlluminance,
        PhysicalQuantity::DEFAULT_PHOTOMETRIC_ILLUMINANCE,
    ),
    (
        "RadiometricDomeLightAPI",
        "radiometric:irradiance",
        PhysicalQuantity::RadiometricIrradiance,
        PhysicalQuantity::DEFAULT_RADIOMETRIC_IRRADIANCE,
    ),
    (
        "PhotometricDistantLightAPI",
        "photometric:illuminance",
        PhysicalQuantity::PhotometricIlluminance,
        PhysicalQuantity::DEFAULT_PHOTOMETRIC_ILLUMINANCE,
    ),
    (
        "RadiometricDistantLightAPI",
        "radiometric:irradiance",
        PhysicalQuantity::RadiometricIrradiance,
        PhysicalQuantity::DEFAULT_RADIOMETRIC_IRRADIANCE,
    ),
];

/// The authored name of attribute `name`: `inputs:name` when that has a value or metadata,
/// else `name` when it does, else `None`.
fn authored_name(r: &Reader<'_>, prim: &Prim, name: &str) -> Result<Option<String>, LoadError> {
    for n in [format!("inputs:{name}"), name.to_owned()] {
        if r.raw(prim, &n)?.is_some() || r.metadata_text(prim, &n, "illuminantPreset").is_some() {
            return Ok(Some(n));
        }
    }
    Ok(None)
}

/// `(wavelength, value)` pairs from a `float2[]` (or an even-length number array).
fn pairs(r: &mut Reader<'_>, prim: &Prim, name: &str) -> Result<Option<Vec<[f32; 2]>>, LoadError> {
    let Some(v) = r.raw(prim, name)? else {
        return Ok(None);
    };
    if let Some(a) = value::as_vec2_array(&v) {
        return Ok(Some(a.iter().map(|p| [p.x as f32, p.y as f32]).collect()));
    }
    if let Some(a) = value::as_f64_array(&v).filter(|a| a.len() % 2 == 0) {
        return Ok(Some(
            a.chunks_exact(2)
                .map(|c| [c[0] as f32, c[1] as f32])
                .collect(),
        ));
    }
    r.warn(
        prim,
        WarningKind::InvalidValue,
        format!(
            "{name}: expected float2[] (wavelength, value) pairs, found {}; ignored",
            value::type_label(&v)
        ),
    );
    Ok(None)
}

/// A token parsed by `parse`, or `default` with a warning naming the attribute.
fn token<T>(
    r: &mut Reader<'_>,
    prim: &Prim,
    what: &str,
    text: Option<String>,
    parse: impl Fn(&str) -> Result<T, lux_spectral::SpectralError>,
    default: Option<T>,
) -> Option<T> {
    let t = text?;
    match parse(&t) {
        Ok(v) => Some(v),
        Err(e) => {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!("{what}: {e}; using the default"),
            );
            default
        }
    }
}

/// The physical-light-unit inputs of a light with API schemas `api` (see the module docs).
pub fn read_physical_light(
    r: &mut Reader<'_>,
    prim: &Prim,
    api: &[String],
) -> Result<Option<PhysicalLight>, LoadError> {
    let has = |n: &str| api.iter().any(|a| a == n);
    let mut quantity = None;
    for (name, attr, make, default) in QUANTITY_APIS {
        if has(name) {
            let x = match authored_name(r, prim, attr)? {
                Some(n) => r.f64_or(prim, &n, default)?,
                None => default,
            };
            quantity = Some(make(x));
            break;
        }
    }
    if quantity.is_none() && !has("PhysicalLightIlluminantAPI") {
        return Ok(None);
    }
    let illuminant = match authored_name(r, prim, "physical:illuminant")? {
        Some(n) => {
            let text = r.text(prim, &n)?;
            token(
                r,
                prim,
                &n,
                text,
                IlluminantKind::parse,
                Some(IlluminantKind::White),
            )
            .unwrap_or_default()
        }
        None => IlluminantKind::default(),
    };
    let custom_illuminant = match authored_name(r, prim, "physical:customIlluminant")? {
        Some(n) => pairs(r, prim, &n)?.unwrap_or_default(),
        None => Vec::new(),
    };
    Ok(Some(PhysicalLight {
        quantity,
        illuminant,
        custom_illuminant,
    }))
}

/// A `wavelength:*` attribute with its metadata; `None` when neither values nor an
/// `illuminantPreset` are authored. `interpolation_key` names the interpolation metadata
/// (`emissionInterpolation`), if the attribute has one.
fn spectral_attribute(
    r: &mut Reader<'_>,
    prim: &Prim,
    attr: &str,
    interpolation_key: Option<&str>,
) -> Result<Option<SpectralAttribute>, LoadError> {
    let Some(name) = authored_name(r, prim, attr)? else {
        return Ok(None);
    };
    let values = pairs(r, prim, &name)?;
    let preset_text = r.metadata_text(prim, &name, "illuminantPreset");
    if values.is_none() && preset_text.is_none() {
        return Ok(None);
    }
    let unit_text = r.metadata_text(prim, &name, "unitForWavelength");
    let unit_for_wavelength = token(
        r,
        prim,
        &format!("{name} unitForWavelength"),
        unit_text,
        WavelengthUnit::parse,
        None,
    );
    let interpolation = match interpolation_key {
        Some(k) => {
            let t = r.metadata_text(prim, &name, k);
            token(
                r,
                prim,
                &format!("{name} {k}"),
                t,
                |t| Interpolation::parse(t, attr),
                None,
            )
            .unwrap_or_default()
        }
        None => Interpolation::default(),
    };
    let illuminant_preset = token(
        r,
        prim,
        &format!("{name} illuminantPreset"),
        preset_text,
        Illuminant::parse,
        None,
    );
    Ok(Some(SpectralAttribute {
        values: values.unwrap_or_default(),
        unit_for_wavelength,
        interpolation,
        illuminant_preset,
    }))
}

/// A light's `wavelength:emission` (with `emissionInterpolation`), if authored.
pub fn read_emission(
    r: &mut Reader<'_>,
    prim: &Prim,
) -> Result<Option<SpectralAttribute>, LoadError> {
    spectral_attribute(
        r,
        prim,
        "wavelength:emission",
        Some("emissionInterpolation"),
    )
}

/// A surface's LTESpectralAPI inputs (see [`SurfaceSpectral`]).
pub fn read_surface_spectral(
    r: &mut Reader<'_>,
    prim: &Prim,
) -> Result<SurfaceSpectral, LoadError> {
    let reflectance = spectral_attribute(r, prim, "wavelength:reflectance", None)?;
    let ior = match authored_name(r, prim, "wavelength:ior")? {
        None => None,
        Some(name) => match pairs(r, prim, &name)? {
            None => None,
            Some(values) => {
                let unit = r.metadata_text(prim, &name, "unitForWavelength");
                let interp = r.metadata_text(prim, &name, "iorInterpolation");
                Some(IorAttribute {
                    values,
                    unit_for_wavelength: token(
                        r,
                        prim,
                        &format!("{name} unitForWavelength"),
                        unit,
                        WavelengthUnit::parse,
                        None,
                    ),
                    interpolation: token(
                        r,
                        prim,
                        &format!("{name} iorInterpolation"),
                        interp,
                        IorInterpolation::parse,
                        None,
                    )
                    .unwrap_or_default(),
                })
            }
        },
    };
    let scalar_ior = match authored_name(r, prim, "ior")? {
        Some(n) => r.f64(prim, &n)?.filter(|x| x.is_finite()),
        None => None,
    };
    Ok(SurfaceSpectral {
        reflectance,
        ior,
        scalar_ior,
    })
}

/// The stage's `unitForWavelength` metadata (nanometres when unauthored or unknown; an unknown
/// token is reported in `warnings`).
pub fn stage_wavelength_unit(text: Option<&str>) -> Result<WavelengthUnit, String> {
    match text {
        None => Ok(WavelengthUnit::default()),
        Some(t) => WavelengthUnit::parse(t).map_err(|e| format!("stage unitForWavelength: {e}")),
    }
}
