//! UsdSkel posing: a skinned gprim (a `Mesh`, curves, points or an implicit surface bound to a
//! `SkelRoot`) drawn at the load time as usd-core's `UsdSkelBakeSkinning` poses it.
//!
//! What is read, and how UsdSkel (26.11) resolves it:
//!
//! - **Binding** (`UsdSkelCache::Populate`): from the `SkelRoot` down to the gprim, every prim
//!   with `SkelBindingAPI` applied may author `skel:skeleton`, `primvars:skel:jointIndices`,
//!   `primvars:skel:jointWeights`, `primvars:skel:geomBindTransform`, `skel:joints` and
//!   `primvars:skel:skinningMethod`; the nearest authored opinion wins. Properties on prims
//!   without the API are ignored, and nothing outside a `SkelRoot` is posed. `skel:blendShapes`
//!   and `skel:blendShapeTargets` are read on the gprim itself only.
//! - **Animation** (`UsdSkelBindingAPI::GetInheritedAnimationSource` of the skeleton): the
//!   `SkelAnimation`'s `joints`, `translations`, `rotations`, `scales` at the load time
//!   (interpolated by the [`Reader`]), mapped by joint name onto the skeleton's `joints`; joints
//!   the animation does not cover, or no usable animation, take the skeleton's
//!   `restTransforms`.
//! - **Skinning transforms** (`UsdSkelSkeletonQuery::ComputeSkinningTransforms`): in UsdSkel's
//!   row-vector form `skinning[j] = inverse(bindTransforms[j]) × skelSpace[j]`, with
//!   `skelSpace[j] = local[j] × skelSpace[parent(j)]`; in the column form used here
//!   `S[j] = skelSpace[j] · bind[j]⁻¹`.
//! - **Points** (`UsdSkelSkinPointsLBS`): `p' = Σₖ wₖ · S[jₖ] · G · p` with `G` the geom bind
//!   transform, after blend shapes (`p + Σ wₛ · offsetₛ`), in the skeleton's space. The weights
//!   are used as authored (UsdSkel does not normalise them when skinning; a set that does not
//!   sum to 1 is reported). `constant` influences pose rigidly (`UsdSkelSkinTransformLBS`).
//!   `primvars:skel:skinningMethod = "dualQuaternion"` blends the joints' dual quaternions
//!   instead (`UsdSkelSkinPointsDQS`, [`skin_point_dqs`]).
//! - **Where it goes**: skinned points are in skeleton space, so the posed gprim is drawn with
//!   the *skeleton's* local-to-world transform; the gprim's own transform no longer applies
//!   (`UsdSkelBakeSkinning` writes `skelPoint × skelLocalToWorld × inverse(gprimLocalToWorld)`
//!   as the gprim's points). A gprim posed by blend shapes alone keeps its own transform.
//! - **Normals** (`UsdSkelSkinNormalsLBS`): `n' = Σₖ wₖ · S₃[jₖ]⁻ᵀ · G₃⁻ᵀ · n`, after the blend
//!   shapes' `normalOffsets`, per triangle corner with the influences of the corner's point.
//!
//! Whatever cannot be posed as authored is a warning naming the prim, and the gprim is drawn as
//! authored (as usd-core leaves it unbaked).

use crate::error::{LoadError, WarningKind};
use crate::mesh::{Gprim, Topology};
use crate::reader::Reader;
use crate::value;
use crate::xform::local_transform;
use glam::{DMat3, DMat4, DQuat, DVec3};
use openusd::sdf::Value;
use openusd::usd::Prim;

/// The tolerance UsdSkel's blend-shape query and rigid skinning compare weights with.
const EPS: f64 = 1e-6;

/// The joint parents of a `Skeleton.joints` array (UsdSkelTopology): joint `i`'s parent is the
/// nearest ancestor path of `joints[i]` (`"A/B/C"` → `"A/B"`, else `"A"`) present in the array;
/// `None` for a root joint.
pub fn joint_parents(joints: &[String]) -> Vec<Option<usize>> {
    let index: std::collections::HashMap<&str, usize> = joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.as_str(), i))
        .collect();
    joints
        .iter()
        .map(|j| {
            let mut path = j.as_str();
            while let Some((parent, _)) = path.rsplit_once('/') {
                if let Some(&p) = index.get(parent) {
                    return Some(p);
                }
                path = parent;
            }
            None
        })
        .collect()
}

/// A joint-local transform from `SkelAnimation` components (`UsdSkelMakeTransform`): UsdSkel's
/// row-vector `scale × rotate × translate`, i.e. the column-form `T · R · S`. The quaternion is
/// used as stored (`GfMatrix3f(GfQuatf)` does not normalise it either).
pub fn joint_local_transform(translation: DVec3, rotation: DQuat, scale: DVec3) -> DMat4 {
    let r = DMat3::from_quat(rotation);
    DMat4::from_cols(
        (r.x_axis * scale.x).extend(0.0),
        (r.y_axis * scale.y).extend(0.0),
        (r.z_axis * scale.z).extend(0.0),
        translation.extend(1.0),
    )
}

/// Skeleton-space joint transforms from joint-local ones (`UsdSkelConcatJointTransforms`):
/// `skel[i] = skel[parent(i)] · local[i]` (UsdSkel's `local × parentSkel`), a root joint's own.
/// `Err(i)` when joint `i`'s parent does not come before it (UsdSkel requires that order).
pub fn concat_joint_transforms(
    parents: &[Option<usize>],
    local: &[DMat4],
) -> Result<Vec<DMat4>, usize> {
    let mut out: Vec<DMat4> = Vec::with_capacity(local.len());
    for (i, l) in local.iter().enumerate() {
        match parents.get(i).copied().flatten() {
            Some(p) if p < i => out.push(out[p] * *l),
            Some(_) => return Err(i),
            None => out.push(*l),
        }
    }
    Ok(out)
}

/// Linear blend skinning of one point (`UsdSkelSkinPointsLBS`): `Σₖ wₖ · S[jₖ] · G · p` over the
/// point's influences `(jₖ, wₖ)` (zero weights skipped, as UsdSkel does). `None` when an index
/// is outside `skinning` (UsdSkel then leaves the whole prim unposed).
pub fn skin_point_lbs(
    p: DVec3,
    geom_bind: &DMat4,
    skinning: &[DMat4],
    influences: &[(i64, f64)],
) -> Option<DVec3> {
    let bound = geom_bind.transform_point3(p);
    let mut out = DVec3::ZERO;
    for &(j, w) in influences {
        let m = skinning.get(usize::try_from(j).ok()?)?;
        if w != 0.0 {
            out += m.transform_point3(bound) * w;
        }
    }
    Some(out)
}

/// The normal transform of one point under linear blend skinning (`UsdSkelSkinNormalsLBS`):
/// `Σₖ wₖ · S₃[jₖ]⁻ᵀ · G₃⁻ᵀ`, `S₃` and `G₃` the upper 3×3 blocks (the inverse transposes are
/// passed in, `inv_t[j] = S₃[j]⁻ᵀ`, `geom_inv_t = G₃⁻ᵀ`). `None` for an index out of range.
pub fn normal_matrix_lbs(
    geom_inv_t: &DMat3,
    inv_t: &[DMat3],
    influences: &[(i64, f64)],
) -> Option<DMat3> {
    let mut m = DMat3::ZERO;
    for &(j, w) in influences {
        let t = inv_t.get(usize::try_from(j).ok()?)?;
        if w != 0.0 {
            m += *t * w;
        }
    }
    Some(m * *geom_inv_t)
}

