//! A Material's UsdShade network as a [`Network`]: the surface terminal
//! (`outputs:mtlx:surface`, the MaterialX render context, else the universal `outputs:surface`)
//! and every `Shader` prim upstream of it, NodeGraph boundaries and Material interface inputs
//! resolved away.
//!
//! Each Shader becomes a [`NetNode`] named by its prim path whose nodedef is its `info:id` as
//! authored (`ND_standard_surface_surfaceshader`, `UsdPreviewSurface`, `UsdUVTexture`,
//! `UsdPrimvarReader_float2`, …); each authored `inputs:*` attribute becomes a [`NetInput`]
//! typed by its USD type ([`usd_value_type`]) holding a value or a connection to another
//! node's output. A connection into a `NodeGraph` (or a Material) is followed through its
//! outputs (`outputs:x.connect`) and interface inputs (`inputs:y`, a value or a further
//! connection) until a Shader output or a value. An asset input is a file with its colour space
//! (its `colorSpace` metadata; a `UsdUVTexture`'s `sourceColorSpace` `sRGB` / `raw`, folded into
//! its file as `srgb_texture` / `raw`, is not an input of its own). A connection cycle or a dangling connection
//! (to a prim or attribute that does not exist, or to something that is neither a Shader, a
//! NodeGraph nor a Material) drops the input with a warning naming the prim and the input.

use crate::error::{LoadError, Warning, WarningKind};
use crate::reader::{Reader, is_prim_path, is_property_name};
use crate::shading::{
    Connection, FileValue, NetInput, NetNode, NetSource, Network, Value, ValueType,
};
use openusd::sdf;
use openusd::usd::Prim;
use std::collections::{HashMap, HashSet};

/// The MaterialX render context's surface terminal, read first.
pub const MTLX_SURFACE: &str = "outputs:mtlx:surface";
/// The universal surface terminal, read when the MaterialX one is absent or unreadable.
pub const UNIVERSAL_SURFACE: &str = "outputs:surface";
/// Most connections followed from one input through NodeGraph outputs and interface inputs.
const MAX_HOPS: usize = 64;

/// The MaterialX type of a USD attribute type name (`float`, `color3f`, `normal3f`, `asset`,
/// …): numbers of any precision, `bool` as `boolean`, `color3*` as `color3`, `normal3*` /
/// `vector3*` / `point3*` / `float3` as `vector3`, `float2` / `texCoord2*` as `vector2`,
/// `float4` as `vector4`, `color4*` as `color4`, `string` / `token` as `string`, `asset` as
/// `filename`, `matrix3d` / `matrix4d`. `None` for arrays and other types.
pub fn usd_value_type(usd: &str) -> Option<ValueType> {
    Some(match usd {
        "float" | "double" | "half" => ValueType::Float,
        "int" | "int64" | "uint" | "uint64" | "uchar" => ValueType::Integer,
        "bool" => ValueType::Boolean,
        "color3f" | "color3d" | "color3h" => ValueType::Color3,
        "color4f" | "color4d" | "color4h" => ValueType::Color4,
        "normal3f" | "normal3d" | "normal3h" | "vector3f" | "vector3d" | "vector3h" | "point3f"
        | "point3d" | "point3h" | "float3" | "double3" | "half3" => ValueType::Vector3,
        "float2" | "double2" | "half2" | "texCoord2f" | "texCoord2d" | "texCoord2h" => {
            ValueType::Vector2
        }
        "float4" | "double4" | "half4" => ValueType::Vector4,
        "string" | "token" => ValueType::String,
        "asset" => ValueType::Filename,
        "matrix3d" => ValueType::Matrix33,
        "matrix4d" => ValueType::Matrix44,
        _ => return None,
    })
}

