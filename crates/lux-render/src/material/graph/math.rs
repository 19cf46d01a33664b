//! The stdlib's value nodes (`MaterialX.StandardNodes.md`, "Math Nodes", "Adjustment Nodes",
//! "Conditional Nodes", "Channel Nodes") and the pbrlib helpers without a node graph
//! (`MaterialX.PBRSpec.md`, "Utility Nodes": `roughness_anisotropy`, `artistic_ior`; and
//! OpenPBR's `open_pbr_anisotropy`), evaluated on values held as `DVec4`.
//!
//! Values are *canonical* ([`canon`]): a `float`, `integer` or `boolean` is splatted into all
//! four channels (so the `FA` nodedefs — a colour or vector with a float second operand — need
//! no broadcasting), a two- or three-channel value has zeros beyond its channels.

use glam::{DVec3, DVec4, Vec4Swizzles};
use lux_usd::shading::ValueType;

/// A per-channel unary function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Unary {
    /// `sqrt`: `√in`.
    Sqrt,
    /// `ln`: natural logarithm.
    Ln,
    /// `exp`: `eⁱⁿ`.
    Exp,
    /// `sign`: −1, 0 or +1.
    Sign,
    /// `absval`: `|in|`.
    Abs,
    /// `floor`: `⌊in⌋`.
    Floor,
    /// `ceil`: `⌈in⌉`.
    Ceil,
    /// `round`: nearest integer.
    Round,
    /// `fract`: `in − ⌊in⌋`.
    Fract,
    /// `sin` (radians).
    Sin,
    /// `cos` (radians).
    Cos,
    /// `tan` (radians).
    Tan,
    /// `asin`.
    Asin,
    /// `acos`.
    Acos,
}

impl Unary {
    fn apply(self, x: f64) -> f64 {
        match self {
            Unary::Sqrt => x.sqrt(),
            Unary::Ln => x.ln(),
            Unary::Exp => x.exp(),
            // GLSL `sign`: 0 at 0 (Rust's `signum` gives ±1 there).
            Unary::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
            Unary::Abs => x.abs(),
            Unary::Floor => x.floor(),
            Unary::Ceil => x.ceil(),
            Unary::Round => x.round(),
            Unary::Fract => x - x.floor(),
            Unary::Sin => x.sin(),
            Unary::Cos => x.cos(),
            Unary::Tan => x.tan(),
            Unary::Asin => x.asin(),
            Unary::Acos => x.acos(),
        }
    }

    /// The unary node of a category.
    pub(crate) fn of(category: &str) -> Option<Unary> {
        Some(match category {
            "sqrt" => Unary::Sqrt,
            "ln" => Unary::Ln,
            "exp" => Unary::Exp,
            "sign" => Unary::Sign,
            "absval" => Unary::Abs,
            "floor" => Unary::Floor,
            "ceil" => Unary::Ceil,
            "round" => Unary::Round,
            "fract" => Unary::Fract,
            "sin" => Unary::Sin,
            "cos" => Unary::Cos,
            "tan" => Unary::Tan,
            "asin" => Unary::Asin,
            "acos" => Unary::Acos,
            _ => return None,
        })
    }
}

