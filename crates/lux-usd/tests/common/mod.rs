//! Helpers shared by lux-usd's integration tests.

/// Each mesh of `scene` with its bound material's path (`"None"` when unbound), in scene order:
/// what usd-core's `ComputeBoundMaterial` tables list.
pub fn bound_materials(scene: &lux_usd::Scene) -> Vec<(String, String)> {
    scene
        .meshes
        .iter()
        .map(|m| {
            let mat = m
                .material
                .map(|i| scene.materials[i].path.clone())
                .unwrap_or_else(|| "None".into());
            (m.path.clone(), mat)
        })
        .collect()
}

/// A (mesh, material) table as owned strings.
pub fn listed(table: &[(&str, &str)]) -> Vec<(String, String)> {
    table
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}