/// The rigid transform of a gprim with `constant` influences (`UsdSkelSkinTransformLBS`): one
/// influence of weight 1 (±1e-6) gives `S[j] · G`; otherwise the frame `G` (its origin and its
/// three axes) is skinned point by point and the affine map through the skinned frame
/// returned. `None` for an index out of range.
pub fn rigid_transform_lbs(
    geom_bind: &DMat4,
    skinning: &[DMat4],
    influences: &[(i64, f64)],
) -> Option<DMat4> {
    if let [(j, w)] = influences
        && (w - 1.0).abs() <= EPS
    {
        return Some(*skinning.get(usize::try_from(*j).ok()?)? * *geom_bind);
    }
    let pivot = geom_bind.w_axis.truncate();
    let frame = [
        pivot + geom_bind.x_axis.truncate(),
        pivot + geom_bind.y_axis.truncate(),
        pivot + geom_bind.z_axis.truncate(),
        pivot,
    ];
    let mut out = [DVec3::ZERO; 4];
    for (o, f) in out.iter_mut().zip(frame) {
        *o = skin_point_lbs(f, &DMat4::IDENTITY, skinning, influences)?;
    }
    let t = out[3];
    Some(DMat4::from_cols(
        (out[0] - t).extend(0.0),
        (out[1] - t).extend(0.0),
        (out[2] - t).extend(0.0),
        t.extend(1.0),
    ))
}

/// The rotation and stretch of a 3×3 linear map, `m = rotation · stretch` (the polar
/// decomposition `GfMatrix4d::Factor` computes: the stretch symmetric, negated with the
/// rotation when `m` mirrors, so that the rotation is proper). `None` for a singular map.
pub fn polar_rotation(m: &DMat3) -> Option<(DMat3, DMat3)> {
    let det = m.determinant();
    if !det.is_finite() || det.abs() < 1e-10 {
        return None;
    }
    // Newton's iteration X ← (X + X⁻ᵀ)/2 converges to the orthogonal polar factor.
    let mut x = *m;
    for _ in 0..64 {
        let next = (x + x.inverse().transpose()) * 0.5;
        let done = (next - x).to_cols_array().iter().all(|d| d.abs() < 1e-15);
        x = next;
        if done {
            break;
        }
    }
    if det < 0.0 {
        x = -x;
    }
    Some((x, x.transpose() * *m))
}

/// A joint's skinning transform as dual-quaternion skinning uses it (UsdSkel's
/// `_ConvertToDualQuaternions`): the rotation `real` and translation (`dual = ½ (t, 0) · real`)
/// of the transform, and the stretch applied before them by linear blending.
#[derive(Clone, Copy, Debug)]
pub struct JointDq {
    /// The rotation quaternion (zero for a singular transform).
    pub real: DQuat,
    /// The dual part carrying the translation.
    pub dual: DQuat,
    /// The stretch (`rotationᵀ · M₃`; identity for a singular transform).
    pub stretch: DMat3,
}

impl JointDq {
    /// The dual quaternion of the affine transform `m` (see [`polar_rotation`]).
    pub fn new(m: &DMat4) -> JointDq {
        match polar_rotation(&DMat3::from_mat4(*m)) {
            Some((rot, stretch)) => {
                let real = DQuat::from_mat3(&rot);
                let t = m.w_axis.truncate();
                let dual = DQuat::from_xyzw(t.x, t.y, t.z, 0.0) * real * 0.5;
                JointDq {
                    real,
                    dual,
                    stretch,
                }
            }
            None => JointDq {
                real: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                dual: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                stretch: DMat3::IDENTITY,
            },
        }
    }
}

/// Whether any joint stretches (its stretch differs from the identity by more than 1e-6 in any
/// element): UsdSkel then blends the stretches linearly before the dual quaternions.
pub fn joints_stretch(joints: &[JointDq]) -> bool {
    joints.iter().any(|j| {
        (j.stretch - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .any(|d| d.abs() > 1e-6)
    })
}

/// The blended, normalised dual quaternion of one point's influences and its blended stretch
/// (`UsdSkelSkinPointsDQS`): each joint's weight is negated when its rotation lies in the other
/// hemisphere from the heaviest influence's. `None` for an index out of range.
fn blend_dq(
    joints: &[JointDq],
    influences: &[(i64, f64)],
    stretch: bool,
) -> Option<(DQuat, DQuat, DMat3)> {
    let mut pivot: Option<(usize, f64)> = None;
    for &(j, w) in influences {
        if let Ok(j) = usize::try_from(j)
            && j < joints.len()
            && pivot.is_none_or(|(_, m)| m < w)
        {
            pivot = Some((j, w));
        }
    }
    let pivot_q = pivot.map_or(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), |(j, _)| {
        joints[j].real
    });
    let zero = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let (mut real, mut dual, mut s) = (zero, zero, DMat3::ZERO);
    for &(j, w) in influences {
        let joint = joints.get(usize::try_from(j).ok()?)?;
        if w == 0.0 {
            continue;
        }
        if stretch {
            s += joint.stretch * w;
        }
        let w = if joint.real.dot(pivot_q) < 0.0 { -w } else { w };
        real += joint.real * w;
        dual += joint.dual * w;
    }
    // GfDualQuatd::Normalize: unit real part, dual part made orthogonal to it.
    let len = real.length();
    if len < 1e-10 {
        real = DQuat::IDENTITY;
        dual = zero;
    } else {
        real *= 1.0 / len;
        dual *= 1.0 / len;
        dual = dual - real * real.dot(dual);
    }
    Some((real, dual, if stretch { s } else { DMat3::IDENTITY }))
}

fn dq_transform(real: DQuat, dual: DQuat, p: DVec3) -> DVec3 {
    let t = dual * real.conjugate() * 2.0;
    real.mul_vec3(p) + DVec3::new(t.x, t.y, t.z)
}

/// Dual-quaternion skinning of one point (`UsdSkelSkinPointsDQS`): `G · p` stretched by the
/// blended joint stretches (when any joint stretches), then rotated and translated by the
/// normalised blend of the joints' dual quaternions. `None` for an index out of range.
pub fn skin_point_dqs(
    p: DVec3,
    geom_bind: &DMat4,
    joints: &[JointDq],
    stretch: bool,
    influences: &[(i64, f64)],
) -> Option<DVec3> {
    let bound = geom_bind.transform_point3(p);
    let (real, dual, s) = blend_dq(joints, influences, stretch)?;
    Some(dq_transform(real, dual, s * bound))
}

