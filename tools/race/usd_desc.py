#!/usr/bin/env python3
"""Print peer_mitsuba.extract_scene(STAGE, FRAME) as JSON (lights, mesh names / sidedness / colours, camera):
what peer_cycles.py needs to correct Blender's USD importer. Runs in the lux-peer venv (usd-core);
peer_cycles.py runs in the bpy venv, which has no pxr module, and calls this through $LUX_PEER_PY.

  usd_desc.py STAGE FRAME [--points]     (--points keeps mesh points and triangles; default drops them)
"""
import json, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_mitsuba as pm  # noqa: E402


def main():
    path, frame = sys.argv[1], float(sys.argv[2])
    d = pm.extract_scene(path, frame)
    if "--points" not in sys.argv:
        for m in d["meshes"]:
            m.pop("points"); m.pop("tris")
    json.dump(d, sys.stdout, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))


if __name__ == "__main__":
    main()
