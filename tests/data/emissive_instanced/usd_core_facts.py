"""What usd-core composes from the stages here, written to usd_core_facts.json for
tests/render_emissive_instanced.rs (run with usd-core's python: `python usd_core_facts.py`).

Per stage: the native instances and the prototype each draws, the PointInstancer instance
count, and every emitter (a drawn mesh whose bound UsdPreviewSurface has a non-black
emissiveColor, instance proxies and point instances included): its path, emission, world
corners in authored order, doubleSided, and its front normal in the world
(sign(det M) * (b - a) x (c - a) for the rightHanded orientation).
"""

import json
import os
from pxr import Gf, Usd, UsdGeom, UsdShade

HERE = os.path.dirname(os.path.abspath(__file__))
T = Usd.TimeCode.Default()


def emission(prim, inherited=None):
    mat = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0]
    if not mat:
        mat = inherited
    if not mat:
        return None
    shader = mat.ComputeSurfaceSource()[0]
    if not shader:
        return None
    e = shader.GetInput("emissiveColor")
    v = e.Get() if e else None
    if v is None or max(v) <= 0:
        return None
    return [float(c) for c in v]


def emitter(path, mesh, m, e):
    pts = [m.Transform(Gf.Vec3d(p)) for p in mesh.GetPointsAttr().Get(T)]
    det = m.ExtractRotationMatrix().GetDeterminant()
    a, b, c = pts[0], pts[1], pts[2]
    n = Gf.Cross(b - a, c - a)
    if mesh.GetOrientationAttr().Get(T) == "leftHanded":
        n = -n
    if det < 0:
        n = -n
    n = n.GetNormalized()
    return {
        "path": path,
        "emissive": e,
        "corners": [[p[0], p[1], p[2]] for p in pts],
        "double_sided": bool(mesh.GetDoubleSidedAttr().Get(T)),
        "front": [n[0], n[1], n[2]],
    }


def facts(name):
    stage = Usd.Stage.Open(os.path.join(HERE, name))
    out = {"native_instances": [], "prototypes": [], "point_instances": 0, "emitters": []}
    out["prototypes"] = [str(p.GetPath()) for p in stage.GetPrototypes()]
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if prim.IsInstance():
            out["native_instances"].append([str(prim.GetPath()), str(prim.GetPrototype().GetPath())])
        if prim.IsA(UsdGeom.PointInstancer):
            pi = UsdGeom.PointInstancer(prim)
            xs = pi.ComputeInstanceTransformsAtTime(T, T)
            out["point_instances"] += len(xs)
            world = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(T)
            protos = pi.GetPrototypesRel().GetTargets()
            inherited = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0]
            for i, (x, k) in enumerate(zip(xs, pi.GetProtoIndicesAttr().Get(T))):
                root = stage.GetPrimAtPath(protos[k])
                for p in Usd.PrimRange(root):
                    if not p.IsA(UsdGeom.Mesh):
                        continue
                    e = emission(p, inherited)
                    if e is None:
                        continue
                    # Mesh → prototype root, then the instance transform (which includes the
                    # root's own transform), then the instancer's world transform.
                    cache = UsdGeom.XformCache(T)
                    rel = cache.ComputeRelativeTransform(p, root)[0]
                    m = rel * x * world
                    out["emitters"].append(emitter("%s[%d]%s" % (prim.GetPath(), i, p.GetPath()),
                                                   UsdGeom.Mesh(p), m, e))
        if prim.IsA(UsdGeom.Mesh) and not any(
            a.IsA(UsdGeom.PointInstancer) for a in iter_ancestors(prim)
        ):
            e = emission(prim)
            if e is not None:
                m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(T)
                out["emitters"].append(emitter(str(prim.GetPath()), UsdGeom.Mesh(prim), m, e))
    return out


def iter_ancestors(prim):
    p = prim.GetParent()
    while p and not p.IsPseudoRoot():
        yield p
        p = p.GetParent()


def main():
    result = {n: facts(n) for n in ["native.usda", "pointinstancer.usda", "pointinstancer_flat.usda"]}
    with open(os.path.join(HERE, "usd_core_facts.json"), "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
