//! A [`Material`]'s UsdPreviewSurface fields as the UsdShade network they describe: a
//! `UsdPreviewSurface` node with its inputs, each texture a `UsdUVTexture` reading
//! coordinates from a `UsdPrimvarReader_float2` (through a `UsdTransform2d` when one is set),
//! each primvar input a `UsdPrimvarReader_*`. Flattened ([`crate::shading::flatten`]), it is
//! the MaterialX graph of the material (`ND_UsdPreviewSurface_surfaceshader`), so a material
//! built in code shades exactly as one read from a stage.

use glam::DVec3;

use crate::material::{Input, Material, PrimvarInput, SourceColorSpace, TextureInput, Wrap};
use crate::shading::{
    Connection, FileValue, NetInput, NetNode, NetSource, Network, Value, ValueType,
};

/// What an input of the surface reads: a constant, or a node's output.
enum Feed {
    Value(ValueType, Value),
    Node(ValueType, Connection),
}

struct Builder {
    net: Network,
}

impl Builder {
    fn node(&mut self, name: String, nodedef: &str, inputs: Vec<NetInput>) -> usize {
        self.net.nodes.push(NetNode {
            name,
            nodedef: Some(nodedef.to_owned()),
            category: String::new(),
            ty: None,
            inputs,
        });
        self.net.nodes.len() - 1
    }

    /// The `UsdUVTexture` of `t` (with its coordinate reader and transform); its output
    /// `t.output`.
    fn texture(&mut self, t: &TextureInput) -> Connection {
        let base = &t.shader;
        let reader = self.node(
            format!("{base}/st_reader"),
            "UsdPrimvarReader_float2",
            vec![
                value(
                    "varname",
                    ValueType::String,
                    Value::String(t.st_primvar.clone()),
                ),
                value(
                    "fallback",
                    ValueType::Vector2,
                    numbers(&t.st_fallback.to_array()),
                ),
            ],
        );
        let mut st = Connection {
            node: reader,
            output: "result".into(),
        };
        if let Some(x) = &t.transform {
            let transform = self.node(
                format!("{base}/st_transform"),
                "UsdTransform2d",
                vec![
                    connected("in", ValueType::Vector2, st),
                    value("rotation", ValueType::Float, numbers(&[x.rotation])),
                    value("scale", ValueType::Vector2, numbers(&x.scale.to_array())),
                    value(
                        "translation",
                        ValueType::Vector2,
                        numbers(&x.translation.to_array()),
                    ),
                ],
            );
            st = Connection {
                node: transform,
                output: "result".into(),
            };
        }
        let mut inputs = vec![connected("st", ValueType::Vector2, st)];
        // `useMetadata`, the schema default, is left unauthored, as a stage leaves it: the
        // MaterialX node's own default (`periodic`) then applies, which is what lux reads
        // `useMetadata` as.
        for (name, wrap) in [("wrapS", t.wrap_s), ("wrapT", t.wrap_t)] {
            if wrap != Wrap::UseMetadata {
                inputs.push(value(
                    name,
                    ValueType::String,
                    Value::String(wrap.token().into()),
                ));
            }
        }
        inputs.extend([
            value("scale", ValueType::Vector4, numbers(&t.scale.to_array())),
            value("bias", ValueType::Vector4, numbers(&t.bias.to_array())),
            value(
                "fallback",
                ValueType::Vector4,
                numbers(&t.fallback.to_array()),
            ),
        ]);
        if let Some(asset) = &t.file {
            let colorspace = match t.source_color_space {
                SourceColorSpace::Srgb => "srgb_texture",
                SourceColorSpace::Raw => "raw",
                SourceColorSpace::Auto => "",
            };
            inputs.push(value(
                "file",
                ValueType::Filename,
                Value::File(FileValue {
                    asset: asset.clone(),
                    colorspace: colorspace.into(),
                }),
            ));
        }
        let node = self.node(base.clone(), "UsdUVTexture", inputs);
        Connection {
            node,
            output: t.output.clone(),
        }
    }