/// A value node; its arguments are the inputs [`MathOp::inputs`] names, in that order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MathOp {
    /// `add`: `in1 + in2`.
    Add,
    /// `subtract`: `in1 − in2`.
    Subtract,
    /// `multiply`: `in1 · in2`.
    Multiply,
    /// `divide`: `in1 / in2`.
    Divide,
    /// `modulo`: `in1 − in2·⌊in1/in2⌋` (GLSL `mod`).
    Modulo,
    /// `power`: `in1^in2`.
    Power,
    /// `max`.
    Max,
    /// `min`.
    Min,
    /// `atan2`: `atan2(iny, inx)`.
    Atan2,
    /// A per-channel function of `in`.
    Unary(Unary),
    /// `invert`: `amount − in`.
    Invert,
    /// `clamp`: `min(max(in, low), high)`.
    Clamp,
    /// `mix`: `fg·mix + bg·(1 − mix)`.
    Mix,
    /// `remap`: `outlow + (in − inlow)·(outhigh − outlow)/(inhigh − inlow)`.
    Remap,
    /// `smoothstep`: 0 at or below `low`, 1 at or above `high`, `t²(3 − 2t)` between.
    Smoothstep,
    /// `normalize`: `in/|in|`.
    Normalize,
    /// `magnitude`: `|in|`.
    Magnitude,
    /// `distance`: `|in1 − in2|`.
    Distance,
    /// `dotproduct`: `in1·in2`.
    DotProduct,
    /// `crossproduct`: `in1 × in2`.
    CrossProduct,
    /// `mincomponent` over the input's `n` channels.
    MinComponent(u8),
    /// `maxcomponent` over the input's `n` channels.
    MaxComponent(u8),
    /// `luminance`: `dot(in.rgb, lumacoeffs)` in the colour channels, alpha kept.
    Luminance,
    /// `rotate2d` (MaterialX's `mx_rotate_vector2`): `(c·x + s·y, −s·x + c·y)` with `c, s`
    /// the cosine and sine of `amount` degrees.
    Rotate2d,
    /// `rotate3d` (`mx_rotate_vector3`): with the unit `axis` `a` and `amount` θ in degrees,
    /// `in·cos θ + (in × a)·sin θ + a·(a·in)·(1 − cos θ)`.
    Rotate3d,
    /// `ifgreater`: `value1 > value2 ? in1 : in2`.
    IfGreater,
    /// `ifgreatereq`: `value1 ≥ value2 ? in1 : in2`.
    IfGreaterEq,
    /// `ifequal`: `value1 = value2 ? in1 : in2`.
    IfEqual,
    /// `switch`: input `clamp(⌊which⌋, 0, n − 1)` of its `n` inputs (`which` last).
    Switch(u8),
    /// `convert` from one type to another (see [`convert`]).
    Convert {
        /// The input's type.
        from: ValueType,
        /// The output's type.
        to: ValueType,
    },
    /// `extract`, `separateN`: channel `index` of `in`.
    Extract(u8),
    /// `combineN`: the inputs' channels (the counts given) concatenated.
    Combine([u8; 4]),
    /// `normalmap` (`mx_normalmap_vector2`): `v = in·2 − 1` (`(0, 0, 1)` for a zero `in`),
    /// `normalize(T·v.x·scale.x + B·v.y·scale.y + N·v.z)`.
    Normalmap,
    /// `roughness_anisotropy` (`mx_roughness_anisotropy`): `r² = clamp(roughness², 1e-8, 1)`;
    /// for `anisotropy > 0`, `aspect = √(1 − clamp(anisotropy, 0, 0.98))` and
    /// `(min(r²/aspect, 1), r²·aspect)`, else `(r², r²)`.
    RoughnessAnisotropy,
    /// `open_pbr_anisotropy` (OpenPBR's graph): `αx = roughness²·√(2/(1 + (1 − anisotropy)²))`,
    /// `αy = (1 − anisotropy)·αx`.
    OpenPbrAnisotropy,
    /// `artistic_ior` (Gulbrandsen 2014, `mx_artistic_ior`): output `ior` or `extinction`.
    ArtisticIor {
        /// Whether the output is `extinction` (else `ior`).
        extinction: bool,
    },
    /// `and`.
    And,
    /// `or`.
    Or,
    /// `xor`.
    Xor,
    /// `not`.
    Not,
}

impl MathOp {
    /// The input names of the op's arguments, in order (`switch`'s are built by the
    /// compiler).
    pub(crate) fn inputs(self) -> &'static [&'static str] {
        match self {
            MathOp::Add
            | MathOp::Subtract
            | MathOp::Multiply
            | MathOp::Divide
            | MathOp::Modulo
            | MathOp::Power
            | MathOp::Max
            | MathOp::Min
            | MathOp::Distance
            | MathOp::DotProduct
            | MathOp::CrossProduct
            | MathOp::And
            | MathOp::Or
            | MathOp::Xor => &["in1", "in2"],
            MathOp::Atan2 => &["iny", "inx"],
            MathOp::Unary(_)
            | MathOp::Normalize
            | MathOp::Magnitude
            | MathOp::MinComponent(_)
            | MathOp::MaxComponent(_)
            | MathOp::Convert { .. }
            | MathOp::Extract(_)
            | MathOp::Not => &["in"],
            MathOp::Invert => &["in", "amount"],
            MathOp::Clamp => &["in", "low", "high"],
            MathOp::Mix => &["fg", "bg", "mix"],
            MathOp::Remap => &["in", "inlow", "inhigh", "outlow", "outhigh"],
            MathOp::Smoothstep => &["in", "low", "high"],
            MathOp::Luminance => &["in", "lumacoeffs"],
            MathOp::Rotate2d => &["in", "amount"],
            MathOp::Rotate3d => &["in", "amount", "axis"],
            MathOp::IfGreater | MathOp::IfGreaterEq | MathOp::IfEqual => {
                &["value1", "value2", "in1", "in2"]
            }
            MathOp::Switch(_) => &[],
            MathOp::Combine(_) => &["in1", "in2", "in3", "in4"],
            MathOp::Normalmap => &["in", "scale", "normal", "tangent", "bitangent"],
            MathOp::RoughnessAnisotropy | MathOp::OpenPbrAnisotropy => &["roughness", "anisotropy"],
            MathOp::ArtisticIor { .. } => &["reflectivity", "edge_color"],
        }
    }
}