/// The rigid transform of `constant` influences under dual-quaternion skinning
/// (`UsdSkelSkinTransformDQS`): as [`rigid_transform_lbs`], the frame of `G` skinned point by
/// point with [`skin_point_dqs`]'s blend.
pub fn rigid_transform_dqs(
    geom_bind: &DMat4,
    skinning: &[DMat4],
    joints: &[JointDq],
    stretch: bool,
    influences: &[(i64, f64)],
) -> Option<DMat4> {
    if let [(j, w)] = influences
        && (w - 1.0).abs() <= EPS
    {
        return Some(*skinning.get(usize::try_from(*j).ok()?)? * *geom_bind);
    }
    let (real, dual, s) = blend_dq(joints, influences, stretch)?;
    let pivot = geom_bind.w_axis.truncate();
    let f = |p: DVec3| dq_transform(real, dual, s * p);
    let t = f(pivot);
    Some(DMat4::from_cols(
        (f(pivot + geom_bind.x_axis.truncate()) - t).extend(0.0),
        (f(pivot + geom_bind.y_axis.truncate()) - t).extend(0.0),
        (f(pivot + geom_bind.z_axis.truncate()) - t).extend(0.0),
        t.extend(1.0),
    ))
}

/// The normal transform of one point under dual-quaternion skinning
/// (`UsdSkelSkinNormalsDQS`): the joints' normal matrices `S₃⁻ᵀ` split into rotation and
/// stretch ([`polar_rotation`]), the stretches blended linearly (when any stretches), the
/// rotations blended as quaternions (hemisphere-aligned to the heaviest influence) and
/// normalised, after `G₃⁻ᵀ`. `None` for an index out of range.
///
/// `normal_joints[j]` is `JointDq::new` of joint `j`'s `S₃⁻ᵀ`, `stretch` whether any of them
/// stretches ([`joints_stretch`]).
pub fn normal_matrix_dqs(
    geom_inv_t: &DMat3,
    normal_joints: &[JointDq],
    stretch: bool,
    influences: &[(i64, f64)],
) -> Option<DMat3> {
    let (real, _, s) = blend_dq(normal_joints, influences, stretch)?;
    Some(DMat3::from_quat(real) * s * *geom_inv_t)
}

/// Which shape a blend-shape sub-shape is: the rest (weight 0), the primary `offsets` (weight
/// 1), or the `k`-th valid inbetween.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SubShape {
    /// The rest shape (no offsets).
    Null,
    /// The `BlendShape`'s `offsets`.
    Primary,
    /// The `k`-th inbetween passed to [`sub_shape_weights`].
    Inbetween(usize),
}

/// The weighted sub-shapes of one blend shape at weight `w`
/// (`UsdSkelBlendShapeQuery::ComputeSubShapeWeights`): without inbetweens, the primary shape at
/// `w` (any `w`, negative or above 1, extrapolates); with inbetweens (each at its `weight`
/// metadata; ones within 1e-6 of 0 or 1 are dropped, as UsdSkel does), the two sub-shapes of
/// `{0 (rest), inbetweens…, 1 (primary)}` around `w`, weighted `1 − α` and `α` with
/// `α = (w − w₀)/(w₁ − w₀)`, extrapolating from the first or last pair outside that range.
pub fn sub_shape_weights(w: f64, inbetween_weights: &[f64]) -> Vec<(SubShape, f64)> {
    let mut subs: Vec<(f64, SubShape)> = vec![(1.0, SubShape::Primary), (0.0, SubShape::Null)];
    for (k, &iw) in inbetween_weights.iter().enumerate() {
        if iw.is_finite() && (iw - 0.0).abs() > EPS && (iw - 1.0).abs() > EPS {
            subs.push((iw, SubShape::Inbetween(k)));
        }
    }
    if subs.len() < 3 {
        return vec![(SubShape::Primary, w)];
    }
    subs.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The first sub-shape heavier than `w` (std::upper_bound).
    let it = subs.iter().position(|s| s.0 > w).unwrap_or(subs.len());
    let (lo, hi) = if it == subs.len() {
        (subs.len() - 2, subs.len() - 1)
    } else if it > 0 {
        (it - 1, it)
    } else {
        (0, 1)
    };
    let (lower, upper) = (subs[lo], subs[hi]);
    let delta = upper.0 - lower.0;
    let mut out = Vec::with_capacity(2);
    if delta > EPS {
        let alpha = (w - lower.0) / delta;
        if lower.1 != SubShape::Null && (alpha - 1.0).abs() > EPS {
            out.push((lower.1, 1.0 - alpha));
        }
        if upper.1 != SubShape::Null && alpha.abs() > EPS {
            out.push((upper.1, alpha));
        }
    }
    out
}

/// A `BlendShape` prim: `offsets`, `normalOffsets`, `pointIndices` and its inbetweens
/// (`inbetweens:NAME` with `weight` metadata, `inbetweens:NAME:normalOffsets`).
struct BlendShape {
    path: String,
    offsets: Vec<DVec3>,
    normal_offsets: Vec<DVec3>,
    point_indices: Option<Vec<i64>>,
    inbetweens: Vec<(f64, Vec<DVec3>, Vec<DVec3>)>,
}

impl BlendShape {
    /// Adds `weight ×` the sub-shape's offsets (or normal offsets) to `out`
    /// (`UsdSkelApplyBlendShape`); `Err` describes a size mismatch or an index out of range.
    fn apply(
        &self,
        sub: SubShape,
        weight: f64,
        normals: bool,
        out: &mut [DVec3],
    ) -> Result<(), String> {
        let offsets = match (sub, normals) {
            (SubShape::Null, _) => return Ok(()),
            (SubShape::Primary, false) => &self.offsets,
            (SubShape::Primary, true) => &self.normal_offsets,
            (SubShape::Inbetween(k), false) => &self.inbetweens[k].1,
            (SubShape::Inbetween(k), true) => &self.inbetweens[k].2,
        };
        if offsets.is_empty() || weight.abs() <= EPS {
            return Ok(());
        }
        match &self.point_indices {
            None if offsets.len() != out.len() => Err(format!(
                "{}: {} offsets for {} points",
                self.path,
                offsets.len(),
                out.len()
            )),
            None => {
                for (o, d) in out.iter_mut().zip(offsets) {
                    *o += *d * weight;
                }
                Ok(())
            }
            Some(ix) if ix.len() != offsets.len() => Err(format!(
                "{}: {} offsets for {} pointIndices",
                self.path,
                offsets.len(),
                ix.len()
            )),
            Some(ix) => {
                for (&i, d) in ix.iter().zip(offsets) {
                    match usize::try_from(i).ok().and_then(|i| out.get_mut(i)) {
                        Some(o) => *o += *d * weight,
                        None => {
                            return Err(format!(
                                "{}: point index {i} out of range ({} points)",
                                self.path,
                                out.len()
                            ));
                        }
                    }
                }
                Ok(())
            }
        }
    }
}

/// How a posed gprim is drawn: its (possibly deformed) local points under `to_target`, and how
/// its authored normals are skinned.
pub(crate) struct Pose {
    /// Posed-space → the walk's target space (world, or the prototype's space): the skeleton's
    /// local-to-world (times the rigid transform for `constant` influences); the gprim's own
    /// transform for blend shapes alone.
    pub to_target: DMat4,
    /// Per point: the normal transform of linear blend skinning (see [`normal_matrix_lbs`]).
    normal_matrices: Option<Vec<DMat3>>,
    /// Per point: the summed, weighted blend-shape `normalOffsets`.
    normal_offsets: Option<Vec<DVec3>>,
}

