//! Piecewise-constant 1D and 2D distributions on \[0,1\] and \[0,1\]², with inverses.
//!
//! The function is given as non-negative values on equal cells; the density is proportional to
//! it (pbrt-v4 §A.4.1–A.4.2). Sampling inverts the tabulated CDF by binary search and is
//! allocation-free.

use crate::alias::AliasTable;
use crate::error::{MAX_ENTRIES, SampleError};

/// A piecewise-constant density on \[0,1\] with `n` equal cells: pdf(x) = f\[i\]/(mean f) in cell i.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f64>,
    cdf: Vec<f64>,
    integral: f64,
}

impl Distribution1D {
    /// Builds the distribution of `func` (finite, ≥ 0). A function that is zero everywhere
    /// becomes the uniform distribution (its `integral` stays 0 so callers can detect it).
    pub fn new(func: &[f64]) -> Result<Self, SampleError> {
        let n = func.len();
        if n == 0 || n > MAX_ENTRIES {
            return Err(SampleError::BadSize {
                field: "func",
                expected: format!("1..={MAX_ENTRIES} cells"),
                got: n,
            });
        }
        for (index, &value) in func.iter().enumerate() {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SampleError::BadWeight {
                    field: "func",
                    index,
                    value,
                });
            }
        }
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        let mut acc = 0.0;
        for &f in func {
            acc += f / n as f64;
            cdf.push(acc);
        }
        let integral = acc;
        let func = if integral > 0.0 {
            for c in cdf.iter_mut().skip(1) {
                *c /= integral;
            }
            func.to_vec()
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f64 / n as f64;
            }
            vec![1.0; n]
        };
        cdf[n] = 1.0;
        Ok(Self {
            func,
            cdf,
            integral,
        })
    }

    /// Number of cells.
    #[inline]
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Always false (a distribution has at least one cell).
    #[inline]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// ∫₀¹ f(x) dx of the original function (0 if it was zero everywhere).
    #[inline]
    pub fn integral(&self) -> f64 {
        self.integral
    }

    #[inline]
    fn norm(&self) -> f64 {
        if self.integral > 0.0 {
            self.integral
        } else {
            1.0
        }
    }

    /// Samples x ∈ \[0,1) from `u`; returns `(x, pdf(x), cell index)`.
    #[inline]
    pub fn sample(&self, u: f64) -> (f64, f64, usize) {
        let n = self.func.len();
        // Largest i with cdf[i] <= u, i in [0, n−1].
        let i = self.cdf[1..n].partition_point(|&c| c <= u);
        let c0 = self.cdf[i];
        let width = self.cdf[i + 1] - c0;
        let du = if width > 0.0 {
            ((u - c0) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let x = ((i as f64 + du) / n as f64).min(1.0 - f64::EPSILON / 2.0);
        (x, self.func[i] / self.norm(), i)
    }

    /// Density at x (0 outside \[0,1\]).
    #[inline]
    pub fn pdf(&self, x: f64) -> f64 {
        if !(0.0..=1.0).contains(&x) {
            return 0.0;
        }
        let i = ((x * self.func.len() as f64) as usize).min(self.func.len() - 1);
        self.func[i] / self.norm()
    }

    /// Probability of cell `i` (0 if out of range).
    #[inline]
    pub fn cell_probability(&self, i: usize) -> f64 {
        if i >= self.func.len() {
            return 0.0;
        }
        self.cdf[i + 1] - self.cdf[i]
    }

    /// The CDF at x: the `u` for which `sample(u)` returns x.
    #[inline]
    pub fn invert(&self, x: f64) -> f64 {
        let n = self.func.len();
        let xs = (x.clamp(0.0, 1.0)) * n as f64;
        let i = (xs as usize).min(n - 1);
        let t = xs - i as f64;
        crate::lerp(t, self.cdf[i], self.cdf[i + 1])
    }
}

/// A piecewise-constant density on \[0,1\]² from an `nu × nv` table (row-major, v = row):
/// a marginal over rows and one conditional per row.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
    nu: usize,
    /// Alias cells of the marginal (one per row) and of every row, flat.
    row_alias: Vec<AliasCell>,
    cell_alias: Vec<AliasCell>,
    /// Density of every cell, flat (f/∫∫f).
    density: Vec<f64>,
}

