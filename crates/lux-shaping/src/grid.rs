//! The bilinear type C lookup of [`Shaping::factor`](crate::Shaping::factor) on evenly spaced
//! angles: the `ies:normalize` scale folded into a padded copy of the candela table, the cell
//! found by arithmetic.

use core::f64::consts::{PI, TAU};
use lux_ies::{PhotometricType, PhotometricWeb, Symmetry};

/// Adding 1.5·2⁵² to a value in \[0, 2⁵¹) rounds it to an integer, in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// Most table entries copied (2²¹ doubles, 16 MiB; a 0.25° × 0.25° full-sphere profile has
/// about 2²⁰): beyond it, the general lookup.
const MAX_ENTRIES: usize = 1 << 21;

/// A type C profile with evenly spaced vertical and horizontal angles
/// ([`PhotometricWeb::vertical_step`], [`PhotometricWeb::horizontal_step`]), bilinear, prepared for
/// `inputs:shaping:ies:file` lookups with the `ies:normalize` factor `s` already applied:
///
/// ```text
/// u = (θies − v₀)/Δv,  i = ⌊u⌋,  a = u − i        (vertical cell and fraction)
/// w = φ/Δh,            j = ⌊w⌋,  b = w − j        (horizontal, φ ∈ [0, 2π))
/// I = lerp(lerp(s·C[j][i], s·C[j][i+1], a), lerp(s·C[j+1][i], s·C[j+1][i+1], a), b)
/// ```
///
/// the same interpolant as `PhotometricWeb::intensity` (linear in the vertical angle, then in
/// the horizontal one) times `s`, with the fractions taken from the even grid rather than from
/// each knot. The rounding of `u` is ε·u absolute in the fraction (and ε·w for φ), the same
/// order as the web's own knots, which are the degrees rounded to radians: the two agree to
/// `4ε·(nv + nh + 2)` of the largest value (the tests measure at most a seventh of that).
/// `⌊u⌋` is found by adding 1.5·2⁵² to `u − ½` (no float → integer conversion); at an odd
/// integer `u` that gives the cell below with fraction 1, the same value. The table has one
/// more column and one more row than the web (copies of the last ones), so the cell `i + 1`,
/// `j + 1` of the last knot is inside it and no index needs clamping for φ < 2π.
///
/// Outside `[v₀, v_last]` the web's edge rules: 0 below the range (θies < 0 and NaN included)
/// and above it short of π; at θies ≥ π the values of the last vertical angle, which
/// [`eval`](Self::eval) leaves to the web (`None`).
#[derive(Clone, Debug)]
pub(crate) struct EvenGrid {
    /// 1/Δv.
    inv_dv: f64,
    /// `−v₀/Δv − ½`: `θies/Δv + offset` is `u − ½`.
    offset: f64,
    /// The first and last vertical angle (radians).
    lo: f64,
    hi: f64,
    /// 1/Δh (0 for an axially symmetric profile: one row).
    inv_dh: f64,
    /// `nh − 1`: the largest row index `j` (0 when axial).
    j_max: usize,
    /// Columns per row: `nv + 1`.
    stride: usize,
    /// `(nh + 1) × (nv + 1)` scaled candela values, rows by horizontal angle.
    values: Vec<f64>,
}

impl EvenGrid {
    /// The grid of `web` scaled by `scale`, when `web` is type C with evenly spaced angles
    /// (horizontal over exactly \[0, 2π\]) and the table is small enough to copy; else `None`.
    pub(crate) fn new(web: &PhotometricWeb, scale: f64) -> Option<EvenGrid> {
        if web.photometric_type() != PhotometricType::C || !scale.is_finite() {
            return None;
        }
        let v = web.vertical_angles();
        let h = web.horizontal_angles();
        let (nv, nh) = (v.len(), h.len());
        let axial = web.symmetry() == Symmetry::Axial;
        let dv = web.vertical_step()?;
        let (rows, dh) = if axial {
            (1, 0.0)
        } else {
            // the expansion of a type C profile spans 0..360°; a table that did not would
            // need φ outside it
            let dh = web.horizontal_step()?;
            if h[0] != 0.0 || (h[nh - 1] - TAU).abs() > 1e-9 * dh {
                return None;
            }
            (nh, dh)
        };
        let stride = nv + 1;
        if (rows + 1).checked_mul(stride)? > MAX_ENTRIES {
            return None;
        }
        let src = web.values();
        let mut values = Vec::with_capacity((rows + 1) * stride);
        for k in 0..=rows {
            let r = &src[k.min(rows - 1) * nv..][..nv];
            values.extend(r.iter().map(|c| c * scale));
            values.push(r[nv - 1] * scale);
        }
        Some(EvenGrid {
            inv_dv: 1.0 / dv,
            offset: -v[0] / dv - 0.5,
            lo: v[0],
            hi: v[nv - 1],
            inv_dh: if axial { 0.0 } else { 1.0 / dh },
            j_max: rows - 1,
            stride,
            values,
        })
    }

