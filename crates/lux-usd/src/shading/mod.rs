//! Shading networks as MaterialX describes them (MaterialX Specification, "Nodes", "Node
//! Graphs", "Materials"): what lux-usd hands a renderer for a material whose surface is a
//! MaterialX shader (`outputs:mtlx:surface`, an inline `ND_*` shader, a `.mtlx` document
//! composed into the stage) or a UsdPreviewSurface network (whose nodes are MaterialX's
//! `ND_UsdPreviewSurface_surfaceshader`, `ND_UsdUVTexture`, `ND_UsdPrimvarReader_*`,
//! `ND_UsdTransform2d`, defined as node graphs in `usd_preview_surface.mtlx`).
//!
//! Two stages:
//!
//! - a [`Network`]: the shader nodes as authored — a node names its nodedef (or only its
//!   category), its authored inputs are values or connections to another node's output;
//!   NodeGraph boundaries (USD NodeGraph prims, MaterialX `<nodegraph>` with `interfacename`)
//!   are already resolved away, so a connection always names a node of the network;
//! - a [`ShadingGraph`]: the network *flattened* against the MaterialX library
//!   ([`flatten`]): every node's nodedef resolved, every input present (authored, else the
//!   nodedef's `value`, else its `defaultgeomprop` as [`Source::Geomprop`]), every node whose
//!   nodedef has a node-graph implementation in the library (`standard_surface`,
//!   `open_pbr_surface`, `UsdPreviewSurface`, `UsdUVTexture`, …) replaced by that graph, and the
//!   nodes sorted so that every connection points to an earlier node. What is left are the
//!   nodes a renderer implements natively: the pbrlib closures (`oren_nayar_diffuse_bsdf`,
//!   `dielectric_bsdf`, `layer`, …), the pbrlib helpers without a graph in the library
//!   (`roughness_anisotropy`, `artistic_ior`, …) and the stdlib nodes (`multiply`, `image`, …).

pub mod color_space;
mod flatten;

pub use flatten::flatten;

use crate::reader::AssetRef;

/// A MaterialX data type (MaterialX Specification, "MaterialX Data Types"), as a nodedef's
/// `type` attribute names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ValueType {
    /// `integer`.
    Integer,
    /// `boolean`.
    Boolean,
    /// `float`.
    Float,
    /// `color3`.
    Color3,
    /// `color4`.
    Color4,
    /// `vector2`.
    Vector2,
    /// `vector3`.
    Vector3,
    /// `vector4`.
    Vector4,
    /// `matrix33`.
    Matrix33,
    /// `matrix44`.
    Matrix44,
    /// `string`.
    String,
    /// `filename`.
    Filename,
    /// `BSDF` (a closure).
    Bsdf,
    /// `EDF` (an emission closure).
    Edf,
    /// `VDF` (a volume closure).
    Vdf,
    /// `surfaceshader`.
    SurfaceShader,
    /// `displacementshader`.
    DisplacementShader,
    /// `volumeshader`.
    VolumeShader,
    /// `material`.
    Material,
}

impl ValueType {
    /// The type named by a MaterialX `type` attribute (`"color3"`, `"BSDF"`, …).
    pub fn parse(name: &str) -> Option<ValueType> {
        Some(match name {
            "integer" => ValueType::Integer,
            "boolean" => ValueType::Boolean,
            "float" => ValueType::Float,
            "color3" => ValueType::Color3,
            "color4" => ValueType::Color4,
            "vector2" => ValueType::Vector2,
            "vector3" => ValueType::Vector3,
            "vector4" => ValueType::Vector4,
            "matrix33" => ValueType::Matrix33,
            "matrix44" => ValueType::Matrix44,
            "string" => ValueType::String,
            "filename" => ValueType::Filename,
            "BSDF" => ValueType::Bsdf,
            "EDF" => ValueType::Edf,
            "VDF" => ValueType::Vdf,
            "surfaceshader" => ValueType::SurfaceShader,
            "displacementshader" => ValueType::DisplacementShader,
            "volumeshader" => ValueType::VolumeShader,
            "material" => ValueType::Material,
            _ => return None,
        })
    }