/// The MaterialX type of a value whose attribute declares no type.
fn inferred_type(v: &sdf::Value) -> Option<ValueType> {
    use sdf::Value as V;
    Some(match v {
        V::Half(_) | V::Float(_) | V::Double(_) => ValueType::Float,
        V::Int(_) | V::Int64(_) | V::Uint(_) | V::Uint64(_) | V::Uchar(_) => ValueType::Integer,
        V::Bool(_) => ValueType::Boolean,
        V::Vec2h(_) | V::Vec2f(_) | V::Vec2d(_) => ValueType::Vector2,
        V::Vec3h(_) | V::Vec3f(_) | V::Vec3d(_) => ValueType::Vector3,
        V::Vec4h(_) | V::Vec4f(_) | V::Vec4d(_) => ValueType::Vector4,
        V::Token(_) | V::String(_) => ValueType::String,
        V::AssetPath(_) => ValueType::Filename,
        V::Matrix3d(_) => ValueType::Matrix33,
        V::Matrix4d(_) => ValueType::Matrix44,
        _ => return None,
    })
}

/// Which surface terminal of a Material a [`Network`] was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Terminal {
    /// `outputs:mtlx:surface`.
    Mtlx,
    /// `outputs:surface`.
    Universal,
}

/// What produces an input's value: a Shader's output, or an attribute that holds (or lacks)
/// a value.
#[derive(Debug)]
enum Producer {
    /// A Shader prim's output (name without `outputs:`).
    Output { shader: String, output: String },
    /// An attribute holding the value: the input itself, or an interface input.
    Value { prim: String, attr: String },
}

/// The type name of a prim, empty when it has none or does not exist.
fn prim_type(r: &Reader<'_>, prim: &Prim) -> Result<String, LoadError> {
    Ok(prim
        .type_name()
        .map_err(|e| r.usd_error(prim, e))?
        .map(|t| t.as_str().to_owned())
        .unwrap_or_default())
}

/// The declared USD type name of `name` on `prim` (`None` when it has none or does not exist).
fn attr_type(r: &Reader<'_>, prim: &Prim, name: &str) -> Result<Option<String>, LoadError> {
    if !is_property_name(name) {
        return Ok(None);
    }
    Ok(prim
        .attribute(name)
        .type_name()
        .map_err(|e| r.usd_error(prim, format_args!("attribute {name}: {e:#}")))?
        .map(|t| t.as_str().to_owned()))
}

/// Follows the connection of `attr` on `prim` through NodeGraph / Material outputs and
/// interface inputs to its producer; `Err(reason)` for a dangling connection or a cycle.
fn resolve(r: &Reader<'_>, prim: &str, attr: &str) -> Result<Result<Producer, String>, LoadError> {
    let mut cur = (prim.to_owned(), attr.to_owned());
    let mut seen = HashSet::new();
    for _ in 0..MAX_HOPS {
        let p = r.stage.prim(cur.0.as_str());
        let Some(src) = r.connections(&p, &cur.1)?.into_iter().next() else {
            if cur.1.starts_with("outputs:") {
                return Ok(Err(format!("{}.{} is not connected", cur.0, cur.1)));
            }
            return Ok(Ok(Producer::Value {
                prim: cur.0,
                attr: cur.1,
            }));
        };
        let Some((sp, sa)) = src.split_once('.') else {
            return Ok(Err(format!("connection to <{src}> is not an attribute")));
        };
        if !is_prim_path(sp) || !is_property_name(sa) {
            return Ok(Err(format!("connection to <{src}> is not an attribute")));
        }
        if !seen.insert((sp.to_owned(), sa.to_owned())) {
            return Ok(Err(format!("connection cycle through <{src}>")));
        }
        let target = r.stage.prim(sp);
        if !target.is_valid().map_err(|e| r.usd_error(&target, e))? {
            return Ok(Err(format!(
                "connected to <{src}>, whose prim does not exist"
            )));
        }
        let ty = prim_type(r, &target)?;
        let is_graph = matches!(ty.as_str(), "NodeGraph" | "Material");
        if let Some(output) = sa.strip_prefix("outputs:") {
            if ty == "Shader" {
                return Ok(Ok(Producer::Output {
                    shader: sp.to_owned(),
                    output: output.to_owned(),
                }));
            }
            if !is_graph {
                return Ok(Err(not_connectable(&src, &ty)));
            }
            // A NodeGraph's (or Material's) output: followed to what it connects to.
        } else if sa.starts_with("inputs:") && (is_graph || ty == "Shader") {
            // An interface input: its value, or followed further.
            if attr_type(r, &target, sa)?.is_none() {
                return Ok(Err(format!("connected to <{src}>, which is not authored")));
            }
        } else {
            return Ok(Err(not_connectable(&src, &ty)));
        }
        cur = (sp.to_owned(), sa.to_owned());
    }
    Ok(Err(format!(
        "more than {MAX_HOPS} connections followed from {prim}.{attr}"
    )))
}

