//! Sampled spectra: (wavelength, value) tables with linear, held or cubic interpolation.

use crate::error::{MAX_SAMPLES, SpectrumError};
use crate::interpolation::Interpolation;
use crate::wavelength::WavelengthUnit;

/// A spectrum given by samples at strictly increasing wavelengths (nm), evaluated with an
/// [`Interpolation`] mode and **zero outside** [first wavelength, last wavelength] — the rule the
/// LTESpectralAPI and `physical:customIlluminant` give for emission ranges.
///
/// Plain data with a validating constructor: wavelengths finite, positive and strictly
/// increasing, values finite, 2 ≤ count ≤ [`MAX_SAMPLES`].
#[derive(Debug, Clone, PartialEq)]
pub struct SampledSpectrum {
    wavelengths: Vec<f64>,
    values: Vec<f64>,
    /// Hermite tangents dv/dλ (cubic mode only; empty otherwise).
    tangents: Vec<f64>,
    interpolation: Interpolation,
}

impl SampledSpectrum {
    /// Validate and build a spectrum from wavelengths in nanometres and their values.
    pub fn new(
        wavelengths_nm: Vec<f64>,
        values: Vec<f64>,
        interpolation: Interpolation,
    ) -> Result<Self, SpectrumError> {
        if wavelengths_nm.len() != values.len() {
            return Err(SpectrumError::LengthMismatch {
                wavelengths: wavelengths_nm.len(),
                values: values.len(),
            });
        }
        let n = values.len();
        if n < 2 {
            return Err(SpectrumError::TooFewSamples { count: n });
        }
        if n > MAX_SAMPLES {
            return Err(SpectrumError::TooManySamples {
                count: n,
                max: MAX_SAMPLES,
            });
        }
        for (index, (&wavelength, &value)) in wavelengths_nm.iter().zip(&values).enumerate() {
            if !(wavelength.is_finite() && wavelength > 0.0) {
                return Err(SpectrumError::BadWavelength { index, wavelength });
            }
            if index > 0 && wavelength <= wavelengths_nm[index - 1] {
                return Err(SpectrumError::NotIncreasing {
                    index,
                    wavelength,
                    previous: wavelengths_nm[index - 1],
                });
            }
            if !value.is_finite() {
                return Err(SpectrumError::NonFiniteValue { index, value });
            }
        }
        let tangents = match interpolation {
            Interpolation::Cubic => pchip_tangents(&wavelengths_nm, &values),
            _ => Vec::new(),
        };
        Ok(SampledSpectrum {
            wavelengths: wavelengths_nm,
            values,
            tangents,
            interpolation,
        })
    }

    /// Build from (wavelength, value) pairs: a USD `float2[]` as authored (`[f32; 2]`, kept as
    /// stored) or `[f64; 2]`. Wavelengths are converted from `unit` to nm; values are multiplied
    /// by `value_scale` (use [`WavelengthUnit::density_to_per_nm`] for spectral densities such
    /// as `wavelength:emission`, 1 for reflectance or IOR). Errors report the wavelength as
    /// written.
    pub fn from_pairs<T: Copy + Into<f64>>(
        pairs: &[[T; 2]],
        unit: WavelengthUnit,
        value_scale: f64,
        interpolation: Interpolation,
    ) -> Result<Self, SpectrumError> {
        if pairs.len() > MAX_SAMPLES {
            return Err(SpectrumError::TooManySamples {
                count: pairs.len(),
                max: MAX_SAMPLES,
            });
        }
        // Check raw wavelengths first so that errors quote the file's numbers.
        for (index, p) in pairs.iter().enumerate() {
            let w: f64 = p[0].into();
            if !(w.is_finite() && w > 0.0) {
                return Err(SpectrumError::BadWavelength {
                    index,
                    wavelength: w,
                });
            }
            let previous: f64 = if index > 0 {
                pairs[index - 1][0].into()
            } else {
                0.0
            };
            if index > 0 && w <= previous {
                return Err(SpectrumError::NotIncreasing {
                    index,
                    wavelength: w,
                    previous,
                });
            }
        }
        let to_nm = unit.to_nm();
        let wavelengths = pairs.iter().map(|p| p[0].into() * to_nm).collect();
        let values = pairs.iter().map(|p| p[1].into() * value_scale).collect();
        Self::new(wavelengths, values, interpolation)
    }

    /// Wavelengths in nm.
    pub fn wavelengths(&self) -> &[f64] {
        &self.wavelengths
    }

    /// Sample values.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The interpolation mode.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// (first, last) wavelength in nm: the emission range outside which the spectrum is zero.
    pub fn bounds(&self) -> (f64, f64) {
        (
            self.wavelengths[0],
            self.wavelengths[self.wavelengths.len() - 1],
        )
    }