    /// The scaled intensity at lookup angles (θies, φ), φ ∈ \[0, 2π) (the azimuth of
    /// [`lux_math::azimuth_from_xy`]; ignored for an axial profile); `None` for θies ≥ π
    /// beyond the last vertical angle, where the web's last-angle rule applies.
    #[inline(always)]
    pub(crate) fn eval(&self, theta: f64, phi: f64) -> Option<f64> {
        // the web's own range test, on the angle
        if !(theta >= self.lo && theta <= self.hi) {
            return if theta >= PI { None } else { Some(0.0) };
        }
        // u − ½ in one multiply-add (the rounding in `cell_half` wants it), kept ≥ −½ where
        // the product rounds below the first knot; above the last knot the padding column
        // takes the rounding
        let um = (theta * self.inv_dv + self.offset).max(-0.5);
        let (i, a) = cell_half(um);
        let (j, b) = cell_half(phi * self.inv_dh - 0.5);
        // j ≤ nh − 1 for φ < 2π; the clamp only guards the table against φ ≥ 2π
        let k = j.min(self.j_max) * self.stride + i;
        let lo = pair(&self.values, k);
        let hi = pair(&self.values, k + self.stride);
        let lo = lo[0] + a * (lo[1] - lo[0]);
        let hi = hi[0] + a * (hi[1] - hi[0]);
        Some(lo + b * (hi - lo))
    }
}

/// `values[k]` and `values[k + 1]` (zeros past the end, which the indices of
/// [`EvenGrid::eval`] never reach: no bounds-check panic in the hot path).
#[inline(always)]
fn pair(values: &[f64], k: usize) -> [f64; 2] {
    match values.get(k..k + 2) {
        Some(&[x, y]) => [x, y],
        _ => [0.0; 2],
    }
}

