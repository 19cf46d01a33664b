//! UsdLux size factors (normalize), emission units, colour temperature, conformance profiles and shared light-space math.