/// `v` in canonical form for type `ty`: scalars splatted (an `integer` truncated, a `boolean`
/// 0 or 1), channels beyond a vector's count zero.
#[inline]
pub(crate) fn canon(v: DVec4, ty: ValueType) -> DVec4 {
    match ty {
        ValueType::Float => DVec4::splat(v.x),
        ValueType::Integer => DVec4::splat(v.x.trunc()),
        ValueType::Boolean => DVec4::splat(if v.x != 0.0 && !v.x.is_nan() {
            1.0
        } else {
            0.0
        }),
        ValueType::Vector2 => DVec4::new(v.x, v.y, 0.0, 0.0),
        ValueType::Color3 | ValueType::Vector3 => DVec4::new(v.x, v.y, v.z, 0.0),
        _ => v,
    }
}

fn zip(a: DVec4, b: DVec4, f: impl Fn(f64, f64) -> f64) -> DVec4 {
    DVec4::new(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z), f(a.w, b.w))
}

fn map(a: DVec4, f: impl Fn(f64) -> f64) -> DVec4 {
    DVec4::new(f(a.x), f(a.y), f(a.z), f(a.w))
}

/// `convert` (`MaterialX.StandardNodes.md`, "convert"): a boolean, integer or float to
/// every channel; a colour or vector of N channels to M: the first `min(N, M)` copied, the
/// rest 0 except a fourth channel, which is 1; to `integer` truncated, to `boolean` nonzero.
fn convert(v: DVec4, from: ValueType, to: ValueType) -> DVec4 {
    let (n, m) = (from.components(), to.components());
    let mut out = v;
    if n > 1 && m == 4 && n < 4 {
        out.w = 1.0;
    }
    out
}

