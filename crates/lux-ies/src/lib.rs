//! IES LM-63 photometric files: parse every edition, validate, write, expand symmetry, interpolate, integrate flux.
