//! Walker/Vose alias tables: O(1) sampling of a discrete distribution.

use crate::error::{MAX_ENTRIES, SampleError};

const ONE_MINUS_EPS: f64 = 1.0 - f64::EPSILON / 2.0;

#[derive(Clone, Copy, Debug)]
struct Bin {
    /// Probability of keeping this bin's own index when it is drawn.
    q: f64,
    /// The other index stored in this bin.
    alias: u32,
    /// The normalised probability of this index.
    p: f64,
}

/// An alias table over weights w\[i\] ≥ 0 (Walker 1977, Vose 1991 construction): index i is drawn
/// with probability w\[i\]/Σw using one uniform number, in constant time.
#[derive(Clone, Debug)]
pub struct AliasTable {
    bins: Vec<Bin>,
}

impl AliasTable {
    /// Builds the table. Weights must be finite and ≥ 0 with a positive sum; at most 2³¹ entries.
    pub fn new(weights: &[f64]) -> Result<Self, SampleError> {
        let n = weights.len();
        if n == 0 || n > MAX_ENTRIES.min(u32::MAX as usize) {
            return Err(SampleError::BadSize {
                field: "weights",
                expected: format!("1..={MAX_ENTRIES} entries"),
                got: n,
            });
        }
        let mut sum = 0.0;
        for (index, &value) in weights.iter().enumerate() {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SampleError::BadWeight {
                    field: "weights",
                    index,
                    value,
                });
            }
            sum += value;
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return Err(SampleError::AllZero("weights"));
        }
        let mut bins: Vec<Bin> = weights
            .iter()
            .map(|&w| Bin {
                q: 0.0,
                alias: 0,
                p: w / sum,
            })
            .collect();
        // Scaled probabilities n·p; "small" < 1, "large" ≥ 1.
        let mut small = Vec::new();
        let mut large = Vec::new();
        let scaled: Vec<f64> = bins.iter().map(|b| b.p * n as f64).collect();
        let mut work = scaled;
        for (i, &s) in work.iter().enumerate() {
            if s < 1.0 {
                small.push(i)
            } else {
                large.push(i)
            }
        }
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            large.pop();
            bins[s].q = work[s];
            bins[s].alias = l as u32;
            work[l] = (work[l] + work[s]) - 1.0;
            if work[l] < 1.0 {
                small.push(l)
            } else {
                large.push(l)
            }
        }
        // Left-overs are 1 up to round-off.
        for i in small.into_iter().chain(large) {
            bins[i].q = 1.0;
            bins[i].alias = i as u32;
        }
        Ok(Self { bins })
    }

    /// Number of entries.
    #[inline]
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    /// Always false (a table has at least one entry).
    #[inline]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Draws an index from `u ∈ [0,1)`; returns `(index, probability)`.
    #[inline]
    pub fn sample(&self, u: f64) -> (usize, f64) {
        let (k, p, _) = self.sample_remap(u);
        (k, p)
    }

    /// Like [`Self::sample`], also returning a fresh uniform number in \[0,1) recovered from the
    /// unused bits of `u` (so one dimension can drive both the choice and a later warp).
    #[inline]
    pub fn sample_remap(&self, u: f64) -> (usize, f64, f64) {
        let n = self.bins.len();
        let x = u * n as f64;
        let i = (x as usize).min(n - 1);
        let up = (x - i as f64).min(1.0);
        let b = &self.bins[i];
        if up < b.q {
            (i, self.bins[i].p, (up / b.q).min(ONE_MINUS_EPS))
        } else {
            let k = b.alias as usize;
            (
                k,
                self.bins[k].p,
                ((up - b.q) / (1.0 - b.q)).clamp(0.0, ONE_MINUS_EPS),
            )
        }
    }

    /// The (keep probability, alias) pairs, for callers that pack tables into flat arrays.
    pub(crate) fn cells(&self) -> impl Iterator<Item = (f64, u32)> + '_ {
        self.bins.iter().map(|b| (b.q, b.alias))
    }

    /// Probability of index `i` (0 when out of range).
    #[inline]
    pub fn pmf(&self, i: usize) -> f64 {
        self.bins.get(i).map_or(0.0, |b| b.p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies_match_weights() {
        let w = [1.0, 0.0, 5.0, 2.0, 0.5];
        let t = AliasTable::new(&w).unwrap();
        let n = 200_000;
        let mut c = [0usize; 5];
        for k in 0..n {
            let (i, p) = t.sample((k as f64 + 0.5) / n as f64);
            assert!((p - t.pmf(i)).abs() < 1e-15);
            c[i] += 1;
        }
        let s: f64 = w.iter().sum();
        for i in 0..5 {
            // Stratified u: each entry's frequency equals its probability up to n⁻¹·(#bins).
            assert!(
                (c[i] as f64 / n as f64 - w[i] / s).abs() < 1e-4,
                "{i}: {}",
                c[i]
            );
        }
        assert_eq!(c[1], 0);
    }

    #[test]
    fn rejects_bad_weights() {
        assert!(AliasTable::new(&[]).is_err());
        assert!(AliasTable::new(&[0.0, 0.0]).is_err());
        assert!(AliasTable::new(&[1.0, f64::INFINITY]).is_err());
        assert!(AliasTable::new(&[1.0, -0.1]).is_err());
    }
}
