//! `UsdGeomXformable`: a prim's local transform from its `xformOpOrder`, in f64.
//!
//! Conventions: each op yields a glam matrix acting on column vectors (the transpose of USD's
//! row-vector matrix). For `xformOpOrder = [A, B, C]` USD applies the **last** op to a point
//! first: row-vector `p' = p · C · B · A`, i.e. column form `local = A * B * C` — the ops multiply
//! in list order. The world transform is `parent_world * local` unless the prim resets the stack.

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use crate::value;
use glam::{DMat4, DQuat, DVec3};
use openusd::usd::Prim;

/// The local transform of `prim` and whether it resets the parent stack
/// (`!resetXformStack!` first in `xformOpOrder`).
///
/// Supported ops: `transform`, `translate`, `scale`, `rotateX/Y/Z`, the six `rotateXYZ` …
/// `rotateZYX` orders (angles in degrees), `orient` (quaternion), each with an optional
/// `:suffix` and the `!invert!` prefix. Unknown op types and singular inverted ops are skipped
/// with a warning. An op named in the order but not authored is skipped with a warning.
pub fn local_transform(r: &mut Reader<'_>, prim: &Prim) -> Result<(DMat4, bool), LoadError> {
    let order = match r.raw_default(prim, "xformOpOrder")? {
        None => return Ok((DMat4::IDENTITY, false)),
        Some(v) => match v {
            openusd::sdf::Value::TokenVec(t) => t.iter().map(|t| t.as_str().to_owned()).collect(),
            openusd::sdf::Value::StringVec(s) => s,
            other => {
                return Err(LoadError::AttributeType {
                    file: r.file.clone(),
                    prim: prim.path().to_string(),
                    attribute: "xformOpOrder".into(),
                    expected: "a token array",
                    found: value::type_label(&other),
                });
            }
        },
    };
    let order: Vec<String> = order;
    let mut reset = false;
    let mut local = DMat4::IDENTITY;
    for (i, entry) in order.iter().enumerate() {
        if entry == "!resetXformStack!" {
            // Only meaningful first; elsewhere it discards the ops before it as well.
            reset = true;
            local = DMat4::IDENTITY;
            if i != 0 {
                r.warn(
                    prim,
                    WarningKind::Unsupported,
                    "!resetXformStack! not first in xformOpOrder: ops before it are discarded",
                );
            }
            continue;
        }
        let (invert, name) = match entry.strip_prefix("!invert!") {
            Some(n) => (true, n),
            None => (false, entry.as_str()),
        };
        let Some(m) = op_matrix(r, prim, name)? else {
            continue;
        };
        let m = if invert {
            let det = m.determinant();
            if det == 0.0 || !det.is_finite() {
                r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("!invert!{name}: op is singular; skipped"),
                );
                continue;
            }
            m.inverse()
        } else {
            m
        };
        local *= m;
    }
    if !local.is_finite() {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            "local transform is not finite; using identity",
        );
        local = DMat4::IDENTITY;
    }
    Ok((local, reset))
}

/// The matrix of one op attribute (`xformOp:<type>[:suffix]`) at the load time.
fn op_matrix(r: &mut Reader<'_>, prim: &Prim, name: &str) -> Result<Option<DMat4>, LoadError> {
    let mut parts = name.split(':');
    let (Some("xformOp"), Some(kind)) = (parts.next(), parts.next()) else {
        r.warn(
            prim,
            WarningKind::Unsupported,
            format!("xformOpOrder entry {name:?} is not an xformOp; skipped"),
        );
        return Ok(None);
    };
    let Some(v) = r.raw(prim, name)? else {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!("{name} is listed in xformOpOrder but has no value; skipped"),
        );
        return Ok(None);
    };
    let bad = |expected: &'static str| LoadError::AttributeType {
        file: r.file.clone(),
        prim: prim.path().to_string(),
        attribute: name.to_owned(),
        expected,
        found: value::type_label(&v),
    };
    let m = match kind {
        "transform" => snap_affine(value::as_matrix4(&v).ok_or_else(|| bad("a matrix4d"))?),
        "translate" => {
            DMat4::from_translation(value::as_vec3(&v).ok_or_else(|| bad("a 3-vector"))?)
        }
        "scale" => DMat4::from_scale(value::as_vec3(&v).ok_or_else(|| bad("a 3-vector"))?),
        "rotateX" | "rotateY" | "rotateZ" => {
            let deg = value::as_f64(&v).ok_or_else(|| bad("a number"))?;
            let a = deg.to_radians();
            match kind {
                "rotateX" => DMat4::from_rotation_x(a),
                "rotateY" => DMat4::from_rotation_y(a),
                _ => DMat4::from_rotation_z(a),
            }
        }
        "orient" => {
            let q = value::as_quat(&v).ok_or_else(|| bad("a quaternion"))?;
            let len = q.length();
            if len == 0.0 || !len.is_finite() {
                r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("{name}: zero quaternion; skipped"),
                );
                return Ok(None);
            }
            DMat4::from_quat(DQuat::from_xyzw(q.x / len, q.y / len, q.z / len, q.w / len))
        }
        k if k.len() == 9 && k.starts_with("rotate") => {
            let axes = &k[6..];
            let deg = value::as_vec3(&v).ok_or_else(|| bad("a 3-vector"))?;
            euler(axes, deg).ok_or_else(|| bad("a rotateXYZ-style op"))?
        }
        other => {
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!("xform op type {other:?} ({name}) is not supported; skipped"),
            );
            return Ok(None);
        }
    };
    Ok(Some(m))
}

