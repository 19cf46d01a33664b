//! Conversions from `openusd` values to plain f64 / glam values, accepting every precision USD
//! allows for a role (half, float, double; int where a number is expected).

use glam::{DMat4, DQuat, DVec2, DVec3, DVec4};
use openusd::sdf::Value;

/// A scalar number of any USD numeric type.
pub fn as_f64(v: &Value) -> Option<f64> {
    Some(match v {
        Value::Half(x) => x.to_f64(),
        Value::Float(x) => f64::from(*x),
        Value::Double(x) => *x,
        Value::Int(x) => f64::from(*x),
        Value::Uint(x) => f64::from(*x),
        Value::Int64(x) => *x as f64,
        Value::Uint64(x) => *x as f64,
        Value::Uchar(x) => f64::from(*x),
        Value::TimeCode(t) => t.0,
        _ => return None,
    })
}

/// A boolean (`bool`, or an integer 0/1: `openusd` 0.6 parses `bool` time samples written as
/// `1: 0` type-blind, as `Int64`).
pub fn as_bool(v: &Value) -> Option<bool> {
    match v {
        Value::Bool(b) => Some(*b),
        Value::Int(i) => Some(*i != 0),
        Value::Int64(i) => Some(*i != 0),
        _ => None,
    }
}

/// A token or string.
pub fn as_text(v: &Value) -> Option<String> {
    match v {
        Value::Token(t) => Some(t.as_str().to_owned()),
        Value::String(s) => Some(s.clone()),
        _ => None,
    }
}

/// A 2-vector of any precision.
pub fn as_vec2(v: &Value) -> Option<DVec2> {
    Some(match v {
        Value::Vec2h(a) => DVec2::new(a.x.to_f64(), a.y.to_f64()),
        Value::Vec2f(a) => DVec2::new(a.x.into(), a.y.into()),
        Value::Vec2d(a) => DVec2::new(a.x, a.y),
        Value::Vec2i(a) => DVec2::new(a.x.into(), a.y.into()),
        _ => return None,
    })
}

/// A 3-vector of any precision (points, colours, normals, scales).
pub fn as_vec3(v: &Value) -> Option<DVec3> {
    Some(match v {
        Value::Vec3h(a) => DVec3::new(a.x.to_f64(), a.y.to_f64(), a.z.to_f64()),
        Value::Vec3f(a) => DVec3::new(a.x.into(), a.y.into(), a.z.into()),
        Value::Vec3d(a) => DVec3::new(a.x, a.y, a.z),
        Value::Vec3i(a) => DVec3::new(a.x.into(), a.y.into(), a.z.into()),
        _ => return None,
    })
}

/// A 4-vector of any precision.
pub fn as_vec4(v: &Value) -> Option<DVec4> {
    Some(match v {
        Value::Vec4h(a) => DVec4::new(a.x.to_f64(), a.y.to_f64(), a.z.to_f64(), a.w.to_f64()),
        Value::Vec4f(a) => DVec4::new(a.x.into(), a.y.into(), a.z.into(), a.w.into()),
        Value::Vec4d(a) => DVec4::new(a.x, a.y, a.z, a.w),
        Value::Vec4i(a) => DVec4::new(a.x.into(), a.y.into(), a.z.into(), a.w.into()),
        _ => return None,
    })
}

/// A `matrix4d` as a glam matrix applying it to column vectors (see `lux_math::usd_matrix`).
pub fn as_matrix4(v: &Value) -> Option<DMat4> {
    match v {
        Value::Matrix4d(m) => {
            let a = m.0;
            Some(lux_math::usd_matrix([
                [a[0], a[1], a[2], a[3]],
                [a[4], a[5], a[6], a[7]],
                [a[8], a[9], a[10], a[11]],
                [a[12], a[13], a[14], a[15]],
            ]))
        }
        _ => None,
    }
}

/// A quaternion of any precision (`GfQuat`: real part `w`, imaginary `x, y, z`), unnormalised.
pub fn as_quat(v: &Value) -> Option<DQuat> {
    Some(match v {
        Value::Quath(q) => DQuat::from_xyzw(q.x.to_f64(), q.y.to_f64(), q.z.to_f64(), q.w.to_f64()),
        Value::Quatf(q) => DQuat::from_xyzw(q.x.into(), q.y.into(), q.z.into(), q.w.into()),
        Value::Quatd(q) => DQuat::from_xyzw(q.x, q.y, q.z, q.w),
        _ => return None,
    })
}

/// An array of quaternions of any precision (`quath[]`, `quatf[]`, `quatd[]`), unnormalised.
pub fn as_quat_array(v: &Value) -> Option<Vec<DQuat>> {
    Some(match v {
        Value::QuathVec(a) => a
            .iter()
            .map(|q| DQuat::from_xyzw(q.x.to_f64(), q.y.to_f64(), q.z.to_f64(), q.w.to_f64()))
            .collect(),
        Value::QuatfVec(a) => a
            .iter()
            .map(|q| DQuat::from_xyzw(q.x.into(), q.y.into(), q.z.into(), q.w.into()))
            .collect(),
        Value::QuatdVec(a) => a
            .iter()
            .map(|q| DQuat::from_xyzw(q.x, q.y, q.z, q.w))
            .collect(),
        _ => return None,
    })
}