impl Pose {
    /// Skins per-corner normals of `primvar` (expanded from `topo`, in the gprim's own space):
    /// each corner by the blend-shape normal offsets and the skinning of the point it belongs
    /// to (`UsdSkelSkinNormalsLBS` for `vertex`, `varying` and `faceVarying` normals; a
    /// `uniform` or `constant` primvar, which UsdSkel does not skin, is skinned per corner the
    /// same way, with a warning).
    pub(crate) fn skin_normals(
        &self,
        r: &mut Reader<'_>,
        prim: &Prim,
        primvar: &str,
        default_interp: &str,
        corners: Vec<[DVec3; 3]>,
        topo: &Topology,
    ) -> Vec<[DVec3; 3]> {
        if self.normal_matrices.is_none() && self.normal_offsets.is_none() {
            return corners;
        }
        let interp = r
            .attr_metadata_text(prim, primvar, "interpolation")
            .unwrap_or_else(|| default_interp.to_owned());
        let indexed = r
            .raw(prim, &format!("{primvar}:indices"))
            .ok()
            .flatten()
            .is_some();
        let per_point = matches!(interp.as_str(), "vertex" | "varying") && !indexed;
        if self.normal_matrices.is_some()
            && !matches!(interp.as_str(), "vertex" | "varying" | "faceVarying")
        {
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!(
                    "{primvar}: {interp} normals are skinned per triangle corner with the \
                     corner's point (UsdSkel skins vertex and faceVarying normals only)"
                ),
            );
        }
        let offsets = match &self.normal_offsets {
            Some(o) if per_point => Some(o),
            Some(_) => {
                r.warn(
                    prim,
                    WarningKind::Unsupported,
                    format!(
                        "{primvar}: blend-shape normalOffsets apply to non-indexed vertex \
                         normals only; not applied to these {interp} normals"
                    ),
                );
                None
            }
            None => None,
        };
        corners
            .into_iter()
            .zip(&topo.triangles)
            .map(|(c, t)| {
                let mut out = c;
                for k in 0..3 {
                    let p = t[k] as usize;
                    let mut n = c[k];
                    if let Some(o) = offsets.and_then(|o| o.get(p)) {
                        n = (n + *o).normalize_or_zero();
                    }
                    if let Some(m) = self.normal_matrices.as_ref().and_then(|m| m.get(p)) {
                        n = *m * n;
                    }
                    out[k] = n;
                }
                out
            })
            .collect()
    }
}

/// The binding of a skinnable prim, resolved from the prim up to its `SkelRoot`: each property
/// with the prim that authors it.
#[derive(Default)]
struct Binding {
    /// `skel:skeleton`: `Some(None)` when authored without a usable target.
    skeleton: Option<Option<String>>,
    joint_indices: Option<(String, Value)>,
    joint_weights: Option<(String, Value)>,
    geom_bind: Option<DMat4>,
    joints: Option<Vec<String>>,
    skinning_method: Option<String>,
}

fn tokens(v: &Value) -> Option<Vec<String>> {
    match v {
        Value::TokenVec(t) => Some(t.iter().map(|t| t.as_str().to_owned()).collect()),
        Value::StringVec(s) => Some(s.clone()),
        _ => None,
    }
}

fn matrices(v: &Value) -> Option<Vec<DMat4>> {
    match v {
        Value::Matrix4dVec(m) => Some(
            m.iter()
                .filter_map(|m| value::as_matrix4(&Value::Matrix4d(*m)))
                .collect(),
        ),
        _ => None,
    }
}

fn parent_prim(r: &Reader<'_>, prim: &Prim) -> Option<Prim> {
    let path = prim.path().as_str();
    let (parent, _) = path.rsplit_once('/')?;
    (!parent.is_empty()).then(|| r.stage.prim(parent))
}

fn has_api(r: &Reader<'_>, prim: &Prim) -> Result<bool, LoadError> {
    Ok(prim
        .api_schemas()
        .map_err(|e| r.usd_error(prim, e))?
        .iter()
        .any(|a| a.as_str() == "SkelBindingAPI"))
}

fn type_name(r: &Reader<'_>, prim: &Prim) -> Result<String, LoadError> {
    Ok(prim
        .type_name()
        .map_err(|e| r.usd_error(prim, e))?
        .map(|t| t.as_str().to_owned())
        .unwrap_or_default())
}

/// The first target of relationship `name` on `prim` when it is authored there (an authored
/// empty list blocks what is inherited: `Some(None)`), else `None`.
fn first_target(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &str,
) -> Result<Option<Option<String>>, LoadError> {
    let targets = r.targets(prim, name)?;
    let authored = !targets.is_empty()
        || prim
            .relationship(name)
            .has_authored_targets()
            .map_err(|e| r.usd_error(prim, e))?;
    if !authored {
        return Ok(None);
    }
    if targets.len() > 1 {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!(
                "{name} has {} targets; only the first is used",
                targets.len()
            ),
        );
    }
    Ok(Some(targets.into_iter().next()))
}

/// Resolves the binding of `prim` (`UsdSkelCache::Populate`); `None` when no `SkelRoot` is
/// above it.
fn resolve_binding(r: &mut Reader<'_>, prim: &Prim) -> Result<Option<Binding>, LoadError> {
    let mut b = Binding::default();
    let mut cur = Some(prim.clone());
    while let Some(p) = cur {
        if has_api(r, &p)? {
            if b.skeleton.is_none() {
                b.skeleton = first_target(r, &p, "skel:skeleton")?;
            }
            let path = p.path().to_string();
            if b.joint_indices.is_none()
                && let Some(v) = r.raw(&p, "primvars:skel:jointIndices")?
            {
                b.joint_indices = Some((path.clone(), v));
            }
            if b.joint_weights.is_none()
                && let Some(v) = r.raw(&p, "primvars:skel:jointWeights")?
            {
                b.joint_weights = Some((path.clone(), v));
            }
            if b.geom_bind.is_none() {
                b.geom_bind = r.matrix(&p, "primvars:skel:geomBindTransform")?;
            }
            if b.joints.is_none() {
                b.joints = r.raw(&p, "skel:joints")?.as_ref().and_then(tokens);
            }
            if b.skinning_method.is_none() {
                b.skinning_method = r.text(&p, "primvars:skel:skinningMethod")?;
            }
        }
        if type_name(r, &p)? == "SkelRoot" {
            return Ok(Some(b));
        }
        cur = parent_prim(r, &p);
    }
    Ok(None)
}

/// `prim`'s local-to-world transform in the composed stage (its own and its ancestors'
/// transform ops, up to a `!resetXformStack!`).
fn stage_transform(r: &mut Reader<'_>, prim: &Prim) -> Result<DMat4, LoadError> {
    let mut m = DMat4::IDENTITY;
    let mut cur = Some(prim.clone());
    while let Some(p) = cur {
        let (local, reset) = local_transform(r, &p)?;
        m = local * m;
        if reset {
            break;
        }
        cur = parent_prim(r, &p);
    }
    Ok(m)
}

/// An `int` / `float` primvar's `elementSize` (1 when unauthored).
fn element_size(r: &Reader<'_>, prim_path: &str, name: &str) -> i64 {
    let prim = r.stage.prim(prim_path);
    prim.attribute(name)
        .get_metadata::<Value>("elementSize")
        .ok()
        .flatten()
        .and_then(|v| value::as_f64(&v))
        .map_or(1, |x| x as i64)
}