/// Evaluates `op` on canonical arguments; the caller canonicalises the result for the
/// output's type.
pub(crate) fn apply(op: MathOp, a: &[DVec4]) -> DVec4 {
    let arg = |i: usize| a.get(i).copied().unwrap_or(DVec4::ZERO);
    match op {
        MathOp::Add => arg(0) + arg(1),
        MathOp::Subtract => arg(0) - arg(1),
        MathOp::Multiply => arg(0) * arg(1),
        MathOp::Divide => arg(0) / arg(1),
        MathOp::Modulo => zip(arg(0), arg(1), |x, y| x - y * (x / y).floor()),
        MathOp::Power => zip(arg(0), arg(1), f64::powf),
        MathOp::Max => zip(arg(0), arg(1), f64::max),
        MathOp::Min => zip(arg(0), arg(1), f64::min),
        MathOp::Atan2 => zip(arg(0), arg(1), f64::atan2),
        MathOp::Unary(u) => map(arg(0), |x| u.apply(x)),
        MathOp::Invert => arg(1) - arg(0),
        MathOp::Clamp => zip(zip(arg(0), arg(1), f64::max), arg(2), f64::min),
        MathOp::Mix => arg(0) * arg(2) + arg(1) * (DVec4::ONE - arg(2)),
        MathOp::Remap => {
            let (x, il, ih, ol, oh) = (arg(0), arg(1), arg(2), arg(3), arg(4));
            ol + (x - il) * (oh - ol) / (ih - il)
        }
        MathOp::Smoothstep => {
            let (x, lo, hi) = (arg(0), arg(1), arg(2));
            DVec4::new(
                smoothstep(x.x, lo.x, hi.x),
                smoothstep(x.y, lo.y, hi.y),
                smoothstep(x.z, lo.z, hi.z),
                smoothstep(x.w, lo.w, hi.w),
            )
        }
        MathOp::Normalize => {
            let v = arg(0);
            v / v.length()
        }
        MathOp::Magnitude => DVec4::splat(arg(0).length()),
        MathOp::Distance => DVec4::splat((arg(0) - arg(1)).length()),
        MathOp::DotProduct => DVec4::splat(arg(0).dot(arg(1))),
        MathOp::CrossProduct => arg(0).xyz().cross(arg(1).xyz()).extend(0.0),
        MathOp::MinComponent(n) => {
            let v = arg(0).to_array();
            DVec4::splat(
                v[..(n as usize).clamp(1, 4)]
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min),
            )
        }
        MathOp::MaxComponent(n) => {
            let v = arg(0).to_array();
            DVec4::splat(
                v[..(n as usize).clamp(1, 4)]
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max),
            )
        }
        MathOp::Luminance => {
            let v = arg(0);
            let l = v.xyz().dot(arg(1).xyz());
            DVec4::new(l, l, l, v.w)
        }
        MathOp::Rotate2d => {
            let (s, c) = arg(1).x.to_radians().sin_cos();
            let v = arg(0);
            DVec4::new(c * v.x + s * v.y, -s * v.x + c * v.y, 0.0, 0.0)
        }
        MathOp::Rotate3d => {
            let v = arg(0).xyz();
            let axis = arg(2).xyz().normalize();
            let (s, c) = arg(1).x.to_radians().sin_cos();
            (v * c + v.cross(axis) * s + axis * axis.dot(v) * (1.0 - c)).extend(0.0)
        }
        MathOp::IfGreater => {
            if arg(0).x > arg(1).x {
                arg(2)
            } else {
                arg(3)
            }
        }
        MathOp::IfGreaterEq => {
            if arg(0).x >= arg(1).x {
                arg(2)
            } else {
                arg(3)
            }
        }
        MathOp::IfEqual => {
            if arg(0).x == arg(1).x {
                arg(2)
            } else {
                arg(3)
            }
        }
        MathOp::Switch(n) => arg(switch_index(arg(n as usize).x, n as usize)),
        MathOp::Convert { from, to } => convert(arg(0), from, to),
        MathOp::Extract(i) => DVec4::splat(arg(0)[(i as usize).min(3)]),
        MathOp::Combine(counts) => {
            let mut out = [0.0; 4];
            let mut k = 0;
            for (i, &c) in counts.iter().enumerate() {
                let v = arg(i).to_array();
                for &x in v.iter().take(c as usize) {
                    if k < 4 {
                        out[k] = x;
                        k += 1;
                    }
                }
            }
            DVec4::from_array(out)
        }
        MathOp::Normalmap => normalmap(arg(0), arg(1), arg(2), arg(3), arg(4)).extend(0.0),
        MathOp::RoughnessAnisotropy => {
            let (x, y) = roughness_anisotropy(arg(0).x, arg(1).x);
            DVec4::new(x, y, 0.0, 0.0)
        }
        MathOp::OpenPbrAnisotropy => {
            let (x, y) = open_pbr_anisotropy(arg(0).x, arg(1).x);
            DVec4::new(x, y, 0.0, 0.0)
        }
        MathOp::ArtisticIor { extinction } => {
            let (n, k) = artistic_ior(arg(0).xyz(), arg(1).xyz());
            if extinction { k } else { n }.extend(0.0)
        }
        MathOp::And => DVec4::splat(((arg(0).x != 0.0) && (arg(1).x != 0.0)) as u8 as f64),
        MathOp::Or => DVec4::splat(((arg(0).x != 0.0) || (arg(1).x != 0.0)) as u8 as f64),
        MathOp::Xor => DVec4::splat(((arg(0).x != 0.0) != (arg(1).x != 0.0)) as u8 as f64),
        MathOp::Not => DVec4::splat((arg(0).x == 0.0) as u8 as f64),
    }
}

/// `switch`'s selected input: `⌊which⌋` clamped to the `n` inputs (a NaN selects the first).
pub(crate) fn switch_index(which: f64, n: usize) -> usize {
    let i = which.floor();
    if i.is_nan() || i < 0.0 {
        0
    } else {
        (i as usize).min(n.saturating_sub(1))
    }
}