    /// Index i of the segment [λᵢ, λᵢ₊₁] containing `lambda_nm`, or `None` outside the bounds
    /// (and for NaN). The last wavelength belongs to the last segment.
    pub fn segment_index(&self, lambda_nm: f64) -> Option<usize> {
        let (lo, hi) = self.bounds();
        if !(lambda_nm >= lo && lambda_nm <= hi) {
            return None;
        }
        let i = self.wavelengths.partition_point(|&w| w <= lambda_nm);
        Some(i.saturating_sub(1).min(self.wavelengths.len() - 2))
    }

    /// Value at `lambda_nm` (nm); 0 outside the bounds and for NaN.
    pub fn eval(&self, lambda_nm: f64) -> f64 {
        match self.segment_index(lambda_nm) {
            Some(i) => self.eval_in_segment(i, lambda_nm),
            None => 0.0,
        }
    }

    /// Value at `lambda_nm`, which the caller guarantees lies in segment `i`.
    #[inline]
    pub(crate) fn eval_in_segment(&self, i: usize, lambda_nm: f64) -> f64 {
        let (x0, x1) = (self.wavelengths[i], self.wavelengths[i + 1]);
        let (y0, y1) = (self.values[i], self.values[i + 1]);
        match self.interpolation {
            Interpolation::Linear => {
                let t = (lambda_nm - x0) / (x1 - x0);
                y0 + t * (y1 - y0)
            }
            Interpolation::Held => {
                if lambda_nm >= x1 {
                    y1
                } else {
                    y0
                }
            }
            Interpolation::Cubic => {
                let h = x1 - x0;
                let t = (lambda_nm - x0) / h;
                let (t2, t3) = (t * t, t * t * t);
                let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
                let h10 = t3 - 2.0 * t2 + t;
                let h01 = -2.0 * t3 + 3.0 * t2;
                let h11 = t3 - t2;
                h00 * y0 + h10 * h * self.tangents[i] + h01 * y1 + h11 * h * self.tangents[i + 1]
            }
        }
    }

    /// ∫ S(λ) dλ over the bounds, exact for each interpolation mode: trapezoids (linear),
    /// rectangles (held), h(y₀+y₁)/2 + h²(m₀−m₁)/12 per Hermite segment (cubic).
    pub fn integral(&self) -> f64 {
        let mut sum = 0.0;
        for i in 0..self.wavelengths.len() - 1 {
            let h = self.wavelengths[i + 1] - self.wavelengths[i];
            let (y0, y1) = (self.values[i], self.values[i + 1]);
            sum += match self.interpolation {
                Interpolation::Linear => 0.5 * h * (y0 + y1),
                Interpolation::Held => h * y0,
                Interpolation::Cubic => {
                    0.5 * h * (y0 + y1) + h * h * (self.tangents[i] - self.tangents[i + 1]) / 12.0
                }
            };
        }
        sum
    }

    /// Smallest value over the samples (for cubic mode also the extreme of the curve, since
    /// monotone cubic interpolation never leaves the sample range).
    pub fn min_value(&self) -> f64 {
        self.values.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The same spectrum restricted to [lo, hi] nm (new end samples are interpolated; held and
    /// cubic modes are kept). `None` if the intersection with the bounds is shorter than a point.
    pub fn restricted(&self, lo: f64, hi: f64) -> Option<SampledSpectrum> {
        let (a, b) = self.bounds();
        let (lo, hi) = (lo.max(a), hi.min(b));
        if lo.partial_cmp(&hi) != Some(core::cmp::Ordering::Less) {
            return None;
        }
        let mut w = vec![lo];
        let mut v = vec![self.eval(lo)];
        for (&x, &y) in self.wavelengths.iter().zip(&self.values) {
            if x > lo && x < hi {
                w.push(x);
                v.push(y);
            }
        }
        w.push(hi);
        v.push(self.eval(hi));
        SampledSpectrum::new(w, v, self.interpolation).ok()
    }
}

/// Fritsch–Carlson monotone tangents (the PCHIP rule): zero at local extrema, a weighted
/// harmonic mean of the neighbouring slopes elsewhere, a shape-preserving three-point formula at
/// the two ends.
fn pchip_tangents(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    if n == 2 {
        return vec![d[0], d[0]];
    }
    let mut m = vec![0.0; n];
    for k in 1..n - 1 {
        if d[k - 1] * d[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
        let mut t = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if t * d0 <= 0.0 {
            t = 0.0;
        } else if d0 * d1 <= 0.0 && t.abs() > 3.0 * d0.abs() {
            t = 3.0 * d0;
        }
        t
    };
    m[0] = end(h[0], h[1], d[0], d[1]);
    m[n - 1] = end(h[n - 2], h[n - 3], d[n - 2], d[n - 3]);
    m
}