/// One packed alias-table entry: keep probability and alias index.
#[derive(Clone, Copy, Debug)]
struct AliasCell {
    q: f64,
    alias: u32,
}

/// Alias lookup in a packed table: (index, u remapped to [0,1)).
#[inline]
fn alias_pick(cells: &[AliasCell], u: f64) -> (usize, f64) {
    let n = cells.len();
    let x = u * n as f64;
    let i = (x as usize).min(n - 1);
    let up = (x - i as f64).clamp(0.0, 1.0);
    let c = cells[i];
    const ONE_MINUS_EPS: f64 = 1.0 - f64::EPSILON / 2.0;
    if up < c.q {
        (i, (up / c.q).min(ONE_MINUS_EPS))
    } else {
        (
            c.alias as usize,
            ((up - c.q) / (1.0 - c.q)).clamp(0.0, ONE_MINUS_EPS),
        )
    }
}

fn pack(weights: &[f64]) -> Vec<AliasCell> {
    match AliasTable::new(weights) {
        Ok(t) => t.cells().map(|(q, alias)| AliasCell { q, alias }).collect(),
        // All zero: never selected; any valid table will do.
        Err(_) => (0..weights.len())
            .map(|i| AliasCell {
                q: 1.0,
                alias: i as u32,
            })
            .collect(),
    }
}

impl Distribution2D {
    /// Builds the distribution of `func` with `nu` columns and `nv` rows.
    pub fn new(func: &[f64], nu: usize, nv: usize) -> Result<Self, SampleError> {
        if nu == 0 || nv == 0 || nu.checked_mul(nv) != Some(func.len()) || func.len() > MAX_ENTRIES
        {
            return Err(SampleError::BadSize {
                field: "func",
                expected: format!("nu·nv = {nu}·{nv} values, at most {MAX_ENTRIES}"),
                got: func.len(),
            });
        }
        let conditional = func
            .chunks_exact(nu)
            .map(Distribution1D::new)
            .collect::<Result<Vec<_>, _>>()?;
        let marg: Vec<f64> = conditional.iter().map(|c| c.integral()).collect();
        let marginal = Distribution1D::new(&marg)?;
        let total = marginal.integral();
        let row_alias = pack(&marg);
        let mut cell_alias = Vec::with_capacity(func.len());
        for row in func.chunks_exact(nu) {
            cell_alias.extend(pack(row));
        }
        let density = if total > 0.0 {
            func.iter().map(|&f| f / total).collect()
        } else {
            vec![1.0; func.len()]
        };
        Ok(Self {
            conditional,
            marginal,
            nu,
            row_alias,
            cell_alias,
            density,
        })
    }

    /// ∫∫ f du dv of the original table.
    #[inline]
    pub fn integral(&self) -> f64 {
        self.marginal.integral()
    }

    /// Samples (u, v) ∈ \[0,1)²; returns `([u, v], pdf)`.
    #[inline]
    pub fn sample(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let (v, pv, row) = self.marginal.sample(u[1]);
        let (x, pu, _) = self.conditional[row].sample(u[0]);
        ([x, v], pv * pu)
    }

    /// Samples (u, v) with alias tables (Walker/Vose) for the marginal and the chosen row: O(1)
    /// and two to three memory accesses instead of two binary searches, at the price of a
    /// mapping that is not monotone (no [`Self::invert`]). Same density as [`Self::sample`].
    #[inline]
    pub fn sample_alias(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let nv = self.row_alias.len();
        let (row, v_in) = alias_pick(&self.row_alias, u[1]);
        let start = row * self.nu;
        let (col, u_in) = alias_pick(&self.cell_alias[start..start + self.nu], u[0]);
        let p = self.density[start + col];
        let uv = [
            (col as f64 + u_in) / self.nu as f64,
            (row as f64 + v_in) / nv as f64,
        ];
        (uv, p)
    }

