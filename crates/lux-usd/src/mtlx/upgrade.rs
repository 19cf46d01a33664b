//! Upgrading documents older than MaterialX 1.39 (MaterialX Specification, "MTLX File Format
//! Definition": "The MaterialX library automatically upgrades older-versioned documents to the
//! current MaterialX version at load time"), as MaterialX 1.39 does for 1.38 documents:
//!
//! - a `channels` swizzle on an input connection becomes a `swizzle` node between the two;
//! - `swizzle` nodes (removed in 1.39) become `extract` (one channel), `convert` (a float
//!   spread over every channel, or the leading channels in order) or a `separateN` feeding a
//!   `combineN` (any other channel string; `0`/`1` become constants);
//! - `atan2`'s inputs `in1`/`in2` are renamed `iny`/`inx`;
//! - `normalmap`'s `space` input (removed in 1.39) is dropped.

use std::collections::HashSet;

use super::document::{Document, Input, Node};
use crate::shading::{Value, ValueType};

/// Upgrades `doc` to MaterialX 1.39 in place (see the module docs); [`Document::version`]
/// keeps the version as authored.
pub fn upgrade(doc: &mut Document) {
    upgrade_scope(&mut doc.nodes);
    for g in &mut doc.nodegraphs {
        upgrade_scope(&mut g.nodes);
    }
}

fn unique(names: &mut HashSet<String>, base: &str) -> String {
    let mut name = base.to_string();
    let mut k = 2;
    while names.contains(&name) {
        name = format!("{base}{k}");
        k += 1;
    }
    names.insert(name.clone());
    name
}

fn upgrade_scope(nodes: &mut Vec<Node>) {
    let mut names: HashSet<String> = nodes.iter().map(|n| n.name.clone()).collect();
    // `channels` on connections → swizzle nodes.
    let mut added = Vec::new();
    for ni in 0..nodes.len() {
        for ii in 0..nodes[ni].inputs.len() {
            let Some(channels) = nodes[ni].inputs[ii].channels.take() else {
                continue;
            };
            let input = nodes[ni].inputs[ii].clone();
            let Some(src) = &input.nodename else { continue };
            let src_ty = nodes
                .iter()
                .find(|n| &n.name == src)
                .and_then(|n| n.ty)
                .or(input.ty);
            let name = unique(&mut names, "swizzle");
            let out_ty = input.ty.unwrap_or(ValueType::Float);
            let mut feed = input.clone();
            feed.name = "in".into();
            feed.ty = src_ty;
            added.push(Node {
                name: name.clone(),
                category: "swizzle".into(),
                type_name: out_ty.name().into(),
                ty: Some(out_ty),
                nodedef: None,
                version: None,
                inputs: vec![
                    feed,
                    Input::constant("channels", ValueType::String, Value::String(channels)),
                ],
                line: input.line,
            });
            let target = &mut nodes[ni].inputs[ii];
            target.nodename = Some(name);
            target.output = None;
        }
    }
    nodes.extend(added);

    let mut extra = Vec::new();
    for ni in 0..nodes.len() {
        let types: Vec<(String, Option<ValueType>)> =
            nodes.iter().map(|n| (n.name.clone(), n.ty)).collect();
        let node = &mut nodes[ni];
        match node.category.as_str() {
            "atan2" => {
                for i in &mut node.inputs {
                    match i.name.as_str() {
                        "in1" => i.name = "iny".into(),
                        "in2" => i.name = "inx".into(),
                        _ => {}
                    }
                }
            }
            "normalmap" => node.inputs.retain(|i| i.name != "space"),
            "swizzle" => {
                let src_ty = node.input("in").and_then(|i| {
                    i.nodename
                        .as_ref()
                        .and_then(|s| types.iter().find(|(n, _)| n == s).and_then(|t| t.1))
                        .or(i.ty)
                });
                if let Some(sep) = upgrade_swizzle(node, src_ty, &mut names) {
                    extra.push(sep);
                }
            }
            _ => {}
        }
    }
    nodes.extend(extra);
}

fn channel_index(c: char) -> Option<usize> {
    match c {
        'r' | 'x' => Some(0),
        'g' | 'y' => Some(1),
        'b' | 'z' => Some(2),
        'a' | 'w' => Some(3),
        _ => None,
    }
}

/// Rewrites a swizzle node in place; returns the `separateN` node it now reads, if any.
fn upgrade_swizzle(
    node: &mut Node,
    src_ty: Option<ValueType>,
    names: &mut HashSet<String>,
) -> Option<Node> {
    let channels = match node.input("channels").and_then(|i| i.value.clone()) {
        Some(Value::String(s)) => s,
        _ => String::new(),
    };
    let mut input = node.input("in").cloned()?;
    input.ty = src_ty.or(input.ty);
    let m = src_ty.map_or(1, |t| t.components().max(1));
    let n = channels.chars().count();
    let out_ty = node.ty.unwrap_or(ValueType::Float);
    let chars: Vec<char> = channels.chars().collect();
    if n == 1 && m > 1 {
        node.category = "extract".into();
        let index = channel_index(chars[0]).unwrap_or(0);
        node.inputs = vec![
            input,
            Input::constant(
                "index",
                ValueType::Integer,
                Value::Numbers(vec![index as f64]),
            ),
        ];
        return None;
    }
    let spread = m == 1 && chars.iter().all(|&c| channel_index(c) == Some(0));
    let leading = chars
        .iter()
        .enumerate()
        .all(|(k, &c)| channel_index(c) == Some(k) && k < m);
    if spread || leading {
        node.category = if src_ty == Some(out_ty) {
            "dot".into()
        } else {
            "convert".into()
        };
        node.inputs = vec![input];
        return None;
    }
    let letters: &[&str] = match src_ty {
        Some(ValueType::Color3 | ValueType::Color4) => &["r", "g", "b", "a"],
        _ => &["x", "y", "z", "w"],
    };
    let sep = (m > 1).then(|| {
        let name = unique(names, "separate");
        Node {
            name,
            category: format!("separate{m}"),
            type_name: "multioutput".into(),
            ty: None,
            nodedef: None,
            version: None,
            inputs: vec![Input {
                name: "in".into(),
                ..input.clone()
            }],
            line: node.line,
        }
    });
    node.category = format!("combine{n}");
    node.inputs = chars
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let name = format!("in{}", k + 1);
            match (c, channel_index(c), &sep) {
                ('1', _, _) => Input::constant(&name, ValueType::Float, Value::Numbers(vec![1.0])),
                (_, Some(i), Some(sep)) if i < m => Input::connected(
                    &name,
                    Some(ValueType::Float),
                    &sep.name,
                    Some(&format!("out{}", letters[i])),
                ),
                (_, Some(_), None) => Input {
                    name: name.clone(),
                    ty: Some(ValueType::Float),
                    ..input.clone()
                },
                _ => Input::constant(&name, ValueType::Float, Value::Numbers(vec![0.0])),
            }
        })
        .collect();
    sep
}
