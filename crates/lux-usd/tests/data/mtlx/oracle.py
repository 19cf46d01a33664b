#!/usr/bin/env python3
"""Writes oracle.json: what MaterialX itself reads from lux-usd's embedded library and the test
documents here. Run with the PyPI `materialx` bindings (the committed oracle: MaterialX 1.39.5):

    python oracle.py          # from this folder; rewrites oracle.json

- `nodedefs`: every nodedef of the five embedded files (`../../../data/materialx/`): its node,
  active inputs (inherited ones included; name, type, default value as numbers/string, or null,
  defaultgeomprop, uniform), active outputs and the nodegraph implementing it, if any;
- `resolve`: for every node of the test documents (but `UNRESOLVED`) and of the library's implementation graphs,
  the nodedef MaterialX finds for it (`Node.getNodeDef()`), with the node's category, type and
  authored (input, type) pairs and requested version;
- `upgraded`: for each `upgrade_*.mtlx`, its 1.39 form as MaterialX's `upgradeVersion` makes it
  on reading: the top-level nodes and each nodegraph's nodes and outputs (category, type,
  nodedef string; every input's type, value string and bindings).
"""

import json
import os

import MaterialX as mx

HERE = os.path.dirname(os.path.abspath(__file__))
LIB = os.path.join(HERE, "..", "..", "..", "data", "materialx")
FILES = ["stdlib_defs", "pbrlib_defs", "standard_surface", "open_pbr_surface", "usd_preview_surface"]
DOCS = sorted(f for f in os.listdir(HERE) if f.endswith(".mtlx") and f != "bad.mtlx")
# Documents whose upgraded nodes no nodedef matches, even in MaterialX: not `resolve` records.
UNRESOLVED = {"upgrade_138_unresolved.mtlx"}


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
            "outputs": [
                [o.getName(), o.getType(),
                 o.getAttribute("default") if o.hasAttribute("default") else None,
                 o.getAttribute("defaultinput") or None]
                for o in nd.getActiveOutputs()
            ],
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
        "version": node.getVersionString() or None,
        "inputs": [[i.getName(), i.getType()] for i in node.getInputs()],
        "nodedef": nd.getName() if nd is not None else None,
    }


def resolve(lib):
    out = []
    for f in DOCS:
        if f in UNRESOLVED:
            continue
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


UPGRADES = sorted(f for f in DOCS if f.startswith("upgrade_"))


def port_record(p):
    return {
        "name": p.getName(),
        "type": p.getType() or None,
        "value": p.getValueString() or None,
        "nodename": p.getNodeName() or None,
        "nodegraph": p.getNodeGraphString() or None,
        "output": p.getOutputString() or None,
        "interfacename": p.getInterfaceName() or None,
    }


def upgraded_node(n):
    return {
        "name": n.getName(),
        "category": n.getCategory(),
        "type": n.getType(),
        "nodedef": n.getNodeDefString() or None,
        "inputs": [port_record(i) for i in n.getInputs()],
    }


def upgraded(name):
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, os.path.join(HERE, name))
    return {
        "version": doc.getVersionString(),
        "nodes": [upgraded_node(n) for n in doc.getNodes()],
        "nodegraphs": {
            g.getName(): {
                "nodes": [upgraded_node(n) for n in g.getNodes()],
                "outputs": [port_record(o) for o in g.getOutputs()],
            }
            for g in doc.getNodeGraphs()
        },
    }


def main():
    lib = load_library()
    data = {
        "materialx": mx.getVersionString(),
        "nodedefs": nodedefs(lib),
        "resolve": resolve(lib),
        "upgraded": {f: upgraded(f) for f in UPGRADES},
    }
    with open(os.path.join(HERE, "oracle.json"), "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