    /// The MaterialX name of the type.
    pub fn name(self) -> &'static str {
        match self {
            ValueType::Integer => "integer",
            ValueType::Boolean => "boolean",
            ValueType::Float => "float",
            ValueType::Color3 => "color3",
            ValueType::Color4 => "color4",
            ValueType::Vector2 => "vector2",
            ValueType::Vector3 => "vector3",
            ValueType::Vector4 => "vector4",
            ValueType::Matrix33 => "matrix33",
            ValueType::Matrix44 => "matrix44",
            ValueType::String => "string",
            ValueType::Filename => "filename",
            ValueType::Bsdf => "BSDF",
            ValueType::Edf => "EDF",
            ValueType::Vdf => "VDF",
            ValueType::SurfaceShader => "surfaceshader",
            ValueType::DisplacementShader => "displacementshader",
            ValueType::VolumeShader => "volumeshader",
            ValueType::Material => "material",
        }
    }

    /// How many floats a value of the type holds (1 for `float`, `integer` and `boolean`,
    /// 3 for `color3`, 16 for `matrix44`; 0 for strings, filenames and closures).
    pub fn components(self) -> usize {
        match self {
            ValueType::Integer | ValueType::Boolean | ValueType::Float => 1,
            ValueType::Vector2 => 2,
            ValueType::Color3 | ValueType::Vector3 => 3,
            ValueType::Color4 | ValueType::Vector4 => 4,
            ValueType::Matrix33 => 9,
            ValueType::Matrix44 => 16,
            _ => 0,
        }
    }
}

/// A constant input value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A `float`, `integer` or `boolean` (1 or 0), or a `color3`, `vector2`, … or matrix (row
    /// by row) as its components; the input's [`ValueType`] says which.
    Numbers(Vec<f64>),
    /// A `string` (for example `image`'s `uaddressmode`, `geompropvalue`'s `geomprop`).
    String(String),
    /// A `filename`, resolved.
    File(FileValue),
}

/// A `filename` input: the path as authored (after `fileprefix`), where it resolved, and the
/// colour space its texels are in.
#[derive(Clone, Debug, PartialEq)]
pub struct FileValue {
    /// The asset: as authored (with the document's `fileprefix` applied) and resolved against
    /// the document or layer that authored it (`None` when the file does not exist).
    pub asset: AssetRef,
    /// The colour space of the file's texels (`colorspace` on the input or inherited from the
    /// document or node; `UsdUVTexture`'s `sourceColorSpace` mapped to `srgb_texture` / `raw`),
    /// empty when unstated (a renderer then decides by the file type, as MaterialX does).
    pub colorspace: String,
}

/// A connection in a [`Network`]: node `node`'s output named `output` (`"out"` for a
/// single-output node).
#[derive(Clone, Debug, PartialEq)]
pub struct Connection {
    /// Index into [`Network::nodes`].
    pub node: usize,
    /// Output name.
    pub output: String,
}

/// An authored input of a network node.
#[derive(Clone, Debug, PartialEq)]
pub struct NetInput {
    /// Input name (`base_color`, `diffuseColor`, `file`).
    pub name: String,
    /// Its type as authored, when the document or layer states one.
    pub ty: Option<ValueType>,
    /// A value or a connection.
    pub source: NetSource,
}

/// What feeds an authored input.
#[derive(Clone, Debug, PartialEq)]
pub enum NetSource {
    /// A constant.
    Value(Value),
    /// Another node's output.
    Connection(Connection),
}

