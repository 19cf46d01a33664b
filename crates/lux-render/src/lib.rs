//! lux reference renderer: USD scene loading, BVH, direct-lighting integrators, EXR/PNG output.
