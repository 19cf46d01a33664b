//! UsdLux ShapingAPI: focus, focusTint, cone angle and softness, IES angleScale and normalize.