/// A primvar's values flattened through its `:indices` (`UsdGeomPrimvar::ComputeFlattened`,
/// `element_size` values per index).
fn flattened<T: Copy>(
    r: &Reader<'_>,
    prim_path: &str,
    name: &str,
    values: Vec<T>,
    element_size: usize,
) -> Result<Option<Vec<T>>, LoadError> {
    let prim = r.stage.prim(prim_path);
    let Some(ix) = r
        .raw(&prim, &format!("{name}:indices"))?
        .as_ref()
        .and_then(value::as_int_array)
    else {
        return Ok(Some(values));
    };
    let mut out = Vec::with_capacity(
        ix.len()
            .saturating_mul(element_size)
            .min(r.limits.max_array_len),
    );
    for i in ix {
        let start = usize::try_from(i).ok().map(|i| i * element_size);
        match start.and_then(|s| values.get(s..s + element_size)) {
            Some(v) => out.extend_from_slice(v),
            None => return Ok(None),
        }
    }
    Ok(Some(out))
}

/// The joint influences of a binding: `(indices, weights, elementSize, rigid)`, validated as
/// `UsdSkelSkinningQuery` does; `Err` says why they are unusable.
type Influences = (Vec<i64>, Vec<f64>, usize, bool);

fn influences(r: &mut Reader<'_>, b: &Binding) -> Result<Result<Influences, String>, LoadError> {
    let (Some((ip, iv)), Some((wp, wv))) = (&b.joint_indices, &b.joint_weights) else {
        return Ok(Err(
            "primvars:skel:jointIndices and primvars:skel:jointWeights must both be authored"
                .into(),
        ));
    };
    let ji = "primvars:skel:jointIndices";
    let jw = "primvars:skel:jointWeights";
    let (Some(indices), Some(weights)) = (value::as_int_array(iv), value::as_f64_array(wv)) else {
        return Ok(Err(format!("{ji} must be int[] and {jw} float[]")));
    };
    let (ies, wes) = (element_size(r, ip, ji), element_size(r, wp, jw));
    if ies != wes || ies <= 0 || ies as u64 > r.limits.max_array_len as u64 {
        return Ok(Err(format!(
            "{ji} elementSize {ies} and {jw} elementSize {wes} must be equal, positive and \
             within the array limit"
        )));
    }
    let interp = |r: &Reader<'_>, p: &str, n: &str| {
        r.attr_metadata_text(&r.stage.prim(p), n, "interpolation")
            .unwrap_or_else(|| "constant".into())
    };
    let (ii, wi) = (interp(r, ip, ji), interp(r, wp, jw));
    if ii != wi || !matches!(ii.as_str(), "constant" | "vertex") {
        return Ok(Err(format!(
            "{ji} ({ii}) and {jw} ({wi}) interpolations must be equal, constant or vertex"
        )));
    }
    let es = ies as usize;
    let (Some(indices), Some(weights)) = (
        flattened(r, ip, ji, indices, es)?,
        flattened(r, wp, jw, weights, es)?,
    ) else {
        return Ok(Err("a primvar index is out of range".into()));
    };
    if indices.len() != weights.len() || indices.len() % es != 0 {
        return Ok(Err(format!(
            "{} jointIndices and {} jointWeights for elementSize {es}",
            indices.len(),
            weights.len()
        )));
    }
    let rigid = ii == "constant";
    if rigid && indices.len() != es {
        return Ok(Err(format!(
            "constant influences need elementSize ({es}) values, found {}",
            indices.len()
        )));
    }
    Ok(Ok((indices, weights, es, rigid)))
}

/// The skeleton's skinning transforms in `joint_order` (the gprim's `skel:joints`, else the
/// skeleton's own order) at the load time; `Err` says why they cannot be computed.
fn skinning_transforms(
    r: &mut Reader<'_>,
    skel: &Prim,
    anim: Option<&Prim>,
    joint_order: Option<&[String]>,
) -> Result<Result<Vec<DMat4>, String>, LoadError> {
    let path = skel.path().to_string();
    let joints = r
        .raw(skel, "joints")?
        .as_ref()
        .and_then(tokens)
        .unwrap_or_default();
    let n = joints.len();
    let parents = joint_parents(&joints);
    let bind = r.raw(skel, "bindTransforms")?.as_ref().and_then(matrices);
    let rest = r
        .raw(skel, "restTransforms")?
        .as_ref()
        .and_then(matrices)
        .filter(|m| m.len() == n);
    // The animation's local transforms mapped onto the skeleton's joints (UsdSkelAnimMapper).
    let mut local: Option<Vec<Option<DMat4>>> = None;
    if let Some(a) = anim {
        let anim_joints = r
            .raw(a, "joints")?
            .as_ref()
            .and_then(tokens)
            .unwrap_or_default();
        let map: Vec<Option<usize>> = joints
            .iter()
            .map(|j| anim_joints.iter().position(|aj| aj == j))
            .collect();
        if map.iter().any(Option::is_some) {
            let t = r.vec3_array(a, "translations")?;
            let q = r.quat_array(a, "rotations")?;
            let s = r.vec3_array(a, "scales")?;
            match (t, q, s) {
                (Some(t), Some(q), Some(s))
                    if t.len() == anim_joints.len() && q.len() == t.len() && s.len() == t.len() =>
                {
                    local = Some(
                        map.iter()
                            .map(|m| m.map(|i| joint_local_transform(t[i], q[i], s[i])))
                            .collect(),
                    );
                }
                (t, q, s) => {
                    r.warn(
                        skel,
                        WarningKind::InvalidGeometry,
                        format!(
                            "animation <{}>: translations, rotations and scales must all be \
                             authored with one value per joint ({}; found {}, {}, {}); the \
                             skeleton's restTransforms are used",
                            a.path(),
                            anim_joints.len(),
                            t.map_or(0, |v| v.len()),
                            q.map_or(0, |v| v.len()),
                            s.map_or(0, |v| v.len())
                        ),
                    );
                }
            }
        }
    }
    let local: Vec<DMat4> = match (local, &rest) {
        (Some(l), _) if l.iter().all(Option::is_some) => l.into_iter().flatten().collect(),
        (Some(l), Some(rest)) => l
            .into_iter()
            .zip(rest)
            .map(|(l, rest)| l.unwrap_or(*rest))
            .collect(),
        (Some(_), None) => {
            return Ok(Err(format!(
                "the animation does not cover every joint of <{path}> and its restTransforms \
                 are unset or not one per joint"
            )));
        }
        (None, Some(rest)) => rest.clone(),
        (None, None) => {
            return Ok(Err(format!(
                "<{path}> has no usable animation and its restTransforms are unset or not one \
                 per joint"
            )));
        }
    };
    let skel_space = match concat_joint_transforms(&parents, &local) {
        Ok(s) => s,
        Err(i) => {
            return Ok(Err(format!(
                "joint {i} ({}) of <{path}> comes before its parent",
                joints[i]
            )));
        }
    };
    let Some(bind) = bind.filter(|b| b.len() == n) else {
        return Ok(Err(format!(
            "the bindTransforms of <{path}> are unset or not one per joint ({n} joints)"
        )));
    };
    let mut skinning = Vec::with_capacity(n);
    for (i, (s, b)) in skel_space.iter().zip(&bind).enumerate() {
        let det = b.determinant();
        if !det.is_finite() || det.abs() < 1e-300 {
            return Ok(Err(format!("bindTransforms[{i}] of <{path}> is singular")));
        }
        skinning.push(*s * b.inverse());
    }
    let Some(order) = joint_order else {
        return Ok(Ok(skinning));
    };
    let mut out = Vec::with_capacity(order.len());
    for j in order {
        match joints.iter().position(|sj| sj == j) {
            Some(i) => out.push(skinning[i]),
            None => {
                return Ok(Err(format!(
                    "skel:joints names {j:?}, not a joint of <{path}>"
                )));
            }
        }
    }
    Ok(Ok(out))
}

