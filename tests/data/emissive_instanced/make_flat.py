"""Writes pointinstancer_flat.usda: pointinstancer.usda with its PointInstancer flattened by
usd-core (run with usd-core's python: `python make_flat.py`).

Each instance becomes an Xform /World/Flat/I<i> whose xformOp:transform is usd-core's
ComputeInstanceTransformsAtTime matrix for it (written with 17 significant digits, so it reads
back bit for bit), holding a copy of its prototype's prims; the instancer's material binding
moves to the copies that have none, and the Key light's links name the copies. Instances stay
in protoIndices order, so the emissive copies are the lights in the order the renderer gives
the instances' lights.
"""

import os
from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.join(HERE, "pointinstancer.usda")
DST = os.path.join(HERE, "pointinstancer_flat.usda")


def main():
    stage = Usd.Stage.Open(SRC)
    layer = stage.GetRootLayer()
    pi = UsdGeom.PointInstancer(stage.GetPrimAtPath("/World/Cards"))
    t = Usd.TimeCode.Default()
    xforms = pi.ComputeInstanceTransformsAtTime(t, t)
    world = UsdGeom.Xformable(pi.GetPrim()).ComputeLocalToWorldTransform(t)
    protos = pi.GetPrototypesRel().GetTargets()
    indices = pi.GetProtoIndicesAttr().Get()
    binding = UsdShade.MaterialBindingAPI(pi.GetPrim()).GetDirectBinding().GetMaterialPath()

    out = Sdf.Layer.CreateAnonymous(".usda")
    out.pseudoRoot.SetInfo("metersPerUnit", 1.0)
    out.pseudoRoot.SetInfo("upAxis", "Y")
    out.documentation = (
        "pointinstancer.usda with its PointInstancer flattened by usd-core (make_flat.py): "
        "written by a script, do not edit."
    )
    Sdf.CreatePrimInLayer(out, "/World").specifier = Sdf.SpecifierDef
    out.GetPrimAtPath("/World").typeName = "Xform"
    for name in ["Looks", "Floor", "Key"]:
        Sdf.CopySpec(layer, "/World/" + name, out, "/World/" + name)
    flat = Sdf.CreatePrimInLayer(out, "/World/Flat")
    flat.specifier = Sdf.SpecifierDef
    flat.typeName = "Xform"
    copies = {}
    for i, (m, k) in enumerate(zip(xforms, indices)):
        path = "/World/Flat/I%d" % i
        x = Sdf.CreatePrimInLayer(out, path)
        x.specifier = Sdf.SpecifierDef
        x.typeName = "Xform"
        op = Sdf.AttributeSpec(x, "xformOp:transform", Sdf.ValueTypeNames.Matrix4d)
        op.default = Gf.Matrix4d(m * world)
        order = Sdf.AttributeSpec(x, "xformOpOrder", Sdf.ValueTypeNames.TokenArray,
                                  variability=Sdf.VariabilityUniform)
        order.default = ["xformOp:transform"]
        proto = protos[k]
        name = proto.name
        Sdf.CopySpec(layer, proto, out, path + "/" + name)
        copies.setdefault(str(proto), []).append(path + "/" + name)
    # The instancer's binding applies to prototype prims without one of their own.
    for p in out.GetPrimAtPath("/World/Flat").nameChildren:
        for c in p.nameChildren:
            def bind(spec):
                if spec.typeName in ("Mesh", "Cube") and "material:binding" not in spec.relationships:
                    spec.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=["MaterialBindingAPI"]))
                    r = Sdf.RelationshipSpec(spec, "material:binding", custom=False)
                    r.targetPathList.explicitItems = [binding]
                for g in spec.nameChildren:
                    bind(g)
            bind(c)
    key = out.GetPrimAtPath("/World/Key")
    def relink(rel):
        r = key.relationships[rel]
        items = []
        for target in r.targetPathList.prependedItems:
            s = str(target)
            for proto, paths in copies.items():
                if s == proto or s.startswith(proto + "/"):
                    items += [Sdf.Path(p + s[len(proto):]) for p in paths]
        r.targetPathList.ClearEdits()
        r.targetPathList.prependedItems = items
    relink("collection:lightLink:excludes")
    relink("collection:shadowLink:excludes")
    Sdf.CopySpec(layer, "/World/Camera", out, "/World/Camera")
    text = out.ExportToString()
    with open(DST, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