fn not_connectable(src: &str, ty: &str) -> String {
    format!(
        "connected to <{src}>, which is not an output or input of a Shader, NodeGraph or \
         Material ({})",
        if ty.is_empty() { "untyped prim" } else { ty }
    )
}

/// Records a warning on the prim at `prim` (once).
fn warn(r: &mut Reader<'_>, prim: &str, kind: WarningKind, message: String) {
    let w = Warning {
        prim: prim.to_owned(),
        kind,
        message,
    };
    if !r.warnings.contains(&w) {
        r.warnings.push(w);
    }
}

/// The network of the Material at `material`: its surface shader (from `outputs:mtlx:surface`,
/// else — also when that shader has no `info:id` — `outputs:surface`) and every Shader upstream, nodes in breadth-first order from the
/// surface shader (node 0). A material without a readable surface terminal gives a network
/// without nodes (`surface` `None`). Dangling connections and cycles are dropped with a
/// warning in `r.warnings` naming the prim and input.
pub fn read_network(r: &mut Reader<'_>, material: &str) -> Result<Network, LoadError> {
    Ok(read_network_terminal(r, material)?.0)
}

/// [`read_network`], with the terminal the surface was read from (`None` without a surface).
pub fn read_network_terminal(
    r: &mut Reader<'_>,
    material: &str,
) -> Result<(Network, Option<Terminal>), LoadError> {
    let mut net = Network {
        material: material.to_owned(),
        ..Network::default()
    };
    if !is_prim_path(material) {
        return Ok((net, None));
    }
    let mat = r.stage.prim(material);
    let mut surface = None;
    // A MaterialX surface shader without an `info:id`: used only when `outputs:surface` gives
    // nothing better.
    let mut unidentified = None;
    for (terminal, which) in [
        (MTLX_SURFACE, Terminal::Mtlx),
        (UNIVERSAL_SURFACE, Terminal::Universal),
    ] {
        if r.connections(&mat, terminal)?.is_empty() {
            continue;
        }
        match resolve(r, material, terminal)? {
            Ok(Producer::Output { shader, output }) => {
                let id = r.text(&r.stage.prim(shader.as_str()), "info:id")?;
                if which == Terminal::Mtlx && id.is_none_or(|s| s.is_empty()) {
                    unidentified = Some((shader, output, which));
                    continue;
                }
                surface = Some((shader, output, which));
                break;
            }
            Ok(Producer::Value { .. }) => {}
            Err(why) => warn(
                r,
                material,
                WarningKind::InvalidValue,
                match which {
                    Terminal::Mtlx => format!("{terminal}: {why}; outputs:surface is read instead"),
                    Terminal::Universal => format!("{terminal}: {why}; ignored"),
                },
            ),
        }
    }
    let Some((shader, output, terminal)) = surface.or(unidentified) else {
        return Ok((net, None));
    };
    let mut index: HashMap<String, usize> = HashMap::new();
    // A universal surface without an id is the material's own warning ("not
    // UsdPreviewSurface"); an upstream shader without one is this network's.
    let first = add_node(r, &mut net, &mut index, &shader, terminal == Terminal::Mtlx)?;
    net.surface = Some(Connection {
        node: first,
        output,
    });
    let mut next = 0;
    while next < net.nodes.len() {
        read_inputs(r, &mut net, &mut index, next)?;
        next += 1;
    }
    break_cycles(r, &mut net);
    Ok((net, Some(terminal)))
}