/// `(⌊x⌋, x − ⌊x⌋)` from `m = x − ½`, for 0 ≤ x < 2⁵¹ (at an odd integer x: `(x − 1, 1)`):
/// `m + 1.5·2⁵²` rounds `m` to the nearest integer (ties to even) in the low bits of the sum.
#[inline(always)]
fn cell_half(m: f64) -> (usize, f64) {
    let r = m + ROUND;
    (r.to_bits() as u32 as usize, (m - (r - ROUND)) + 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_ies::IesFile;
    use lux_math::Profile;

    fn xorshift(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The well-formed corpus profiles (file name, web).
    fn corpus() -> Vec<(String, PhotometricWeb)> {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ies");
        let mut out = Vec::new();
        for dir in std::fs::read_dir(root).unwrap() {
            let dir = dir.unwrap().path();
            if !dir.is_dir() {
                continue;
            }
            for f in std::fs::read_dir(&dir).unwrap() {
                let p = f.unwrap().path();
                if p.extension().is_none_or(|x| x != "ies") {
                    continue;
                }
                let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
                let Ok(file) = IesFile::parse(&text) else {
                    continue;
                };
                if let Ok(web) = PhotometricWeb::new(&file, Profile::Spec) {
                    out.push((p.display().to_string(), web));
                }
            }
        }
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    /// Worst `|grid − s·web|` over `n` random lookups inside the vertical range and at every
    /// knot, relative to `s·max_candela`, divided by the bound `4ε·(nv + nh + 2)`: the grid's
    /// fraction `θ/Δ − i` carries the rounding of `θ/Δ`, ε·u absolute for u up to nv − 1 (and
    /// nh − 1 for φ); the web's own fraction is exact to its knots, which are the degrees
    /// rounded to radians, ε·u of a cell off the even grid. Each fraction error scales a value
    /// difference of at most the maximum; the last ε's are the lerps' and the scale's roundings.
    fn worst_error(web: &PhotometricWeb, scale: f64, n: usize, seed: u64) -> f64 {
        let g = EvenGrid::new(web, scale).expect("an even grid");
        let (v0, v1) = web.vertical_range();
        let m = scale * web.max_candela().max(f64::MIN_POSITIVE);
        let mut next = xorshift(seed);
        let mut worst: f64 = 0.0;
        let mut check = |t: f64, p: f64| {
            let want = scale * web.intensity(t, p);
            let got = g.eval(t, p).expect("inside the vertical range");
            worst = worst.max((got - want).abs() / m);
        };
        for _ in 0..n {
            check(v0 + (v1 - v0) * next(), TAU * next());
        }
        for &t in web.vertical_angles() {
            for &p in web.horizontal_angles() {
                check(t, if p < TAU { p } else { 0.0 });
            }
            check(t, TAU.next_down());
        }
        let (nv, nh) = (web.vertical_angles().len(), web.horizontal_angles().len());
        worst / (4.0 * f64::EPSILON * (nv + nh + 2) as f64)
    }

    /// Every corpus profile with evenly spaced angles (12 of the 21 well-formed files, among
    /// them all the measured luminaires of the luxtest scenes) gets the grid, and its lookups
    /// are the web's bilinear interpolant within the rounding bound of [`worst_error`].
    #[test]
    fn corpus_grids_match_the_web_interpolant() {
        let mut with_grid = Vec::new();
        for (name, web) in corpus() {
            if EvenGrid::new(&web, 1.0).is_none() {
                continue;
            }
            let s = 1.0 / web.mean_intensity();
            let e = worst_error(&web, s, 20_000, 0x9E3779B97F4A7C15);
            assert!(e <= 1.0, "{name}: {e}");
            with_grid.push(name);
        }
        assert_eq!(with_grid.len(), 12, "{with_grid:?}");
        assert!(
            with_grid
                .iter()
                .any(|n| n.ends_with("bega_omni001_1238lm.ies"))
        );
    }

    /// LM-63-2002 type C text with `nv` even vertical angles over `[v0, v1]` and the horizontal
    /// angles `h` (degrees), random candela values (a quarter of them 0).
    fn even_profile(
        v0: f64,
        v1: f64,
        nv: usize,
        h: &[f64],
        next: &mut impl FnMut() -> f64,
    ) -> String {
        let v: Vec<String> = (0..nv)
            .map(|k| format!("{}", v0 + (v1 - v0) * k as f64 / (nv - 1) as f64))
            .collect();
        let cd: Vec<String> = (0..nv * h.len())
            .map(|_| {
                let x = next();
                if x < 0.25 {
                    "0".into()
                } else {
                    format!("{:.3}", 1000.0 * x)
                }
            })
            .collect();
        let h: Vec<String> = h.iter().map(|a| a.to_string()).collect();
        format!(
            "IESNA:LM-63-2002\n[TEST] even\nTILT=NONE\n1 -1 1 {nv} {} 1 2 0 0 0\n1 1 10\n{}\n{}\n{}\n",
            h.len(),
            v.join(" "),
            h.join(" "),
            cd.join(" ")
        )
    }

    /// Generated even profiles: every type C symmetry (axial, quadrant, the two bilateral ones,
    /// full), vertical ranges from the nadir, to the zenith, and starting off both (v₀ ≠ 0).
    #[test]
    fn generated_even_profiles_match_the_web_interpolant() {
        let mut next = xorshift(0xD1B54A32D192ED03);
        let evenly = |a: f64, b: f64, n: usize| -> Vec<f64> {
            (0..n)
                .map(|k| a + (b - a) * k as f64 / (n - 1) as f64)
                .collect()
        };
        let hsets = [
            vec![0.0],
            evenly(0.0, 90.0, 4),
            evenly(0.0, 180.0, 7),
            evenly(90.0, 270.0, 5),
            evenly(0.0, 360.0, 25),
            evenly(0.0, 360.0, 2),
        ];
        let mut cases = 0;
        for (v0, v1) in [
            (0.0, 180.0),
            (0.0, 90.0),
            (90.0, 180.0),
            (12.5, 167.5),
            (0.0, 50.0),
        ] {
            for nv in [2, 3, 19, 181] {
                for h in &hsets {
                    let text = even_profile(v0, v1, nv, h, &mut next);
                    let web = PhotometricWeb::new(&IesFile::parse(&text).unwrap(), Profile::Spec)
                        .unwrap();
                    let s = 0.5 + next();
                    let e = worst_error(&web, s, 2_000, 17 + cases);
                    assert!(e <= 1.0, "{v0}..{v1} × {nv}, {h:?}: {e}");
                    cases += 1;
                }
            }
        }
        assert_eq!(cases, 120);
    }

    #[test]
    fn edges_and_profiles_without_a_grid() {
        let mut next = xorshift(7);
        let h: Vec<f64> = (0..=8).map(|k| 45.0 * k as f64).collect();
        let text = even_profile(10.0, 170.0, 17, &h, &mut next);
        let web = PhotometricWeb::new(&IesFile::parse(&text).unwrap(), Profile::Spec).unwrap();
        let g = EvenGrid::new(&web, 2.0).unwrap();
        let (v0, v1) = (10f64.to_radians(), 170f64.to_radians());
        // outside the vertical range: 0 as the web, except θies ≥ π (the web's last-angle rule)
        for t in [
            v0.next_down(),
            v1.next_up(),
            -1.0,
            0.0,
            3.0,
            f64::NAN,
            f64::NEG_INFINITY,
        ] {
            assert_eq!(g.eval(t, 1.0), Some(0.0), "{t}");
            assert_eq!(web.intensity(t, 1.0), 0.0, "{t}");
        }
        for t in [PI, 4.0, f64::INFINITY] {
            assert_eq!(g.eval(t, 1.0), None, "{t}");
            assert_eq!(web.intensity(t, 1.0), web.intensity(v1, 1.0), "{t}");
        }
        // both ends of the range are inside, with the tabulated values
        let tol = 1e-13 * web.max_candela();
        for p in [0.0, 0.3, 3.0, 6.0] {
            assert!((g.eval(v0, p).unwrap() - 2.0 * web.intensity(v0, p)).abs() < tol);
            assert!((g.eval(v1, p).unwrap() - 2.0 * web.intensity(v1, p)).abs() < tol);
        }
        // φ just below 2π interpolates towards the 360° plane (the padded row beyond it)
        let a = g.eval(1.0, TAU.next_down()).unwrap();
        assert!(
            (a - 2.0 * web.intensity(1.0, TAU.next_down())).abs() < tol,
            "{a}"
        );
        // φ ≥ 2π and NaN never read outside the table
        assert!(g.eval(1.0, 7.0).is_some());
        assert!(g.eval(1.0, f64::NAN).unwrap().is_nan());
        // no grid: a non-finite scale, uneven vertical angles, a type B profile
        assert!(EvenGrid::new(&web, f64::INFINITY).is_none());
        let uneven = text.replacen("\n10 20 ", "\n10 21 ", 1);
        assert_ne!(uneven, text);
        let w = PhotometricWeb::new(&IesFile::parse(&uneven).unwrap(), Profile::Spec).unwrap();
        assert!(EvenGrid::new(&w, 1.0).is_none());
        let b = "IESNA:LM-63-2002\n[TEST] b\nTILT=NONE\n1 -1 1 3 2 2 2 0 0 0\n1 1 10\n\
                 -90 0 90\n0 90\n1 2 3 4 5 6\n";
        let w = PhotometricWeb::new(&IesFile::parse(b).unwrap(), Profile::Spec).unwrap();
        assert!(EvenGrid::new(&w, 1.0).is_none());
    }
}
