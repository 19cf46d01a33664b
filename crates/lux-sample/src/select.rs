//! Light selection: which light to sample at a shading point, with its probability.

use crate::alias::AliasTable;
use crate::bvh::LightBvh;
use crate::error::SampleError;
use crate::sample::Reference;

/// A light-selection strategy (pbrt-v4 §12.6): uniform, by power (alias table), or by the
/// spatially varying importance of a light BVH.
#[derive(Clone, Debug)]
pub enum LightSelector {
    /// Each of `n` lights with probability 1/n.
    Uniform(usize),
    /// Proportional to a fixed power per light.
    Power(AliasTable),
    /// Proportional to the BVH importance at the reference point.
    Bvh(LightBvh),
}

impl LightSelector {
    /// Uniform selection over `n ≥ 1` lights.
    pub fn uniform(n: usize) -> Result<Self, SampleError> {
        if n == 0 {
            return Err(SampleError::BadSize {
                field: "lights",
                expected: "at least one light".into(),
                got: 0,
            });
        }
        Ok(Self::Uniform(n))
    }

    /// Selection proportional to `power[i]` (finite, ≥ 0, not all zero).
    pub fn power(power: &[f64]) -> Result<Self, SampleError> {
        Ok(Self::Power(AliasTable::new(power)?))
    }

    /// Chooses a light with `u ∈ [0,1)`; returns `(index, probability)`.
    #[inline]
    pub fn sample(&self, r: &Reference, u: f64) -> Option<(usize, f64)> {
        match self {
            Self::Uniform(n) => Some((((u * *n as f64) as usize).min(n - 1), 1.0 / *n as f64)),
            Self::Power(t) => Some(t.sample(u)),
            Self::Bvh(b) => b.sample(r, u),
        }
    }

    /// [`Self::sample`] for each of `us` at one reference point: `out[j]` is `sample(r, us[j])`,
    /// bit for bit; the BVH weighs each node it visits once for all of them
    /// ([`LightBvh::sample_each`]). `out` must be as long as `us`.
    #[inline]
    pub fn sample_each(&self, r: &Reference, us: &[f64], out: &mut [Option<(usize, f64)>]) {
        match self {
            Self::Bvh(b) => b.sample_each(r, us, out),
            _ => {
                assert_eq!(us.len(), out.len(), "one answer per number");
                for (o, &u) in out.iter_mut().zip(us) {
                    *o = self.sample(r, u);
                }
            }
        }
    }

    /// Probability of choosing light `i` at `r`.
    #[inline]
    pub fn pmf(&self, r: &Reference, i: usize) -> f64 {
        match self {
            Self::Uniform(n) => {
                if i < *n {
                    1.0 / *n as f64
                } else {
                    0.0
                }
            }
            Self::Power(t) => t.pmf(i),
            Self::Bvh(b) => b.pmf(r, i),
        }
    }
}