/// Adds the Shader at `path` as a node (inputs read later); its index. Without an `info:id`,
/// a warning when `warn_unidentified`.
fn add_node(
    r: &mut Reader<'_>,
    net: &mut Network,
    index: &mut HashMap<String, usize>,
    path: &str,
    warn_unidentified: bool,
) -> Result<usize, LoadError> {
    if let Some(&i) = index.get(path) {
        return Ok(i);
    }
    let prim = r.stage.prim(path);
    let nodedef = r.text(&prim, "info:id")?.filter(|s| !s.is_empty());
    if nodedef.is_none() && warn_unidentified {
        warn(
            r,
            path,
            WarningKind::Unsupported,
            "shader has no info:id (a shader by source asset or code is not read); its \
             outputs take their defaults"
                .to_owned(),
        );
    }
    // The output type, when the shader declares exactly one typed output.
    let mut outputs = Vec::new();
    for name in prim.property_names().map_err(|e| r.usd_error(&prim, e))? {
        if name.as_str().starts_with("outputs:") {
            outputs.push(attr_type(r, &prim, name.as_str())?);
        }
    }
    let ty = match outputs.as_slice() {
        [Some(t)] => usd_value_type(t).filter(|t| *t != ValueType::String),
        _ => None,
    };
    let i = net.nodes.len();
    net.nodes.push(NetNode {
        name: path.to_owned(),
        nodedef,
        category: String::new(),
        ty,
        inputs: Vec::new(),
    });
    index.insert(path.to_owned(), i);
    Ok(i)
}

/// Reads every authored `inputs:*` of node `i`.
fn read_inputs(
    r: &mut Reader<'_>,
    net: &mut Network,
    index: &mut HashMap<String, usize>,
    i: usize,
) -> Result<(), LoadError> {
    let path = net.nodes[i].name.clone();
    let prim = r.stage.prim(path.as_str());
    let names = prim.property_names().map_err(|e| r.usd_error(&prim, e))?;
    let mut inputs = Vec::new();
    for name in names {
        let attr = name.as_str();
        let Some(input) = attr.strip_prefix("inputs:") else {
            continue;
        };
        if !is_property_name(attr) {
            continue;
        }
        let declared = attr_type(r, &prim, attr)?;
        let mut ty = declared.as_deref().and_then(usd_value_type);
        if declared.is_some() && ty.is_none() {
            // Arrays (an LTESpectralAPI `wavelength:reflectance`) and other types a MaterialX
            // input cannot hold: not part of the network (the material's own fields read them).
            continue;
        }
        let source = match resolve(r, &path, attr)? {
            Err(why) => {
                warn(
                    r,
                    &path,
                    WarningKind::InvalidValue,
                    format!("{attr}: {why}; the input is dropped"),
                );
                continue;
            }
            Ok(Producer::Output { shader, output }) => {
                let node = add_node(r, net, index, &shader, true)?;
                NetSource::Connection(Connection { node, output })
            }
            Ok(Producer::Value { prim: vp, attr: va }) => {
                let held = if vp == path && va == attr {
                    None
                } else {
                    Some((vp, va))
                };
                match read_value(r, &path, attr, held, ty)? {
                    Some((t, v)) => {
                        ty = t;
                        NetSource::Value(v)
                    }
                    None => continue,
                }
            }
        };
        inputs.push(NetInput {
            name: input.to_owned(),
            ty,
            source,
        });
    }
    // A UsdUVTexture's file takes the colour space its sourceColorSpace states (`sRGB`,
    // `raw`; `auto` leaves the file's `colorSpace` metadata, else none). MaterialX's
    // ND_UsdUVTexture has no such input (the colour space is the file's), so the input itself
    // is left out once folded into the file.
    if net.nodes[i].nodedef.as_deref() == Some("UsdUVTexture") {
        let space = inputs
            .iter()
            .find_map(|inp| match (&inp.name[..], &inp.source) {
                ("sourceColorSpace", NetSource::Value(Value::String(s))) => match s.as_str() {
                    "sRGB" => Some("srgb_texture"),
                    "raw" => Some("raw"),
                    _ => None,
                },
                _ => None,
            });
        if let Some(space) = space {
            for inp in &mut inputs {
                if let NetSource::Value(Value::File(f)) = &mut inp.source {
                    f.colorspace = space.to_owned();
                }
            }
        }
        inputs.retain(|inp| inp.name != "sourceColorSpace");
    }
    net.nodes[i].inputs = inputs;
    Ok(())
}

