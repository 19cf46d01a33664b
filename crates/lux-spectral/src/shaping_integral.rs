//! The shaping integral G of an area light: flux per unit area and unit luminance.

use glam::DVec3;
use lux_math::LightKind;

use crate::error::SpectralError;

/// The emitting surface of an area light kind, in the light's local frame: the three forms of
/// G below.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Emitter {
    /// RectLight / DiskLight: one-sided, normal −Z.
    Flat,
    /// SphereLight: every point emits over its outward hemisphere.
    Sphere,
    /// CylinderLight: lateral surface around the local X axis, no caps.
    Cylinder,
}

impl Emitter {
    /// The emitter of `kind`; a typed error for the kinds G is not defined for (distant, dome,
    /// portal, and mesh lights, whose triangles face every way).
    fn of(kind: LightKind) -> Result<Emitter, SpectralError> {
        match kind {
            LightKind::Rect | LightKind::Disk => Ok(Emitter::Flat),
            LightKind::Sphere => Ok(Emitter::Sphere),
            LightKind::Cylinder => Ok(Emitter::Cylinder),
            LightKind::Distant | LightKind::Dome | LightKind::Portal | LightKind::Mesh => {
                Err(SpectralError::NotAnAreaEmitter {
                    light: kind.usd_type_name(),
                })
            }
        }
    }
}

/// G = (1/A) ∫_A ∫_{H(n(x))} f(ω) (ω·n(x)) dω dA: the shaping-weighted projected solid angle per
/// unit area, so that the flux of an area light of luminance L (nits) and world area A is
/// **Φ = L · A · G** (lm; W with radiance). f is the ShapingAPI factor (focus, cone, IES; 1 when
/// unshaped), a function of the emission direction only.
///
/// Exchanging the integrals, G = (1/A) ∫_{S²} f(ω) A⊥(ω) dω with A⊥ the projected area of the
/// emitting surface seen from ω, which gives for each area light kind (local frame, emission
/// around −Z; [`LightKind`]s without such a surface — distant, dome, portal, mesh — are a
/// [`SpectralError::NotAnAreaEmitter`]):
/// - flat (rect, disk): G = ∫_{ω·(−Z) > 0} f(ω) cos θ dω  — π when unshaped;
/// - sphere: A⊥ = πr² for every ω, so G = ¼ ∫_{S²} f(ω) dω  — π when unshaped;
/// - cylinder (axis X, no caps): A⊥ = 2 r ℓ √(1 − ω_x²), so G = (1/π) ∫_{S²} f(ω) √(1 − ω_x²) dω
///   — π when unshaped.
///
/// [`ShapingIntegral::from_integrals`] takes the integrals of the factor from the caller (lux's
/// renderer computes them with lux-shaping's `Shaping::emitter_integral`, on which this crate does not depend);
/// [`ShapingIntegral::integrate`] evaluates any factor by quadrature.
/// For sphere and cylinder the forms assume a similarity transform (no non-uniform scale).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapingIntegral(f64);

impl ShapingIntegral {
    /// An unshaped emitter of any shape: G = π.
    pub const UNSHAPED: ShapingIntegral = ShapingIntegral(std::f64::consts::PI);

    /// G directly; must be finite and > 0 (a light that emits nothing cannot reach a power).
    pub fn new(g: f64) -> Result<Self, SpectralError> {
        if g.is_finite() && g > 0.0 {
            Ok(ShapingIntegral(g))
        } else {
            Err(SpectralError::InvalidValue {
                attribute: "shaping integral".to_owned(),
                value: g,
                expected: "a finite value > 0 (π when unshaped)",
            })
        }
    }

    /// Flat emitter: from ∫ f(ω) cos θ dω over the emitting hemisphere (θ from −Z).
    pub fn flat(cosine_weighted_hemisphere: f64) -> Result<Self, SpectralError> {
        Self::new(cosine_weighted_hemisphere)
    }

    /// Sphere: from ∫_{S²} f(ω) dω.
    pub fn sphere(spherical_integral: f64) -> Result<Self, SpectralError> {
        Self::new(spherical_integral / 4.0)
    }

    /// Cylinder (axis X): from ∫_{S²} f(ω) √(1 − ω_x²) dω.
    pub fn cylinder(axis_sine_weighted_integral: f64) -> Result<Self, SpectralError> {
        Self::new(axis_sine_weighted_integral / std::f64::consts::PI)
    }

    /// G by deterministic midpoint quadrature over the sphere of directions (n × 2n cells
    /// uniform in cos θ and φ, n clamped to [4, 4096]) of a shaping factor `f(ω)` given in the
    /// light's local frame, for the emitter of `kind` (an error for a kind without one). For when
    /// no closed form is at hand.
    pub fn integrate(
        kind: LightKind,
        f: impl Fn(DVec3) -> f64,
        n: usize,
    ) -> Result<Self, SpectralError> {
        let shape = Emitter::of(kind)?;
        let n = n.clamp(4, 4096);
        let (nu, nphi) = (n, 2 * n);
        let dw = (2.0 / nu as f64) * (2.0 * std::f64::consts::PI / nphi as f64);
        let mut sum = 0.0;
        for i in 0..nu {
            let z = -1.0 + (i as f64 + 0.5) * 2.0 / nu as f64;
            let s = (1.0 - z * z).max(0.0).sqrt();
            for j in 0..nphi {
                let phi = (j as f64 + 0.5) * 2.0 * std::f64::consts::PI / nphi as f64;
                let w = DVec3::new(s * phi.cos(), s * phi.sin(), z);
                let weight = match shape {
                    Emitter::Flat => (-w.z).max(0.0),
                    Emitter::Sphere => 0.25,
                    Emitter::Cylinder => (1.0 - w.x * w.x).max(0.0).sqrt() / std::f64::consts::PI,
                };
                if weight > 0.0 {
                    sum += f(w) * weight;
                }
            }
        }
        Self::new(sum * dw)
    }

