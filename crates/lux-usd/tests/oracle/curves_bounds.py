#!/usr/bin/env python3
"""curves_bounds.py -- usd-core's numbers for crates/lux-usd/tests/curves.rs.

Run from the workspace root with usd-core (26.11 when the test was written):

  ~/venv-usd/bin/python crates/lux-usd/tests/oracle/curves_bounds.py

For each stage below, every BasisCurves / NurbsCurves / Points prim usd-core draws (traversal with
instance proxies, purpose default/render, visible) is printed with its world bound: usd-core's
UsdGeom.BBoxCache at the stage's start time, with extentsHint off and with each gprim's own
`extent` computed by usd-core (UsdGeom.Boundable.ComputeExtentFromPlugins: the points' box
padded by half the largest width for curves, each point padded by its own half width for Points)
rather than read from the authored `extent` (the files' authored extents are stale: the Loop's
is padded by 1 for a width of 0.22). To make BBoxCache compute them, the authored extents are
blocked and instancing is turned off in the session layer (instance proxies cannot be edited;
the paths stay the instance-proxy paths lux reports).

Also printed per curves prim, from usd-core's points, widths and world transform:

- `ends`: the box of the points the curve passes through by definition (segment ends: every
  vstep-th vertex of a nonperiodic bezier curve, (P[i-1] + 4 P[i] + P[i+1]) / 6 for bspline),
  which lux's tube box must contain;
- `tube`: the box of the exact tube, from the UsdGeomBasisCurves formulas evaluated here
  (independently of lux) at 400 parameters per segment: the extreme of a circle of radius r
  perpendicular to the unit tangent T along axis e is C.e +- r sqrt(1 - (T.e)^2); the widths
  follow their interpolation (varying: linear per segment; vertex: the basis; one value:
  constant). Only for similarity transforms (the radius scales by det^(1/3));
- `rmax`: the largest world radius;
- the usd-core segment counts (UsdGeom.BasisCurves.ComputeSegmentCounts).
"""

import sys
from pxr import Gf, Sdf, Usd, UsdGeom

ROOT = "tests/data/realusd/openusd/pxr/usdImaging/usdImagingGL/testenv/"
FILES = [
    "testUsdImagingGLBasicLighting/basicDrawing.usda",
    "testUsdImagingGLInstancing/instance.usda",
    "testUsdImagingGLInstancing/nestedInstance.usda",
]
TYPES = ("BasisCurves", "NurbsCurves", "Points")


def segment_ends(prim, world):
    """World positions the curve passes through: the ends of every segment."""
    if not prim.IsA(UsdGeom.BasisCurves):
        return []
    c = UsdGeom.BasisCurves(prim)
    pts = c.GetPointsAttr().Get()
    counts = c.GetCurveVertexCountsAttr().Get()
    basis = c.GetBasisAttr().Get()
    wrap = c.GetWrapAttr().Get()
    kind = c.GetTypeAttr().Get()
    out = []
    start = 0
    for n in counts:
        p = [Gf.Vec3d(pts[start + i]) for i in range(n)]
        start += n
        if kind == "linear":
            out += p
        elif basis == "bezier" and wrap != "periodic":
            out += p[::3]
        elif basis == "bspline" and wrap == "periodic":
            out += [(p[i - 1] + 4 * p[i] + p[(i + 1) % n]) / 6 for i in range(n)]
        elif basis == "bspline":
            out += [(p[i - 1] + 4 * p[i] + p[i + 1]) / 6 for i in range(1, n - 1)]
    return [world.Transform(q) for q in out]