    /// Density at (u, v).
    #[inline]
    pub fn pdf(&self, p: [f64; 2]) -> f64 {
        if !(0.0..=1.0).contains(&p[1]) {
            return 0.0;
        }
        let nv = self.conditional.len();
        let row = ((p[1] * nv as f64) as usize).min(nv - 1);
        self.marginal.pdf(p[1]) * self.conditional[row].pdf(p[0])
    }

    /// The `u` that `sample` maps onto `p`.
    #[inline]
    pub fn invert(&self, p: [f64; 2]) -> [f64; 2] {
        let nv = self.conditional.len();
        let row = ((p[1].clamp(0.0, 1.0) * nv as f64) as usize).min(nv - 1);
        [
            self.conditional[row].invert(p[0]),
            self.marginal.invert(p[1]),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn rejects_bad_input() {
        assert!(Distribution1D::new(&[]).is_err());
        assert!(matches!(
            Distribution1D::new(&[1.0, -1.0]),
            Err(SampleError::BadWeight { index: 1, .. })
        ));
        assert!(Distribution1D::new(&[1.0, f64::NAN]).is_err());
        assert!(Distribution2D::new(&[1.0; 6], 4, 2).is_err());
    }

    #[test]
    fn zero_function_is_uniform() {
        let d = Distribution1D::new(&[0.0; 4]).unwrap();
        assert_eq!(d.integral(), 0.0);
        let (x, pdf, i) = d.sample(0.6);
        assert!((x - 0.6).abs() < 1e-12 && pdf == 1.0 && i == 2);
    }

    #[test]
    fn pdf_is_normalised_and_matches_cells() {
        let f = [1.0, 3.0, 0.0, 4.0];
        let d = Distribution1D::new(&f).unwrap();
        assert!((d.integral() - 2.0).abs() < 1e-15);
        assert!((d.pdf(0.1) - 0.5).abs() < 1e-15);
        assert!((d.pdf(0.3) - 1.5).abs() < 1e-15);
        assert_eq!(d.pdf(0.6), 0.0);
        assert!((d.cell_probability(3) - 0.5).abs() < 1e-15);
        // u = 0.125 + 0.375/2 lands in the middle of cell 1.
        let (x, p, i) = d.sample(0.125 + 0.1875);
        assert_eq!(i, 1);
        assert!((x - 0.375).abs() < 1e-12 && (p - 1.5).abs() < 1e-15);
    }

    proptest! {
        #[test]
        fn roundtrip_1d(u in 0.0..1.0f64) {
            let d = Distribution1D::new(&[0.5, 2.0, 0.0, 1.0, 7.0]).unwrap();
            let (x, p, _) = d.sample(u);
            prop_assert!(p > 0.0);
            prop_assert!((d.invert(x) - u).abs() < 1e-9);
            prop_assert!((d.pdf(x) - p).abs() < 1e-12);
        }

        #[test]
        fn alias_2d_density_matches(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let f: Vec<f64> = (0..12).map(|i| ((i * 7) % 5) as f64 * 0.5).collect();
            let d = Distribution2D::new(&f, 4, 3).unwrap();
            let (p, pdf) = d.sample_alias([u0, u1]);
            prop_assert!(pdf > 0.0);
            prop_assert!((d.pdf(p) - pdf).abs() < 1e-12 * pdf.max(1.0));
        }

        #[test]
        fn roundtrip_2d(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let f: Vec<f64> = (0..12).map(|i| ((i * 7) % 5) as f64 + 0.25).collect();
            let d = Distribution2D::new(&f, 4, 3).unwrap();
            let (p, pdf) = d.sample([u0, u1]);
            prop_assert!((d.pdf(p) - pdf).abs() < 1e-12 * pdf.max(1.0));
            let back = d.invert(p);
            prop_assert!((back[0] - u0).abs() < 1e-9 && (back[1] - u1).abs() < 1e-9);
        }
    }
}
