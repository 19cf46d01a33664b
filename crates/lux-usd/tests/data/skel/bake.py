#!/usr/bin/env python3
"""Writes oracle.json: what lux-usd must reproduce when it poses these skinned stages.

Run with usd-core (`pip install usd-core`; the committed oracle was written by usd-core 26.11):

    python bake.py            # from this folder; rewrites oracle.json

For each (stage, time) below, the stage is opened, `primvars:normals` are copied to `normals`
in the session layer (UsdSkel.BakeSkinning skins only the `normals` attribute; lux skins the
normals it draws, `primvars:normals` first), every time-sampled attribute is held at its value at
that time (a session-layer sample), and UsdSkel.BakeSkinning poses every skinned prim over
[time, time] into the session layer: the files on disk stay untouched. Then, for every drawn gprim (Mesh and
implicit surfaces; lux does not draw curves):

- Mesh: the world-space points `UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time)` ×
  baked points, and where normals are authored the world-space normals (baked normals through
  the inverse transpose of that transform, normalised), with their interpolation and the
  face-vertex counts and indices they are laid out by;
- implicit surface: its world transform after baking (UsdSkel poses these rigidly, as a
  transform) and the attributes lux tessellates it from;
- whether BakeSkinning wrote anything for it (`posed`).

And the world box of the drawn gprims (`UsdGeom.BBoxCache`, default and render purposes).
"""

import json
import math
import os

from pxr import Gf, Usd, UsdGeom, UsdSkel

HERE = os.path.dirname(os.path.abspath(__file__))

CASES = [
    ("usdwg/test_assets/USDZ/RiggedSimple/RiggedSimple.usdz", [1, 25.5, 50]),
    ("usdwg/test_assets/USDZ/RiggedFigure/RiggedFigure.usdz", [0, 12.5, 30]),
    ("openusd/pxr/usd/usdSkel/testenv/testUsdSkelBakeSkinning/lbs.usda", [1, 15.5, 30]),
    (
        "openusd/pxr/usd/usdSkel/testenv/testUsdSkelBakeSkinning/blendshapes.usda",
        [6, 8.5, 11, 16, 21, 31, 41, 51, 61, 71, 86, 91, 94, 100, 106, 111, 126, 131],
    ),
    ("openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdSkel/arm.usda", [1, 5.5, 10]),
    ("Autodesk-maya-usd/test/lib/usd/translators/UsdImportSkeleton/skelCube.usda", [1, 15, 30]),
    ("lux/skel_cases.usda", [1, 5.5, 10]),
]

IMPLICIT = {
    "Sphere": ["radius"],
    "Cube": ["size"],
    "Cylinder": ["radius", "height", "axis"],
    "Cone": ["radius", "height", "axis"],
    "Capsule": ["radius", "height", "axis"],
    "Plane": ["width", "length", "axis"],
}


def r(x):
    """Rounds to 9 significant digits (usd-core computes points in float)."""
    return float("%.9g" % x)


def vec(v):
    return [r(c) for c in v]


def drawn(prim, time):
    img = UsdGeom.Imageable(prim)
    return img.ComputeVisibility(time) != UsdGeom.Tokens.invisible and img.ComputePurpose() in (
        UsdGeom.Tokens.default_,
        UsdGeom.Tokens.render,
    )


def session_values(layer):
    """Per prim path, what the session layer holds for it (to tell what BakeSkinning wrote)."""
    out = {}

    def visit(spec_path):
        spec = layer.GetPrimAtPath(spec_path)
        if spec.properties:
            out[str(spec_path)] = {
                prop.name: (
                    repr(getattr(prop, "default", None)),
                    repr(layer.ListTimeSamplesForPath(prop.path)),
                    repr([layer.QueryTimeSample(prop.path, t)
                          for t in layer.ListTimeSamplesForPath(prop.path)]),
                )
                for prop in spec.properties
            }

    layer.Traverse("/", lambda p: visit(p) if p.IsPrimPath() else None)
    return out


