//! Physical light units (lm, W, lux) and the UsdLux spectral API: illuminants, SPDs to RGB.