/// Largest deviation of a `transform` op's last USD column from `(0, 0, 0, 1)` that counts as
/// rounding noise (DCC exports write `1.0000000000000002`).
pub const AFFINE_TOLERANCE: f64 = 1e-9;

/// `m` with its last USD column (glam's bottom row) set to exactly `(0, 0, 0, 1)` when it is
/// within [`AFFINE_TOLERANCE`] of it; a truly projective matrix is returned unchanged (and
/// refused where an affine map is needed, e.g. by a light).
pub fn snap_affine(mut m: DMat4) -> DMat4 {
    let r = m.row(3);
    let dev =
        r.x.abs()
            .max(r.y.abs())
            .max(r.z.abs())
            .max((r.w - 1.0).abs());
    if dev <= AFFINE_TOLERANCE {
        m.x_axis.w = 0.0;
        m.y_axis.w = 0.0;
        m.z_axis.w = 0.0;
        m.w_axis.w = 1.0;
    }
    m
}

/// A three-axis rotation `rotateABC` with angles `deg = (x, y, z)` in degrees: rotate about A
/// first, then B, then C (column form `R_C · R_B · R_A`). `None` unless `axes` is a permutation of
/// `XYZ`.
pub fn euler(axes: &str, deg: DVec3) -> Option<DMat4> {
    let mut seen = [false; 3];
    let mut m = DMat4::IDENTITY;
    for c in axes.chars() {
        let (i, r) = match c {
            'X' => (0, DMat4::from_rotation_x(deg.x.to_radians())),
            'Y' => (1, DMat4::from_rotation_y(deg.y.to_radians())),
            'Z' => (2, DMat4::from_rotation_z(deg.z.to_radians())),
            _ => return None,
        };
        if seen[i] {
            return None;
        }
        seen[i] = true;
        m = r * m;
    }
    (axes.len() == 3).then_some(m)
}

#[cfg(test)]
mod tests {
    #[test]
    fn rounding_noise_in_the_last_column_is_snapped() {
        use glam::{DMat4, DVec4};
        let mut m = DMat4::from_translation(glam::DVec3::new(1.0, 2.0, 3.0));
        m.w_axis.w = 1.000_000_000_000_000_2;
        m.x_axis.w = -3e-17;
        let s = super::snap_affine(m);
        assert_eq!(s.row(3), DVec4::new(0.0, 0.0, 0.0, 1.0));
        assert_eq!(s.w_axis.truncate(), glam::DVec3::new(1.0, 2.0, 3.0));
        let mut p = DMat4::IDENTITY;
        p.x_axis.w = 0.25;
        assert_eq!(
            super::snap_affine(p),
            p,
            "a projective matrix stays as authored"
        );
    }

    use super::*;

    #[test]
    fn euler_orders_apply_first_axis_first() {
        // rotateXYZ (90, 90, 0): X first maps +Y to +Z, then Y maps +Z to +X.
        let m = euler("XYZ", DVec3::new(90.0, 90.0, 0.0)).unwrap();
        assert!((m.transform_vector3(DVec3::Y) - DVec3::X).length() < 1e-12);
        // rotateZYX (90, 90, 0): Z is zero, then Y maps +Y to +Y, then X maps +Y to +Z.
        let m = euler("ZYX", DVec3::new(90.0, 90.0, 0.0)).unwrap();
        assert!((m.transform_vector3(DVec3::Y) - DVec3::Z).length() < 1e-12);
        assert!(euler("XXY", DVec3::ZERO).is_none());
        assert!(euler("XY", DVec3::ZERO).is_none());
    }
}