/// Blend-shaped points and, when any shape has normal offsets, the per-point normal offsets.
type Shaped = (Vec<DVec3>, Option<Vec<DVec3>>);

/// The blend-shape deformation of the gprim's points and per-point normal offsets at the load
/// time, `None` when it has no blend shapes; `Err` says why they cannot be applied.
fn blend_shapes(
    r: &mut Reader<'_>,
    prim: &Prim,
    anim: Option<&Prim>,
    points: &[DVec3],
) -> Result<Option<Result<Shaped, String>>, LoadError> {
    let Some(names) = r.raw(prim, "skel:blendShapes")?.as_ref().and_then(tokens) else {
        return Ok(None);
    };
    let targets = r.targets(prim, "skel:blendShapeTargets")?;
    if targets.is_empty() {
        return Ok(None);
    }
    let Some(anim) = anim else {
        return Ok(Some(Err(
            "no animation source gives blend-shape weights".into()
        )));
    };
    let anim_names = r
        .raw(anim, "blendShapes")?
        .as_ref()
        .and_then(tokens)
        .unwrap_or_default();
    let Some(anim_weights) = r
        .raw(anim, "blendShapeWeights")?
        .as_ref()
        .and_then(value::as_f64_array)
    else {
        return Ok(Some(Err(format!(
            "<{}> has no blendShapeWeights",
            anim.path()
        ))));
    };
    if anim_weights.len() != anim_names.len() {
        return Ok(Some(Err(format!(
            "<{}>: {} blendShapeWeights for {} blendShapes",
            anim.path(),
            anim_weights.len(),
            anim_names.len()
        ))));
    }
    if names.len() != targets.len() {
        return Ok(Some(Err(format!(
            "{} skel:blendShapes for {} skel:blendShapeTargets",
            names.len(),
            targets.len()
        ))));
    }
    let mut posed = points.to_vec();
    let mut normal_offsets = vec![DVec3::ZERO; points.len()];
    let mut any_normals = false;
    for (name, target) in names.iter().zip(&targets) {
        let w = anim_names
            .iter()
            .position(|n| n == name)
            .map_or(0.0, |i| anim_weights[i]);
        let Some(shape) = read_blend_shape(r, target)? else {
            return Ok(Some(Err(format!("<{target}> is not a BlendShape"))));
        };
        let inbetween_weights: Vec<f64> = shape.inbetweens.iter().map(|i| i.0).collect();
        for (sub, sw) in sub_shape_weights(w, &inbetween_weights) {
            if let Err(e) = shape.apply(sub, sw, false, &mut posed) {
                return Ok(Some(Err(e)));
            }
            if let Err(e) = shape.apply(sub, sw, true, &mut normal_offsets) {
                return Ok(Some(Err(e)));
            }
        }
        any_normals |=
            !shape.normal_offsets.is_empty() || shape.inbetweens.iter().any(|i| !i.2.is_empty());
    }
    Ok(Some(Ok((posed, any_normals.then_some(normal_offsets)))))
}

fn read_blend_shape(r: &mut Reader<'_>, path: &str) -> Result<Option<BlendShape>, LoadError> {
    let p = r.stage.prim(path);
    if !p.is_valid().map_err(|e| r.usd_error(&p, e))? || type_name(r, &p)? != "BlendShape" {
        return Ok(None);
    }
    let offsets = r.vec3_array(&p, "offsets")?.unwrap_or_default();
    let normal_offsets = r.vec3_array(&p, "normalOffsets")?.unwrap_or_default();
    let point_indices = r.int_array(&p, "pointIndices")?.filter(|i| !i.is_empty());
    let mut inbetweens = Vec::new();
    let names = p.property_names().map_err(|e| r.usd_error(&p, e))?;
    for name in names {
        let name = name.as_str();
        let Some(rest) = name.strip_prefix("inbetweens:") else {
            continue;
        };
        if rest.contains(':') {
            continue; // `inbetweens:NAME:normalOffsets`
        }
        let weight = p
            .attribute(name)
            .get_metadata::<Value>("weight")
            .ok()
            .flatten()
            .and_then(|v| value::as_f64(&v));
        let Some(weight) = weight else {
            r.warn(
                &p,
                WarningKind::InvalidValue,
                format!("{name} has no weight metadata; this inbetween is skipped"),
            );
            continue;
        };
        let offsets = r
            .raw(&p, name)?
            .as_ref()
            .and_then(value::as_vec3_array)
            .unwrap_or_default();
        let normals = r
            .raw(&p, &format!("{name}:normalOffsets"))?
            .as_ref()
            .and_then(value::as_vec3_array)
            .unwrap_or_default();
        if offsets.len().max(normals.len()) > r.limits.max_array_len {
            return Err(LoadError::TooLarge {
                file: r.file.clone(),
                prim: path.to_owned(),
                what: "blend-shape inbetween",
                count: offsets.len().max(normals.len()),
                limit: r.limits.max_array_len,
            });
        }
        inbetweens.push((weight, offsets, normals));
    }
    Ok(Some(BlendShape {
        path: path.to_owned(),
        offsets,
        normal_offsets,
        point_indices,
        inbetweens,
    }))
}