    /// G of a light shaped by the UsdLux ShapingAPI (focus, focusTint, cone, softness, IES),
    /// from the per-channel integrals of its RGB shaping factor f, which the caller computes
    /// with its shaping model (lux-shaping's `Shaping` in lux's renderer), for the emitter of
    /// `kind` (an error for a kind without one):
    /// (lux-shaping's `Shaping::emitter_integral(kind)` gives exactly these):
    /// - flat (RectLight, DiskLight): I_c = ∫_{emitting hemisphere} f_c(ω) cos θ dω, and G_c = I_c
    ///   (`Shaping::integral_cos_hemisphere`);
    /// - SphereLight: I_c = ∫_{S²} f_c(ω) dω, and G_c = ¼ I_c (`Shaping::integral_sphere`);
    /// - CylinderLight: I_c = ∫_{S²} f_c(ω) √(1 − ω_x²) dω, and G_c = I_c / π
    ///   (`Shaping::integral_weighted` with the weight √(1 − ω_x²)).
    ///
    /// `integrals` is `None` for an unshaped light (f ≡ 1, no ShapingAPI or an identity one),
    /// which gives exactly π. The factor is RGB (focusTint); its channels are weighted by the
    /// luminance of the light's colour of one nit, `rgb_per_nit` (Rec.709 luminance 1, see
    /// [`crate::ResolvedIlluminant`]): G = Σ_c Y_c·rgb_c·G_c, so that Φ = L·A·G holds for the
    /// luminous flux of the tinted emission.
    pub fn from_integrals(
        kind: LightKind,
        integrals: Option<DVec3>,
        rgb_per_nit: DVec3,
    ) -> Result<Self, SpectralError> {
        let shape = Emitter::of(kind)?;
        let Some(integrals) = integrals else {
            return Ok(Self::UNSHAPED);
        };
        // Σ_c (Y_c·rgb_c)·I_c, the luminance weights scaled by the colour first: the order of
        // the operations the renders were made with (`lux_math::luminance(rgb · I)`, the same
        // sum grouped Y_c·(rgb_c·I_c), can differ in the last bit)
        let weighted = (lux_math::REC709_LUMINANCE * rgb_per_nit).dot(integrals);
        match shape {
            Emitter::Flat => Self::flat(weighted),
            Emitter::Sphere => Self::sphere(weighted),
            Emitter::Cylinder => Self::cylinder(weighted),
        }
    }

    /// G of a **textured** area light (a RectLight's `inputs:texture:file`), shaped as in
    /// [`from_integrals`](Self::from_integrals): the texture multiplies the emitted RGB per
    /// texel, so the luminous flux is Φ = L·A·Σ_c Y_c·rgb_c·t_c·G_c, where `texture_mean` = t is
    /// the area-weighted mean of the texture's linear RGB over the light's surface (for a
    /// texture mapped linearly onto the rect, the mean of its texels). The returned value is
    /// that sum, so that Φ = L·A·G still holds and [`crate::emitted`] needs no texture of its
    /// own: a texture of mean luminance ½ doubles the converted luminance.
    ///
    /// `texture_mean` = (1, 1, 1) is exactly [`from_integrals`](Self::from_integrals); a black
    /// (or negative, or non-finite) mean is an error, since no luminance gives the authored
    /// power.
    pub fn from_integrals_textured(
        kind: LightKind,
        integrals: Option<DVec3>,
        rgb_per_nit: DVec3,
        texture_mean: DVec3,
    ) -> Result<Self, SpectralError> {
        Emitter::of(kind)?;
        if texture_mean == DVec3::ONE {
            return Self::from_integrals(kind, integrals, rgb_per_nit);
        }
        if !texture_mean.is_finite() || texture_mean.min_element() < 0.0 {
            return Err(SpectralError::InvalidValue {
                attribute: "inputs:texture:file".to_owned(),
                value: texture_mean.min_element(),
                expected: "a texture with finite, non-negative texels",
            });
        }
        let tinted = rgb_per_nit * texture_mean;
        if integrals.is_none() {
            // G_c = π in every channel
            let y = lux_math::luminance(tinted);
            return Self::new(Self::UNSHAPED.value() * y);
        }
        Self::from_integrals(kind, integrals, tinted)
    }

    /// The value of G, sr.
    pub fn value(self) -> f64 {
        self.0
    }
}

impl Default for ShapingIntegral {
    fn default() -> Self {
        Self::UNSHAPED
    }
}