BASES = {
    "bezier": (3, lambda t: [(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t * t * (1 - t), t ** 3]),
    "bspline": (1, lambda t: [(1 - t) ** 3 / 6, (3 * t ** 3 - 6 * t * t + 4) / 6,
                              (-3 * t ** 3 + 3 * t * t + 3 * t + 1) / 6, t ** 3 / 6]),
    "catmullRom": (1, lambda t: [(-t ** 3 + 2 * t * t - t) / 2, (3 * t ** 3 - 5 * t * t + 2) / 2,
                                 (-3 * t ** 3 + 4 * t * t + t) / 2, (t ** 3 - t * t) / 2]),
}


def exact_tube(prim, world, t):
    """Box of the exact world-space tube of a BasisCurves prim, and its largest radius."""
    c = UsdGeom.BasisCurves(prim)
    m3 = Gf.Matrix3d(world.ExtractRotationMatrix())
    cols = [Gf.Vec3d(world[i][0], world[i][1], world[i][2]) for i in range(3)]
    lens = [v.GetLength() for v in cols]
    if max(lens) - min(lens) > 1e-9 * max(lens) or any(
        abs(cols[i] * cols[j]) > 1e-9 * lens[0] ** 2 for i in range(3) for j in range(i)
    ):
        return None
    scale = lens[0]
    pts = [Gf.Vec3d(p) for p in c.GetPointsAttr().Get(t)]
    counts = list(c.GetCurveVertexCountsAttr().Get(t))
    kind, basis, wrap = c.GetTypeAttr().Get(), c.GetBasisAttr().Get(), c.GetWrapAttr().Get()
    widths = list(c.GetWidthsAttr().Get(t) or [1.0])
    interp = c.GetWidthsInterpolation() if len(widths) > 1 else "constant"
    vstep, weights = BASES[basis] if kind == "cubic" else (1, lambda t: [1 - t, t])
    lo = Gf.Vec3d(float("inf"), float("inf"), float("inf"))
    hi = -lo
    rmax = 0.0
    start, vstart = 0, 0
    for ci, n in enumerate(counts):
        p = pts[start:start + n]
        w = widths[start:start + n] if interp == "vertex" else None
        if kind == "linear":
            segs = [[i, (i + 1) % n] for i in range(n if wrap == "periodic" else n - 1)]
        elif wrap == "periodic":
            segs = [[(i * vstep + k) % n for k in range(4)] for i in range(n // vstep)]
        elif wrap == "pinned" and basis != "bezier":
            p = [2 * p[0] - p[1]] + p + [2 * p[-1] - p[-2]]
            if w:
                w = [2 * w[0] - w[1]] + w + [2 * w[-1] - w[-2]]
            segs = [[i + k for k in range(4)] for i in range(n - 1)]
        else:
            segs = [[i * vstep + k for k in range(4)] for i in range((n - 4) // vstep + 1)]
        nvary = len(segs) if wrap == "periodic" else len(segs) + 1
        for s, idx in enumerate(segs):
            for j in range(401):
                u = j / 400
                b = weights(u)
                pos = sum((p[i] * b[k] for k, i in enumerate(idx)), Gf.Vec3d(0, 0, 0))
                e = 1e-6
                b2 = weights(min(u + e, 1.0))
                b1 = weights(max(u - e, 0.0))
                tan = sum((p[i] * (b2[k] - b1[k]) for k, i in enumerate(idx)), Gf.Vec3d(0, 0, 0))
                if interp == "constant":
                    width = widths[0]
                elif interp == "uniform":
                    width = widths[ci]
                elif interp == "varying":
                    a, z = widths[vstart + s], widths[vstart + (s + 1) % nvary]
                    width = a + (z - a) * u
                else:
                    width = sum(w[i] * b[k] for k, i in enumerate(idx))
                r = scale * width / 2
                rmax = max(rmax, r)
                pw = world.Transform(pos)
                tw = (m3 * tan).GetNormalized() if tan.GetLength() > 0 else Gf.Vec3d(1, 0, 0)
                for a in range(3):
                    ext = r * max(0.0, 1 - tw[a] ** 2) ** 0.5
                    lo[a] = min(lo[a], pw[a] - ext)
                    hi[a] = max(hi[a], pw[a] + ext)
        start += n
        vstart += nvary
    return lo, hi, rmax


def main():
    for rel in FILES:
        stage = Usd.Stage.Open(ROOT + rel)
        t = Usd.TimeCode(stage.GetStartTimeCode())
        with Usd.EditContext(stage, stage.GetSessionLayer()):
            for prim in stage.Traverse():
                if prim.IsInstance():
                    prim.SetInstanceable(False)
            for prim in stage.Traverse():
                if prim.GetTypeName() in TYPES:
                    prim.GetAttribute("extent").Block()
        cache = UsdGeom.BBoxCache(t, [UsdGeom.Tokens.default_, UsdGeom.Tokens.render], False)
        print(f"# {rel} at {t.GetValue()} (usd-core {Usd.GetVersion()})")
        for prim in Usd.PrimRange(stage.GetPseudoRoot()):
            if prim.GetTypeName() not in TYPES:
                continue
            img = UsdGeom.Imageable(prim)
            if img.ComputeVisibility(t) != UsdGeom.Tokens.inherited:
                continue
            if img.ComputePurpose() not in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render):
                continue
            box = cache.ComputeWorldBound(prim).ComputeAlignedRange()
            world = img.ComputeLocalToWorldTransform(t)
            ext = UsdGeom.Boundable.ComputeExtentFromPlugins(UsdGeom.Boundable(prim), t)
            lo, hi = box.GetMin(), box.GetMax()
            print(f'"{prim.GetPath()}" {prim.GetTypeName()}')
            print(f"  bbox  ({lo[0]!r}, {lo[1]!r}, {lo[2]!r}) ({hi[0]!r}, {hi[1]!r}, {hi[2]!r})")
            print(f"  local extent {list(ext)}")
            ends = segment_ends(prim, world)
            if ends:
                r = Gf.Range3d()
                for q in ends:
                    r.UnionWith(q)
                a, b = r.GetMin(), r.GetMax()
                print(f"  ends  ({a[0]!r}, {a[1]!r}, {a[2]!r}) ({b[0]!r}, {b[1]!r}, {b[2]!r})")
                c = UsdGeom.BasisCurves(prim)
                print(f"  segments {list(c.ComputeSegmentCounts(t))}")
                tube = exact_tube(prim, world, t)
                if tube:
                    a, b, rmax = tube
                    print(f"  tube  ({a[0]!r}, {a[1]!r}, {a[2]!r}) ({b[0]!r}, {b[1]!r}, {b[2]!r})")
                    print(f"  rmax  {rmax!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