/// `mx_smoothstep_float`.
fn smoothstep(x: f64, low: f64, high: f64) -> f64 {
    if x >= high {
        1.0
    } else if x <= low {
        0.0
    } else {
        let t = ((x - low) / (high - low)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }
}

/// `mx_normalmap_vector2`, with an orthonormal frame about `n` standing in for a zero or
/// non-finite tangent or bitangent.
pub(crate) fn normalmap(v: DVec4, scale: DVec4, n: DVec4, t: DVec4, b: DVec4) -> DVec3 {
    let (n, mut t, mut b) = (n.xyz(), t.xyz(), b.xyz());
    let v = if v.xyz().length_squared() == 0.0 {
        DVec3::Z
    } else {
        v.xyz() * 2.0 - 1.0
    };
    let ok = |x: DVec3| x.is_finite() && x.length_squared() > 0.0;
    if !(ok(t) && ok(b)) && ok(n) {
        let nn = n.normalize();
        t = nn.any_orthonormal_vector();
        b = nn.cross(t);
    }
    (t * v.x * scale.x + b * v.y * scale.y + n * v.z).normalize()
}

/// `mx_roughness_anisotropy`.
pub(crate) fn roughness_anisotropy(roughness: f64, anisotropy: f64) -> (f64, f64) {
    let r2 = (roughness * roughness).clamp(1.0e-8, 1.0);
    if anisotropy > 0.0 {
        let aspect = (1.0 - anisotropy.clamp(0.0, 0.98)).sqrt();
        ((r2 / aspect).min(1.0), r2 * aspect)
    } else {
        (r2, r2)
    }
}

/// OpenPBR's `open_pbr_anisotropy` graph.
pub(crate) fn open_pbr_anisotropy(roughness: f64, anisotropy: f64) -> (f64, f64) {
    let inv = 1.0 - anisotropy;
    let ax = roughness * roughness * (2.0 / (1.0 + inv * inv)).sqrt();
    (ax, inv * ax)
}

/// `mx_artistic_ior` (Gulbrandsen 2014, "Artist Friendly Metallic Fresnel"): `r =
/// clamp(reflectivity, 0, 0.99)`, `n = mix(n_max, n_min, edge_color)` with `n_min = (1 − r)/(1
/// + r)`, `n_max = (1 + √r)/(1 − √r)`, `k = √max(((n + 1)²r − (n − 1)²)/(1 − r), 0)`.
pub(crate) fn artistic_ior(reflectivity: DVec3, edge_color: DVec3) -> (DVec3, DVec3) {
    let r = reflectivity.clamp(DVec3::ZERO, DVec3::splat(0.99));
    let rs = r.map(f64::sqrt);
    let n_min = (1.0 - r) / (1.0 + r);
    let n_max = (1.0 + rs) / (1.0 - rs);
    let n = n_max * (1.0 - edge_color) + n_min * edge_color;
    let (np1, nm1) = (n + 1.0, n - 1.0);
    let k2 = ((np1 * np1 * r - nm1 * nm1) / (1.0 - r)).max(DVec3::ZERO);
    (n, k2.map(f64::sqrt))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec4, b: DVec4) -> bool {
        (a - b).abs().max_element() < 1e-12
    }

    #[test]
    fn arithmetic_and_broadcast() {
        let c = DVec4::new(0.2, 0.4, 0.6, 0.0);
        let f = DVec4::splat(2.0);
        assert!(close(
            apply(MathOp::Multiply, &[c, f]),
            DVec4::new(0.4, 0.8, 1.2, 0.0)
        ));
        assert!(close(
            apply(MathOp::Modulo, &[DVec4::splat(-0.25), DVec4::ONE]),
            DVec4::splat(0.75)
        ));
        assert!(close(
            apply(
                MathOp::Unary(Unary::Sign),
                &[DVec4::new(-2.0, 0.0, 3.0, 0.0)]
            ),
            DVec4::new(-1.0, 0.0, 1.0, 0.0)
        ));
        assert!(close(
            apply(MathOp::Invert, &[c, DVec4::ONE]),
            DVec4::new(0.8, 0.6, 0.4, 1.0)
        ));
    }

    #[test]
    fn conversions() {
        let v2 = DVec4::new(0.1, 0.2, 0.0, 0.0);
        let c4 = convert(v2, ValueType::Vector2, ValueType::Color4);
        assert_eq!(c4, DVec4::new(0.1, 0.2, 0.0, 1.0));
        let f = canon(
            convert(DVec4::splat(0.5), ValueType::Float, ValueType::Color3),
            ValueType::Color3,
        );
        assert_eq!(f, DVec4::new(0.5, 0.5, 0.5, 0.0));
        assert_eq!(
            canon(DVec4::splat(-2.7), ValueType::Integer),
            DVec4::splat(-2.0)
        );
    }

    #[test]
    fn pbr_helpers() {
        assert_eq!(roughness_anisotropy(0.5, 0.0), (0.25, 0.25));
        let (x, y) = roughness_anisotropy(0.5, 0.75);
        assert!((x - 0.5).abs() < 1e-15 && (y - 0.125).abs() < 1e-15);
        let (x, y) = open_pbr_anisotropy(0.5, 0.0);
        assert!((x - 0.25).abs() < 1e-15 && (y - 0.25).abs() < 1e-15);
        // A white edge colour gives the lower bound n_min = (1 − r)/(1 + r).
        let (n, k) = artistic_ior(DVec3::splat(0.04), DVec3::ONE);
        assert!((n.x - 0.96 / 1.04).abs() < 1e-12);
        let k2 = ((n.x + 1.0).powi(2) * 0.04 - (n.x - 1.0).powi(2)) / 0.96;
        assert!((k.x - k2.max(0.0).sqrt()).abs() < 1e-12);
    }
}