/// An array of 3-vectors of any precision.
pub fn as_vec3_array(v: &Value) -> Option<Vec<DVec3>> {
    Some(match v {
        Value::Vec3hVec(a) => a
            .iter()
            .map(|p| DVec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64()))
            .collect(),
        Value::Vec3fVec(a) => a
            .iter()
            .map(|p| DVec3::new(p.x.into(), p.y.into(), p.z.into()))
            .collect(),
        Value::Vec3dVec(a) => a.iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect(),
        _ => return None,
    })
}

/// A numeric array of 1 to 4 components an element (`float[]`, `int[]`, `float2[]`,
/// `color3f[]`, `float4[]`, any precision) as 4-vectors padded with zeros: what a
/// `UsdPrimvarReader_*` reads.
pub fn as_dvec4_array(v: &Value) -> Option<Vec<DVec4>> {
    if let Some(a) = as_vec3_array(v) {
        return Some(a.into_iter().map(|p| p.extend(0.0)).collect());
    }
    if let Some(a) = as_vec2_array(v) {
        return Some(
            a.into_iter()
                .map(|p| DVec4::new(p.x, p.y, 0.0, 0.0))
                .collect(),
        );
    }
    if let Some(a) = as_f64_array(v)
        .or_else(|| as_int_array(v).map(|a| a.into_iter().map(|x| x as f64).collect()))
    {
        return Some(
            a.into_iter()
                .map(|x| DVec4::new(x, 0.0, 0.0, 0.0))
                .collect(),
        );
    }
    Some(match v {
        Value::Vec4hVec(a) => a
            .iter()
            .map(|p| DVec4::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64(), p.w.to_f64()))
            .collect(),
        Value::Vec4fVec(a) => a
            .iter()
            .map(|p| DVec4::new(p.x.into(), p.y.into(), p.z.into(), p.w.into()))
            .collect(),
        Value::Vec4dVec(a) => a.iter().map(|p| DVec4::new(p.x, p.y, p.z, p.w)).collect(),
        _ => return None,
    })
}

/// An array of 2-vectors of any precision (texture coordinates).
pub fn as_vec2_array(v: &Value) -> Option<Vec<DVec2>> {
    Some(match v {
        Value::Vec2hVec(a) => a
            .iter()
            .map(|p| DVec2::new(p.x.to_f64(), p.y.to_f64()))
            .collect(),
        Value::Vec2fVec(a) => a
            .iter()
            .map(|p| DVec2::new(p.x.into(), p.y.into()))
            .collect(),
        Value::Vec2dVec(a) => a.iter().map(|p| DVec2::new(p.x, p.y)).collect(),
        _ => return None,
    })
}

/// An integer array (`int[]` and wider/unsigned variants), as i64.
pub fn as_int_array(v: &Value) -> Option<Vec<i64>> {
    Some(match v {
        Value::IntVec(a) => a.iter().map(|x| i64::from(*x)).collect(),
        Value::UintVec(a) => a.iter().map(|x| i64::from(*x)).collect(),
        Value::Int64Vec(a) => a.clone(),
        Value::Uint64Vec(a) => a.iter().map(|x| i64::try_from(*x).unwrap_or(-1)).collect(),
        _ => return None,
    })
}

/// A numeric array of any scalar type.
pub fn as_f64_array(v: &Value) -> Option<Vec<f64>> {
    Some(match v {
        Value::HalfVec(a) => a.iter().map(|x| x.to_f64()).collect(),
        Value::FloatVec(a) => a.iter().map(|x| f64::from(*x)).collect(),
        Value::DoubleVec(a) => a.clone(),
        Value::IntVec(a) => a.iter().map(|x| f64::from(*x)).collect(),
        _ => return None,
    })
}

/// An asset path: `(authored, resolved)`. A one-element `asset[]` is accepted too (see
/// [`crate::usda_fix`]).
pub fn as_asset(v: &Value) -> Option<(String, Option<String>)> {
    match v {
        Value::AssetPath(a) => Some((
            a.asset_path().to_owned(),
            a.resolved_path().map(str::to_owned),
        )),
        Value::AssetPathVec(a) if a.len() == 1 => Some((
            a[0].asset_path().to_owned(),
            a[0].resolved_path().map(str::to_owned),
        )),
        Value::String(s) => Some((s.clone(), None)),
        _ => None,
    }
}

/// The USD-ish name of a value's type, for error messages.
pub fn type_label(v: &Value) -> String {
    let s: &'static str = v.into();
    s.to_owned()
}