/// A shader node as authored.
#[derive(Clone, Debug, PartialEq)]
pub struct NetNode {
    /// Where it is authored, for messages: the Shader prim path, or the document path and
    /// node name (`chess_set.mtlx:/NG_BishopBlack/image_color`).
    pub name: String,
    /// The nodedef when authored (`info:id`, `nodedef="…"`), e.g.
    /// `ND_standard_surface_surfaceshader`, `UsdPreviewSurface` (USD's shader ids are mapped to
    /// MaterialX's nodedef names by [`flatten`]).
    pub nodedef: Option<String>,
    /// The node's category (`standard_surface`, `image`); empty when only the nodedef is known.
    pub category: String,
    /// The node's output type when authored (`type="color3"`), which with the inputs' types
    /// selects the nodedef of a category (MaterialX Specification, "Nodes").
    pub ty: Option<ValueType>,
    /// Authored inputs.
    pub inputs: Vec<NetInput>,
}

impl NetNode {
    /// The (name, type) of each input whose type is known, which with the node's type selects
    /// the nodedef of its category.
    pub fn input_types(&self) -> Vec<(&str, ValueType)> {
        self.inputs
            .iter()
            .filter_map(|i| i.ty.map(|t| (i.name.as_str(), t)))
            .collect()
    }
}

/// A material's shading network as authored, NodeGraph boundaries resolved away.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Network {
    /// The Material prim path.
    pub material: String,
    /// The nodes.
    pub nodes: Vec<NetNode>,
    /// The surface shader output the material's surface terminal connects to.
    pub surface: Option<Connection>,
}

/// Where a flattened node's input comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A constant (authored, or the nodedef's default).
    Value(Value),
    /// Output `output` (an index into that node's [`GraphNode::outputs`]) of an earlier node.
    Node {
        /// Index into [`ShadingGraph::nodes`], smaller than the index of the node reading it.
        node: usize,
        /// Index into its outputs.
        output: usize,
    },
    /// A geometric property by its MaterialX `geompropdef` name, from an unconnected input's
    /// `defaultgeomprop`: `UV0` (texture coordinates, set 0), `Nworld`, `Nobject` (shading
    /// normal), `Tworld`, `Tobject` (tangent), `Bworld` (bitangent), `Pworld`, `Pobject`
    /// (position).
    Geomprop(String),
}

/// An input of a flattened node.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphInput {
    /// Input name, as the nodedef declares it.
    pub name: String,
    /// Type, as the nodedef declares it.
    pub ty: ValueType,
    /// What feeds it.
    pub source: Source,
}

/// A node of a flattened graph: one a renderer implements natively.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphNode {
    /// Where it came from, for messages: the authored node's name, and for nodes of an
    /// expanded implementation graph that name followed by the graph's node name
    /// (`/World/Mat/Surface/NG_standard_surface_surfaceshader_100/coat_affected_roughness`).
    pub name: String,
    /// The node's category (`multiply`, `dielectric_bsdf`, `image`).
    pub category: String,
    /// The resolved nodedef (`ND_multiply_color3FA`).
    pub nodedef: String,
    /// The nodedef's outputs: name and type (`[("out", Color3)]`).
    pub outputs: Vec<(String, ValueType)>,
    /// Every input the nodedef declares, in its order.
    pub inputs: Vec<GraphInput>,
}

impl GraphNode {
    /// The input named `name`.
    pub fn input(&self, name: &str) -> Option<&GraphInput> {
        self.inputs.iter().find(|i| i.name == name)
    }
}

/// A material's shading network flattened against the MaterialX library ([`flatten`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadingGraph {
    /// The Material prim path.
    pub material: String,
    /// The shading model as authored: the surface shader's nodedef
    /// (`ND_standard_surface_surfaceshader`, `ND_open_pbr_surface_surfaceshader`,
    /// `ND_UsdPreviewSurface_surfaceshader`, …).
    pub model: String,
    /// The nodes, every connection pointing to an earlier node.
    pub nodes: Vec<GraphNode>,
    /// The `surfaceshader` output that shades the material (`None`: no surface).
    pub surface: Option<(usize, usize)>,
    /// What could not be honoured as authored, each naming node and input (an unknown
    /// nodedef whose output takes its default, an unresolved file, an input of the wrong
    /// type); `lux info` lists them.
    pub notes: Vec<String>,
}