    /// The `UsdPrimvarReader_*` of `p`; its output `result`.
    fn primvar(&mut self, p: &PrimvarInput) -> Connection {
        let (ty, fallback) = match p.components {
            1 => (ValueType::Float, &p.fallback.to_array()[..1]),
            2 => (ValueType::Vector2, &p.fallback.to_array()[..2]),
            3 => (ValueType::Vector3, &p.fallback.to_array()[..3]),
            _ => (ValueType::Vector4, &p.fallback.to_array()[..]),
        };
        let ty = if p.id == "UsdPrimvarReader_int" {
            ValueType::Integer
        } else {
            ty
        };
        let node = self.node(
            p.shader.clone(),
            &p.id,
            vec![
                value("varname", ValueType::String, Value::String(p.name.clone())),
                value("fallback", ty, numbers(fallback)),
            ],
        );
        Connection {
            node,
            output: "result".into(),
        }
    }

    fn colour(&mut self, i: &Input<DVec3>) -> Feed {
        match i {
            Input::Value(c) => Feed::Value(ValueType::Color3, numbers(&c.to_array())),
            Input::Texture(t) => Feed::Node(ValueType::Color3, self.texture(t)),
            Input::Primvar(p) => Feed::Node(ValueType::Color3, self.primvar(p)),
        }
    }

    fn float(&mut self, i: &Input<f64>) -> Feed {
        match i {
            Input::Value(v) => Feed::Value(ValueType::Float, numbers(&[*v])),
            Input::Texture(t) => Feed::Node(ValueType::Float, self.texture(t)),
            Input::Primvar(p) => Feed::Node(ValueType::Float, self.primvar(p)),
        }
    }
}

fn numbers(v: &[f64]) -> Value {
    Value::Numbers(v.to_vec())
}

fn value(name: &str, ty: ValueType, v: Value) -> NetInput {
    NetInput {
        name: name.into(),
        ty: Some(ty),
        source: NetSource::Value(v),
    }
}

fn connected(name: &str, ty: ValueType, c: Connection) -> NetInput {
    NetInput {
        name: name.into(),
        ty: Some(ty),
        source: NetSource::Connection(c),
    }
}

impl Material {
    /// The UsdShade network these UsdPreviewSurface fields describe (see the module docs):
    /// the surface node first, named `<path>/PreviewSurface`, then its texture and primvar
    /// readers. Every input is authored, the schema defaults included.
    pub fn preview_network(&self) -> Network {
        let mut b = Builder {
            net: Network {
                material: self.path.clone(),
                nodes: Vec::new(),
                surface: None,
            },
        };
        // The surface first, its inputs filled once the readers exist.
        let surface = b.node(
            format!("{}/PreviewSurface", self.path),
            "UsdPreviewSurface",
            Vec::new(),
        );
        let mut feeds: Vec<(&str, Feed)> = vec![
            ("diffuseColor", b.colour(&self.diffuse)),
            ("specularColor", b.colour(&self.specular)),
            ("metallic", b.float(&self.metallic)),
            ("roughness", b.float(&self.roughness)),
            ("clearcoat", b.float(&self.clearcoat)),
            ("clearcoatRoughness", b.float(&self.clearcoat_roughness)),
            ("ior", b.float(&self.ior)),
            ("opacity", b.float(&self.opacity)),
        ];
        feeds.push((
            "useSpecularWorkflow",
            Feed::Value(
                ValueType::Integer,
                numbers(&[f64::from(u8::from(self.use_specular_workflow))]),
            ),
        ));
        feeds.push((
            "opacityThreshold",
            Feed::Value(ValueType::Float, numbers(&[self.opacity_threshold])),
        ));
        let emission = match (&self.emissive_texture, &self.emissive_primvar) {
            (Some(t), _) => Feed::Node(ValueType::Color3, b.texture(t)),
            (None, Some(p)) => Feed::Node(ValueType::Color3, b.primvar(p)),
            (None, None) => Feed::Value(ValueType::Color3, numbers(&self.emissive.to_array())),
        };
        feeds.push(("emissiveColor", emission));
        if let Some(t) = &self.normal {
            feeds.push(("normal", Feed::Node(ValueType::Vector3, b.texture(t))));
        }
        let inputs = feeds
            .into_iter()
            .map(|(name, feed)| match feed {
                Feed::Value(ty, v) => value(name, ty, v),
                Feed::Node(ty, c) => connected(name, ty, c),
            })
            .collect();
        b.net.nodes[surface].inputs = inputs;
        b.net.surface = Some(Connection {
            node: surface,
            output: "surface".into(),
        });
        b.net
    }
}