/// Poses the skinnable gprim `prim` (of kind `gprim`, its local points in `topo`) at the load
/// time, as `UsdSkelBakeSkinning` does: its deformed points replace `topo.points` and the
/// returned [`Pose`] says where they go (`to_target`) and how authored normals follow.
/// `here` is the gprim's own local-to-target transform; `proto_root` the root path of the
/// instancing prototype being walked (`None` in the world). `None`: nothing to pose (no
/// `SkelRoot` above, no binding), or — with a warning naming the prim — what is authored
/// cannot be posed and the gprim is drawn as authored.
pub(crate) fn pose(
    r: &mut Reader<'_>,
    prim: &Prim,
    gprim: Gprim,
    topo: &mut Topology,
    here: &DMat4,
    proto_root: Option<&str>,
) -> Result<Option<Pose>, LoadError> {
    let Some(b) = resolve_binding(r, prim)? else {
        return Ok(None);
    };
    let has_influences = b.joint_indices.is_some() || b.joint_weights.is_some();
    let has_shapes = gprim == Gprim::Mesh && r.raw(prim, "skel:blendShapes")?.is_some();
    if !has_influences && !has_shapes {
        return Ok(None);
    }
    let fail = |r: &mut Reader<'_>, why: String| -> Result<Option<Pose>, LoadError> {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!("UsdSkel: {why}; drawn unposed (as authored)"),
        );
        Ok(None)
    };
    let skel_path = match &b.skeleton {
        Some(Some(p)) => p.clone(),
        _ => return fail(r, "no skel:skeleton is bound (on it or an ancestor with SkelBindingAPI under the SkelRoot)".into()),
    };
    let skel = r.stage.prim(skel_path.as_str());
    if !skel.is_valid().map_err(|e| r.usd_error(prim, e))? || type_name(r, &skel)? != "Skeleton" {
        return fail(
            r,
            format!("skel:skeleton target <{skel_path}> is not a Skeleton"),
        );
    }
    // The skeleton's animation source: its own or its nearest ancestor's with SkelBindingAPI.
    let mut anim = None;
    let mut cur = Some(skel.clone());
    while let Some(p) = cur {
        if has_api(r, &p)?
            && let Some(t) = first_target(r, &p, "skel:animationSource")?
        {
            anim = t.map(|t| r.stage.prim(t.as_str()));
            break;
        }
        cur = parent_prim(r, &p);
    }
    if let Some(a) = &anim
        && (!a.is_valid().map_err(|e| r.usd_error(prim, e))? || type_name(r, a)? != "SkelAnimation")
    {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!(
                "skel:animationSource <{}> is not a SkelAnimation; the rest pose is used",
                a.path()
            ),
        );
        anim = None;
    }
    // Skeleton space → the walk's target space.
    let skel_to_target = match proto_root {
        None => stage_transform(r, &skel)?,
        Some(root) => {
            if !(skel_path == root || skel_path.starts_with(&format!("{root}/"))) {
                return fail(
                    r,
                    format!(
                        "its skeleton <{skel_path}> is outside the instancing prototype \
                         <{root}> it is drawn from (each instance would pose differently)"
                    ),
                );
            }
            let mesh_world = stage_transform(r, prim)?;
            if mesh_world.determinant().abs() < 1e-300 {
                return fail(r, "its transform is singular".into());
            }
            *here * mesh_world.inverse() * stage_transform(r, &skel)?
        }
    };
    let mut points = topo.points.clone();
    let mut normal_offsets = None;
    if has_shapes {
        match blend_shapes(r, prim, anim.as_ref(), &points)? {
            Some(Ok((p, n))) => {
                points = p;
                normal_offsets = n;
            }
            Some(Err(why)) => {
                r.warn(
                    prim,
                    WarningKind::InvalidGeometry,
                    format!("UsdSkel blend shapes not applied: {why}"),
                );
            }
            None => {}
        }
    }
    let mut to_target = *here;
    let mut normal_matrices = None;
    if has_influences {
        let (indices, mut weights, es, rigid) = match influences(r, &b)? {
            Ok(i) => i,
            Err(why) => return fail(r, why),
        };
        // Point-based gprims (meshes, curves, points) skin point by point; implicit surfaces
        // have no points to weight, only a rigid influence.
        let point_based = matches!(
            gprim,
            Gprim::Mesh | Gprim::BasisCurves | Gprim::NurbsCurves | Gprim::Points
        );
        if !point_based && !rigid {
            return fail(
                r,
                format!(
                    "vertex joint influences on a {gprim:?} (UsdSkel skins implicit surfaces \
                     rigidly only)"
                ),
            );
        }
        if !rigid && indices.len() != points.len() * es {
            return fail(
                r,
                format!(
                    "{} joint influences for {} points × elementSize {es}",
                    indices.len(),
                    points.len()
                ),
            );
        }
        let bad = weights.iter().filter(|w| !w.is_finite()).count();
        if bad > 0 {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "primvars:skel:jointWeights: {bad} non-finite weights read as 0 \
                     (usd-core would pose those points at NaN)"
                ),
            );
            for w in &mut weights {
                if !w.is_finite() {
                    *w = 0.0;
                }
            }
        }
        let unnormalised = weights
            .chunks(es)
            .filter(|c| (c.iter().sum::<f64>() - 1.0).abs() > 1e-3)
            .count();
        if unnormalised > 0 {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "primvars:skel:jointWeights: {unnormalised} of {} influence sets do not sum \
                     to 1; applied as authored, as UsdSkel skins them",
                    weights.len() / es
                ),
            );
        }
        let method = b.skinning_method.as_deref().unwrap_or("classicLinear");
        let dq = method == "dualQuaternion";
        if !dq && method != "classicLinear" {
            return fail(
                r,
                format!("primvars:skel:skinningMethod {method:?} is not a UsdSkel skinning method"),
            );
        }
        let skinning = match skinning_transforms(r, &skel, anim.as_ref(), b.joints.as_deref())? {
            Ok(s) => s,
            Err(why) => return fail(r, why),
        };
        let geom_bind = b.geom_bind.unwrap_or(DMat4::IDENTITY);
        let inf: Vec<(i64, f64)> = indices
            .iter()
            .copied()
            .zip(weights.iter().copied())
            .collect();
        let out_of_range = || {
            let j = indices
                .iter()
                .find(|&&j| j < 0 || j as usize >= skinning.len())
                .copied()
                .unwrap_or(-1);
            format!(
                "joint index {j} is out of range ({} joints in the binding's order)",
                skinning.len()
            )
        };
        let joints: Vec<JointDq> = if dq {
            skinning.iter().map(JointDq::new).collect()
        } else {
            Vec::new()
        };
        let stretch = joints_stretch(&joints);
        if rigid {
            let m = if dq {
                rigid_transform_dqs(&geom_bind, &skinning, &joints, stretch, &inf)
            } else {
                rigid_transform_lbs(&geom_bind, &skinning, &inf)
            };
            match m {
                Some(m) => to_target = skel_to_target * m,
                None => {
                    let why = out_of_range();
                    return fail(r, why);
                }
            }
        } else {
            let mut posed = Vec::with_capacity(points.len());
            for (p, i) in points.iter().zip(inf.chunks(es)) {
                let q = if dq {
                    skin_point_dqs(*p, &geom_bind, &joints, stretch, i)
                } else {
                    skin_point_lbs(*p, &geom_bind, &skinning, i)
                };
                match q {
                    Some(q) => posed.push(q),
                    None => {
                        let why = out_of_range();
                        return fail(r, why);
                    }
                }
            }
            points = posed;
            to_target = skel_to_target;
            let geom_inv_t = DMat3::from_mat4(geom_bind).inverse().transpose();
            let inv_t: Vec<DMat3> = skinning
                .iter()
                .map(|s| DMat3::from_mat4(*s).inverse().transpose())
                .collect();
            let normal_joints: Vec<JointDq> = if dq {
                inv_t
                    .iter()
                    .map(|m| JointDq::new(&DMat4::from_mat3(*m)))
                    .collect()
            } else {
                Vec::new()
            };
            let normal_stretch = joints_stretch(&normal_joints);
            normal_matrices = Some(
                inf.chunks(es)
                    .map(|i| {
                        if dq {
                            normal_matrix_dqs(&geom_inv_t, &normal_joints, normal_stretch, i)
                        } else {
                            normal_matrix_lbs(&geom_inv_t, &inv_t, i)
                        }
                        .unwrap_or(DMat3::IDENTITY)
                    })
                    .collect(),
            );
        }
    }
    topo.points = points;
    Ok(Some(Pose {
        to_target,
        normal_matrices,
        normal_offsets,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_1_SQRT_2;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn a_joint_turned_90_degrees_about_z_moves_x_to_y() {
        let s = [DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2)];
        let p = skin_point_lbs(DVec3::X, &DMat4::IDENTITY, &s, &[(0, 1.0)]).unwrap();
        assert!(close(p, DVec3::Y), "{p}");
        // The same through the skeleton: bind at the origin, animated local rotation.
        let local = joint_local_transform(
            DVec3::ZERO,
            DQuat::from_xyzw(0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2),
            DVec3::ONE,
        );
        let skel = concat_joint_transforms(&[None], &[local]).unwrap();
        let q = skin_point_lbs(DVec3::X, &DMat4::IDENTITY, &skel, &[(0, 1.0)]).unwrap();
        assert!(close(q, DVec3::Y), "{q}");
    }

    #[test]
    fn rigid_constant_skinning_is_one_transform() {
        let s = [
            DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)),
            DMat4::from_translation(DVec3::new(0.0, 4.0, 0.0)),
        ];
        let g = DMat4::from_scale(DVec3::splat(3.0));
        // One influence of weight 1: S · G.
        let one = rigid_transform_lbs(&g, &s, &[(1, 1.0)]).unwrap();
        assert_eq!(one, s[1] * g);
        // Half and half: the frame of G blended, an affine map.
        let half = rigid_transform_lbs(&g, &s, &[(0, 0.5), (1, 0.5)]).unwrap();
        assert!(close(
            half.transform_point3(DVec3::X),
            DVec3::new(4.0, 2.0, 0.0)
        ));
        assert_eq!(half.row(3), glam::DVec4::W);
    }

    /// UsdSkel skins with the weights as authored (`UsdSkelSkinPointsLBS` does not normalise
    /// them; `UsdSkelNormalizeWeights` is an authoring utility): weights summing to 2 double
    /// the point, as usd-core's BakeSkinning does (the `Unnormalised` prim of skel_cases.usda).
    #[test]
    fn weights_are_applied_as_authored_not_normalised() {
        let s = [DMat4::IDENTITY, DMat4::IDENTITY];
        let p = DVec3::new(1.0, 2.0, 3.0);
        let doubled = skin_point_lbs(p, &DMat4::IDENTITY, &s, &[(0, 1.0), (1, 1.0)]).unwrap();
        assert!(close(doubled, p * 2.0));
        let zero = skin_point_lbs(p, &DMat4::IDENTITY, &s, &[(0, 0.0), (1, 0.0)]).unwrap();
        assert!(close(zero, DVec3::ZERO));
    }

    #[test]
    fn an_out_of_range_joint_index_is_refused() {
        let s = [DMat4::IDENTITY];
        assert!(skin_point_lbs(DVec3::X, &DMat4::IDENTITY, &s, &[(1, 1.0)]).is_none());
        assert!(skin_point_lbs(DVec3::X, &DMat4::IDENTITY, &s, &[(-1, 1.0)]).is_none());
        assert!(rigid_transform_lbs(&DMat4::IDENTITY, &s, &[(3, 1.0)]).is_none());
    }

    #[test]
    fn joint_parents_are_the_nearest_listed_ancestors() {
        let j = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            joint_parents(&j(&["a", "a/b", "a/b/c", "x/y"])),
            [None, Some(0), Some(1), None]
        );
        assert_eq!(joint_parents(&j(&["a", "a/b/c"])), [None, Some(0)]);
        // A child listed before its parent cannot be concatenated.
        let parents = joint_parents(&j(&["a/b", "a"]));
        assert_eq!(
            concat_joint_transforms(&parents, &[DMat4::IDENTITY; 2]),
            Err(0)
        );
    }

    #[test]
    fn inbetweens_split_the_weight_between_their_neighbours() {
        use SubShape::*;
        // No inbetween: the primary shape at the weight, extrapolated beyond [0, 1].
        assert_eq!(sub_shape_weights(2.0, &[]), [(Primary, 2.0)]);
        // An inbetween at 0.5: below it, the rest and the inbetween; above, it and the primary.
        assert_eq!(sub_shape_weights(0.25, &[0.5]), [(Inbetween(0), 0.5)]);
        assert_eq!(
            sub_shape_weights(0.75, &[0.5]),
            [(Inbetween(0), 0.5), (Primary, 0.5)]
        );
        assert_eq!(sub_shape_weights(0.5, &[0.5]), [(Inbetween(0), 1.0)]);
        // Beyond the primary: extrapolated from the last pair.
        assert_eq!(
            sub_shape_weights(1.5, &[0.5]),
            [(Inbetween(0), -1.0), (Primary, 2.0)]
        );
        // A negative inbetween, and one at 1 (invalid, dropped as UsdSkel drops it).
        assert_eq!(
            sub_shape_weights(-0.25, &[-0.5, 1.0]),
            [(Inbetween(0), 0.5)]
        );
    }

    #[test]
    fn normals_follow_the_inverse_transpose() {
        // A joint stretching y by 2: a 45° normal in xy turns towards x.
        let s = [DMat4::from_scale(DVec3::new(1.0, 2.0, 1.0))];
        let inv_t = [DMat3::from_mat4(s[0]).inverse().transpose()];
        let m = normal_matrix_lbs(&DMat3::IDENTITY, &inv_t, &[(0, 1.0)]).unwrap();
        let n = (m * DVec3::new(1.0, 1.0, 0.0)).normalize();
        assert!(close(n, DVec3::new(1.0, 0.5, 0.0).normalize()), "{n}");
    }

    #[test]
    fn dual_quaternions_blend_rotations_rigidly() {
        // Half identity, half a quarter turn about z: a 45° turn, where linear blending
        // shrinks the point towards the axis.
        let s = [
            DMat4::IDENTITY,
            DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2),
        ];
        let joints: Vec<JointDq> = s.iter().map(JointDq::new).collect();
        assert!(!joints_stretch(&joints));
        let inf = [(0, 0.5), (1, 0.5)];
        let dq = skin_point_dqs(DVec3::X, &DMat4::IDENTITY, &joints, false, &inf).unwrap();
        assert!(
            close(dq, DVec3::new(FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0)),
            "{dq}"
        );
        let lbs = skin_point_lbs(DVec3::X, &DMat4::IDENTITY, &s, &inf).unwrap();
        assert!(close(lbs, DVec3::new(0.5, 0.5, 0.0)), "{lbs}");
        // A translated joint keeps its translation.
        let t = JointDq::new(&DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0)));
        let p = skin_point_dqs(DVec3::X, &DMat4::IDENTITY, &[t], false, &[(0, 1.0)]).unwrap();
        assert!(close(p, DVec3::new(2.0, 2.0, 3.0)), "{p}");
    }

    #[test]
    fn polar_rotation_splits_a_stretched_turn() {
        let r = DMat3::from_rotation_z(0.3);
        let m = r * DMat3::from_diagonal(DVec3::new(2.0, 1.0, 0.5));
        let (rot, stretch) = polar_rotation(&m).unwrap();
        assert!((rot - r).to_cols_array().iter().all(|d| d.abs() < 1e-12));
        assert!(
            (rot * stretch - m)
                .to_cols_array()
                .iter()
                .all(|d| d.abs() < 1e-12)
        );
        assert!(polar_rotation(&DMat3::ZERO).is_none());
    }
}
