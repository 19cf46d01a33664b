//! The Sellmeier dispersion equation (`iorInterpolation = "sellmeier"`).

use crate::error::SpectralError;

/// Sellmeier coefficients: `wavelength:ior = [(B1, C1), (B2, C2), (B3, C3)]` with C in µm², for
/// `n²(λ) = 1 + Σᵢ Bᵢ λ² / (λ² − Cᵢ)`, λ in µm. One to three terms (missing terms are zero).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sellmeier {
    /// B coefficients (dimensionless).
    pub b: [f64; 3],
    /// C coefficients, µm².
    pub c: [f64; 3],
}

impl Sellmeier {
    /// Schott N-BK7 (Schott data sheet): n(587.56 nm) = 1.5168.
    pub const BK7: Sellmeier = Sellmeier {
        b: [1.039_612_12, 0.231_792_344, 1.010_469_45],
        c: [6.000_698_67e-3, 2.001_791_44e-2, 1.035_606_53e2],
    };

    /// Validate coefficients given as (B, C) pairs (C in µm²): the USD `float2[]` as authored
    /// (`[f32; 2]`) or `[f64; 2]`; 1–3 pairs, all finite; errors name `wavelength:ior`.
    pub fn from_pairs<T: Copy + Into<f64>>(pairs: &[[T; 2]]) -> Result<Self, SpectralError> {
        let err = |detail: String| SpectralError::Sellmeier {
            attribute: "wavelength:ior".to_owned(),
            detail,
        };
        if pairs.is_empty() || pairs.len() > 3 {
            return Err(err(format!(
                "{} (B, C) pairs with iorInterpolation = \"sellmeier\", expected 1 to 3",
                pairs.len()
            )));
        }
        let mut s = Sellmeier {
            b: [0.0; 3],
            c: [0.0; 3],
        };
        for (i, p) in pairs.iter().enumerate() {
            let (b, c): (f64, f64) = (p[0].into(), p[1].into());
            if !(b.is_finite() && c.is_finite()) {
                return Err(err(format!(
                    "pair {i}: (B, C) = ({b}, {c}), expected finite numbers"
                )));
            }
            s.b[i] = b;
            s.c[i] = c;
        }
        Ok(s)
    }

    /// n²(λ) at `lambda_nm` (converted to µm); may be ≤ 0 or infinite near an absorption pole.
    pub fn n_squared(&self, lambda_nm: f64) -> f64 {
        let l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
        1.0 + (0..3)
            .map(|i| self.b[i] * l2 / (l2 - self.c[i]))
            .sum::<f64>()
    }

    /// Refractive index n(λ) = √n²(λ); a typed error where n² is not finite and positive.
    pub fn ior(&self, lambda_nm: f64) -> Result<f64, SpectralError> {
        let n2 = self.n_squared(lambda_nm);
        if n2.is_finite() && n2 > 0.0 && lambda_nm.is_finite() && lambda_nm > 0.0 {
            Ok(n2.sqrt())
        } else {
            Err(SpectralError::SellmeierDomain {
                wavelength_nm: lambda_nm,
                n_squared: n2,
            })
        }
    }
}