def case(path, time):
    stage = Usd.Stage.Open(os.path.join(HERE, path))
    session = stage.GetSessionLayer()
    stage.SetEditTarget(session)
    for prim in stage.Traverse():
        if prim.IsA(UsdGeom.Mesh):
            pv = UsdGeom.PrimvarsAPI(prim).GetPrimvar("normals")
            if pv and pv.HasAuthoredValue():
                mesh = UsdGeom.Mesh(prim)
                mesh.GetNormalsAttr().Set(pv.ComputeFlattened(time))
                mesh.SetNormalsInterpolation(pv.GetInterpolation())
    # Every time-sampled attribute gets one session-layer sample at `time` holding its value
    # there, so that BakeSkinning, baking over [time, time], poses exactly at `time` (over its
    # default interval it bakes at the stage's sample times, and a time between two of them
    # would read the baked points interpolated linearly between two poses).
    for prim in stage.TraverseAll():
        for attr in prim.GetAttributes():
            if attr.GetNumTimeSamples() > 0:
                attr.Set(attr.Get(time), time)
    before = session_values(session)
    assert UsdSkel.BakeSkinning(stage.Traverse(), Gf.Interval(time, time))
    after = session_values(session)
    gprims = []
    box = Gf.Range3d()
    bbox = UsdGeom.BBoxCache(time, [UsdGeom.Tokens.default_, UsdGeom.Tokens.render])
    for prim in stage.Traverse():
        kind = prim.GetTypeName()
        if not (kind in ("Mesh", "BasisCurves") or kind in IMPLICIT) or not drawn(prim, time):
            continue
        if kind != "BasisCurves":
            # Curves are left out of the box: usd-core's extent pads their unauthored widths
            # by 0, where renderers draw them 1 wide (Hydra's fallback), as lux does.
            box.UnionWith(bbox.ComputeWorldBound(prim).ComputeAlignedRange())
        l2w = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time)
        prim_path = str(prim.GetPath())
        g = {
            "path": prim_path,
            "type": kind,
            "posed": before.get(prim_path) != after.get(prim_path),
        }
        if kind == "BasisCurves":
            curves = UsdGeom.BasisCurves(prim)
            g["points"] = [vec(l2w.Transform(Gf.Vec3d(p))) for p in curves.GetPointsAttr().Get(time)]
            g["curve_vertex_counts"] = list(curves.GetCurveVertexCountsAttr().Get(time))
        elif kind == "Mesh":
            mesh = UsdGeom.Mesh(prim)
            g["points"] = [vec(l2w.Transform(Gf.Vec3d(p))) for p in mesh.GetPointsAttr().Get(time)]
            g["face_vertex_counts"] = list(mesh.GetFaceVertexCountsAttr().Get(time))
            g["face_vertex_indices"] = list(mesh.GetFaceVertexIndicesAttr().Get(time))
            normals = mesh.GetNormalsAttr().Get(time)
            if normals is not None and len(normals) > 0:
                inv = l2w.ExtractRotationMatrix().GetInverse()
                values = []
                for n in normals:
                    w = inv * Gf.Vec3d(n)  # M₃⁻¹ · n (column) = n · M₃⁻ᵀ (USD row vector)
                    length = math.sqrt(w * w) or 1.0
                    values.append(vec(w / length))
                g["normals"] = {"interpolation": mesh.GetNormalsInterpolation(), "values": values}
        else:
            g["local_to_world"] = [r(l2w[i][j]) for i in range(4) for j in range(4)]
            attrs = {}
            for name in IMPLICIT[kind]:
                v = prim.GetAttribute(name).Get(time)
                attrs[name] = v if isinstance(v, str) else r(v)
            g["attributes"] = attrs
        gprims.append(g)
    return {
        "file": path,
        "time": time,
        "drawn_box": [vec(box.GetMin()), vec(box.GetMax())],
        "gprims": gprims,
    }


def main():
    cases = [case(path, t) for path, times in CASES for t in times]
    out = {
        "generator": "usd-core %s, UsdSkel.BakeSkinning, via bake.py" % ".".join(
            str(v) for v in Usd.GetVersion()
        ),
        "cases": cases,
    }
    with open(os.path.join(HERE, "oracle.json"), "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
