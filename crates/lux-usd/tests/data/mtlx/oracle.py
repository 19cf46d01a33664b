#!/usr/bin/env python3
"""Writes oracle.json: what MaterialX itself reads from lux-usd's embedded library and the test
documents here. Run with the PyPI `materialx` bindings (the committed oracle: MaterialX 1.39.5):

    python oracle.py          # from this folder; rewrites oracle.json

- `nodedefs`: every nodedef of the five embedded files (`../../../data/materialx/`): its node,
  active inputs (inherited ones included; name, type, default value as numbers/string, or null,
  defaultgeomprop, uniform), active outputs and the nodegraph implementing it, if any;
- `resolve`: for every node of the test documents and of the library's implementation graphs,
  the nodedef MaterialX finds for it (`Node.getNodeDef()`), with the node's category, type and
  authored (input, type) pairs;
- `upgraded`: the 1.39 form of `upgrade_138.mtlx` as MaterialX writes it (nodes per nodegraph).
"""

import json
import os

import MaterialX as mx

HERE = os.path.dirname(os.path.abspath(__file__))
LIB = os.path.join(HERE, "..", "..", "..", "data", "materialx")
FILES = ["stdlib_defs", "pbrlib_defs", "standard_surface", "open_pbr_surface", "usd_preview_surface"]
DOCS = sorted(f for f in os.listdir(HERE) if f.endswith(".mtlx"))


def load_library():
    lib = mx.createDocument()
    for f in FILES:
        mx.readFromXmlFile(lib, os.path.join(LIB, f + ".mtlx"))
    return lib


def value(port):
    if not port.hasValueString() and port.getType() not in ("string", "filename"):
        return None
    t = port.getType()
    v = port.getValue()
    if v is None:
        return None
    if t in ("string", "filename"):
        return v
    if isinstance(v, str):
        return None  # closures and shaders: no value
    if t in ("float", "integer"):
        return [float(v)]
    if t == "boolean":
        return [1.0 if v else 0.0]
    if t in ("matrix33", "matrix44"):
        n = 3 if t == "matrix33" else 4
        return [float(v[i, j]) for i in range(n) for j in range(n)]
    return [float(x) for x in v.asTuple()]


def nodedefs(lib):
    out = {}
    for nd in lib.getNodeDefs():
        impl = nd.getImplementation()
        out[nd.getName()] = {
            "node": nd.getNodeString(),
            "inputs": [
                {
                    "name": i.getName(),
                    "type": i.getType(),
                    "value": value(i),
                    "defaultgeomprop": i.getDefaultGeomPropString() or None,
                    "uniform": i.getIsUniform(),
                }
                for i in nd.getActiveInputs()
            ],
            "outputs": [[o.getName(), o.getType()] for o in nd.getActiveOutputs()],
            "implementation": impl.getName() if impl is not None and impl.isA(mx.NodeGraph) else None,
        }
    return out


def node_record(where, node):
    nd = node.getNodeDef()
    return {
        "where": where,
        "name": node.getName(),
        "category": node.getCategory(),
        "type": node.getType(),
        "inputs": [[i.getName(), i.getType()] for i in node.getInputs()],
        "nodedef": nd.getName() if nd is not None else None,
    }


def resolve(lib):
    out = []
    for f in DOCS:
        doc = mx.createDocument()
        mx.readFromXmlFile(doc, os.path.join(HERE, f))
        doc.importLibrary(lib)
        for node in doc.getNodes():
            out.append(node_record(f, node))
        for g in doc.getNodeGraphs():
            if g.hasSourceUri():
                continue
            for node in g.getNodes():
                out.append(node_record(f + ":" + g.getName(), node))
    for g in lib.getNodeGraphs():
        for node in g.getNodes():
            out.append(node_record("library:" + g.getName(), node))
    return out


def upgraded():
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, os.path.join(HERE, "upgrade_138.mtlx"))
    graphs = {}
    for g in doc.getNodeGraphs():
        graphs[g.getName()] = [
            {
                "name": n.getName(),
                "category": n.getCategory(),
                "type": n.getType(),
                "inputs": [
                    {
                        "name": i.getName(),
                        "value": i.getValueString() or None,
                        "nodename": i.getNodeName() or None,
                        "output": i.getOutputString() or None,
                        "interfacename": i.getInterfaceName() or None,
                    }
                    for i in n.getInputs()
                ],
            }
            for n in g.getNodes()
        ]
    return {"version": doc.getVersionString(), "nodegraphs": graphs}


def main():
    lib = load_library()
    data = {
        "materialx": mx.getVersionString(),
        "nodedefs": nodedefs(lib),
        "resolve": resolve(lib),
        "upgraded": upgraded(),
    }
    with open(os.path.join(HERE, "oracle.json"), "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