/// A MaterialX colour-space name for a USD `colorSpace` token (`sRGB` → `srgb_texture`,
/// `raw` → `raw`; MaterialX names pass through).
fn colorspace_name(token: &str) -> String {
    match token {
        "sRGB" | "srgb" => "srgb_texture".to_owned(),
        "auto" => String::new(),
        other => other.to_owned(),
    }
}

/// The value of input `attr` on the shader `shader`, held by `held` (an interface input) or
/// by the input itself; converted to `ty` (or the held value's own type), returned with the
/// type. `None` when no value is authored or (with a warning) when it does not convert.
fn read_value(
    r: &mut Reader<'_>,
    shader: &str,
    attr: &str,
    held: Option<(String, String)>,
    ty: Option<ValueType>,
) -> Result<Option<(Option<ValueType>, Value)>, LoadError> {
    let sprim = r.stage.prim(shader);
    // A value on the interface input; else (an interface input without one) the input's own.
    let mut holder = (shader.to_owned(), attr.to_owned());
    let mut raw = None;
    if let Some((hp, ha)) = held {
        let p = r.stage.prim(hp.as_str());
        raw = r.raw(&p, &ha)?;
        if raw.is_some() {
            holder = (hp, ha);
        }
    }
    if raw.is_none() {
        raw = r.raw(&sprim, attr)?;
    }
    let Some(raw) = raw else {
        return Ok(None);
    };
    if matches!(raw, sdf::Value::ValueBlock) {
        return Ok(None);
    }
    let hprim = r.stage.prim(holder.0.as_str());
    let ty = match ty {
        Some(t) => Some(t),
        None => match attr_type(r, &hprim, &holder.1)? {
            Some(t) => usd_value_type(&t),
            None => inferred_type(&raw),
        },
    };
    let v = match ty {
        Some(ValueType::Filename) => match r.asset(&hprim, &holder.1) {
            Ok(Some(asset)) => {
                let space = r
                    .metadata_text(&sprim, attr, "colorSpace")
                    .or_else(|| r.metadata_text(&hprim, &holder.1, "colorSpace"))
                    .map(|s| colorspace_name(&s))
                    .unwrap_or_default();
                if asset.resolved.is_none() {
                    warn(
                        r,
                        shader,
                        WarningKind::UnresolvedAsset,
                        format!("texture @{}@ does not resolve to a file", asset.authored),
                    );
                }
                Some(Value::File(FileValue {
                    asset,
                    colorspace: space,
                }))
            }
            Ok(None) => return Ok(None),
            Err(LoadError::AttributeType { .. }) => None,
            Err(e) => return Err(e),
        },
        Some(t @ (ValueType::Color3 | ValueType::Color4)) => {
            let mut v = convert(&raw, t);
            // A colour stated in another colour space (`colorSpace` metadata) is converted
            // to lin_rec709, lux's working space.
            let space = r
                .metadata_text(&sprim, attr, "colorSpace")
                .or_else(|| r.metadata_text(&hprim, &holder.1, "colorSpace"));
            if let (Some(space), Some(Value::Numbers(c))) = (space, v.as_mut())
                && !crate::shading::color_space::to_lin_rec709(&space, c)
            {
                warn(
                    r,
                    shader,
                    WarningKind::Unsupported,
                    format!(
                        "{attr}: colour space {space:?} is not one lux converts from \
                         (lin_rec709, srgb_texture, g22_rec709, g18_rec709, acescg); the value \
                         is read as lin_rec709"
                    ),
                );
            }
            v
        }
        Some(t) => convert(&raw, t),
        None => None,
    };
    if v.is_none() {
        warn(
            r,
            shader,
            WarningKind::InvalidValue,
            format!(
                "{attr}: a {} value{} is not a {}; the input is dropped",
                crate::value::type_label(&raw),
                if holder.0 == shader {
                    String::new()
                } else {
                    format!(" (from <{}.{}>)", holder.0, holder.1)
                },
                ty.map_or("supported type", ValueType::name),
            ),
        );
    }
    Ok(v.map(|v| (ty, v)))
}

