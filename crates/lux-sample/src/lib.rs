//! Importance sampling for UsdLux lights: per-shape samplers, environment maps, light selection.
