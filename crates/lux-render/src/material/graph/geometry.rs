//! The geometric nodes (`MaterialX.StandardNodes.md`, "Geometric Nodes": `texcoord`,
//! `position`, `normal`, `tangent`, `bitangent`, `geompropvalue`, `geompropvalueuniform`) and
//! the `defaultgeomprop`s of unconnected inputs (`UV0`, `Nworld`, `Tworld`, `Bworld`,
//! `Pworld` and their object-space forms), read from a [`ShadingContext`].

use super::ShadingContext;
use glam::DVec4;

/// A geometric quantity of the hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Geom {
    /// Position (`Pworld`).
    P,
    /// Shading normal (`Nworld`).
    N,
    /// Tangent (`Tworld`).
    T,
    /// Bitangent (`Bworld`).
    B,
    /// Texture coordinates set 0 (`UV0`).
    Uv,
}

impl Geom {
    /// The quantity a `geompropdef` name stands for, and whether it is in world space
    /// (lux's hits carry world-space quantities only: an object-space one is read in world
    /// space and noted).
    pub(crate) fn of_geomprop(name: &str) -> Option<(Geom, bool)> {
        Some(match name {
            "UV0" => (Geom::Uv, true),
            "Nworld" => (Geom::N, true),
            "Nobject" => (Geom::N, false),
            "Tworld" => (Geom::T, true),
            "Tobject" => (Geom::T, false),
            "Bworld" => (Geom::B, true),
            "Bobject" => (Geom::B, false),
            "Pworld" => (Geom::P, true),
            "Pobject" => (Geom::P, false),
            _ => return None,
        })
    }

    /// The quantity a geometric node's category reads.
    pub(crate) fn of_category(category: &str) -> Option<Geom> {
        Some(match category {
            "texcoord" => Geom::Uv,
            "position" => Geom::P,
            "normal" => Geom::N,
            "tangent" => Geom::T,
            "bitangent" => Geom::B,
            _ => return None,
        })
    }

    /// Its value at a hit, canonical (`UV0` as `(u, v, 0, 0)`, vectors with w = 0).
    #[inline]
    pub(crate) fn at(self, ctx: &ShadingContext) -> DVec4 {
        match self {
            Geom::P => ctx.p.extend(0.0),
            Geom::N => ctx.n.extend(0.0),
            Geom::T => ctx.t.extend(0.0),
            Geom::B => ctx.b.extend(0.0),
            Geom::Uv => DVec4::new(ctx.uv.x, ctx.uv.y, 0.0, 0.0),
        }
    }
}

/// `geompropvalue`: the primvar in `slot`, else (absent or not finite) `default`.
#[inline]
pub(crate) fn primvar(ctx: &ShadingContext, slot: usize, default: DVec4) -> DVec4 {
    match ctx.primvars.get(slot) {
        Some(v) if v.is_finite() => *v,
        _ => default,
    }
}