/// A raw value as a MaterialX value of type `ty`.
fn convert(raw: &sdf::Value, ty: ValueType) -> Option<Value> {
    use crate::value::{as_bool, as_f64, as_text, as_vec2, as_vec3, as_vec4};
    let n = |v: Vec<f64>| Some(Value::Numbers(v));
    match ty {
        ValueType::Float => n(vec![as_f64(raw)?]),
        ValueType::Integer => match raw {
            sdf::Value::Bool(_) => None,
            _ => as_f64(raw)
                .filter(|x| x.fract() == 0.0)
                .and_then(|x| n(vec![x])),
        },
        ValueType::Boolean => n(vec![if as_bool(raw)? { 1.0 } else { 0.0 }]),
        ValueType::Vector2 => {
            let v = as_vec2(raw)?;
            n(vec![v.x, v.y])
        }
        ValueType::Color3 | ValueType::Vector3 => {
            let v = as_vec3(raw)?;
            n(vec![v.x, v.y, v.z])
        }
        ValueType::Color4 | ValueType::Vector4 => {
            let v = as_vec4(raw)?;
            n(vec![v.x, v.y, v.z, v.w])
        }
        ValueType::Matrix33 => match raw {
            sdf::Value::Matrix3d(m) => n(m.0.to_vec()),
            _ => None,
        },
        ValueType::Matrix44 => match raw {
            sdf::Value::Matrix4d(m) => n(m.0.to_vec()),
            _ => None,
        },
        ValueType::String => Some(Value::String(as_text(raw)?)),
        _ => None,
    }
}

/// Drops every connection that closes a cycle (found depth-first from the surface node),
/// with a warning naming the shader and the input.
fn break_cycles(r: &mut Reader<'_>, net: &mut Network) {
    let Some(root) = net.surface.as_ref().map(|c| c.node) else {
        return;
    };
    // 0 unvisited, 1 on the stack, 2 done.
    let mut state = vec![0u8; net.nodes.len()];
    // (node, next input to look at)
    let mut stack = vec![(root, 0usize)];
    state[root] = 1;
    let mut dropped: Vec<(usize, usize)> = Vec::new();
    while let Some(top) = stack.last_mut() {
        let (node, k) = *top;
        top.1 += 1;
        let Some(input) = net.nodes[node].inputs.get(k) else {
            state[node] = 2;
            stack.pop();
            continue;
        };
        let NetSource::Connection(c) = &input.source else {
            continue;
        };
        match state.get(c.node) {
            Some(0) => {
                state[c.node] = 1;
                stack.push((c.node, 0));
            }
            Some(1) => dropped.push((node, k)),
            _ => {}
        }
    }
    // Remove from the last so the indices stay valid.
    dropped.sort_unstable();
    for &(node, k) in dropped.iter().rev() {
        let input = net.nodes[node].inputs.remove(k);
        let upstream = match &input.source {
            NetSource::Connection(c) => net.nodes[c.node].name.clone(),
            NetSource::Value(_) => String::new(),
        };
        let name = net.nodes[node].name.clone();
        warn(
            r,
            &name,
            WarningKind::InvalidValue,
            format!(
                "inputs:{}: connection cycle through <{upstream}>; the input is dropped",
                input.name
            ),
        );
    }
}
