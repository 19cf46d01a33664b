"""The oracle of `crates/lux-usd/tests/subdiv.rs`: Blender's subdivision surface modifier
(OpenSubdiv, C++) at its limit surface, for a few control cages.

Run with the `bpy` package from PyPI (Blender 5.0.1 was used):

    python blender_limit.py > blender_limit.json

For each cage: the cage as lux reads it from USD (points, faces, creases and corners with
their USD sharpness, interpolateBoundary, subdivisionScheme), the level, and the vertex
positions of Blender's evaluated mesh (`use_limit_surface`, `quality` 10: limit points exact
up to OpenSubdiv's isolation limit). Blender takes creases as a weight c in [0, 1] whose
OpenSubdiv sharpness is 10 c^2 (`BKE_subdiv_crease_to_sharpness_f`): the script authors
c = sqrt(s / 10) for a USD sharpness s.

Not an oracle of the bilinear scheme: Blender's "Simple" subdivision places the interior points
of n-gons elsewhere than OpenSubdiv's bilinear refinement (by 0.8-1.5 % of the face's size);
lux's test of the bilinear scheme holds it to its closed form instead.
"""

import json
import math
import sys

import bpy

CUBE_POINTS = [(-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1),
               (-1, -1, -1), (1, -1, -1)]
CUBE_FACES = [(0, 1, 3, 2), (2, 3, 5, 4), (4, 5, 7, 6), (6, 7, 1, 0), (1, 7, 5, 3), (6, 0, 2, 4)]


def cylinder(sides=7, r=1.0, h=2.0):
    """A closed prism: `sides` quads around, an n-gon at each end (n-gons, valence-3 rims)."""
    pts = []
    for z in (-h / 2, h / 2):
        for k in range(sides):
            a = 2 * math.pi * k / sides
            pts.append((r * math.cos(a), r * math.sin(a), z))
    faces = []
    for k in range(sides):
        k1 = (k + 1) % sides
        faces.append((k, k1, sides + k1, sides + k))
    faces.append(tuple(reversed(range(sides))))
    faces.append(tuple(range(sides, 2 * sides)))
    return pts, faces


def open_patch():
    """An open sheet of quads, a pentagon and two triangles (boundaries, n-gons, triangles)."""
    pts = [(0, 0, 0), (1, 0, 0.2), (2, 0, 0), (3, 0, 0.1),
           (0, 1, 0.1), (1, 1, 0.5), (2, 1, 0.3), (3, 1, 0),
           (0, 2, 0), (1, 2, 0.2), (2, 2.3, 0.4), (3, 2, 0), (1.5, 3, 0.2)]
    faces = [(0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (4, 5, 9, 8),
             (5, 6, 10, 12, 9), (6, 7, 11), (6, 11, 10)]
    return pts, faces


CYL_PTS, CYL_FACES = cylinder()
PATCH_PTS, PATCH_FACES = open_patch()

CAGES = [
    dict(name="cube", points=CUBE_POINTS, faces=CUBE_FACES, level=2),
    dict(name="cube_creases", points=CUBE_POINTS, faces=CUBE_FACES, level=3,
         creases=[((0, 1), 2.0), ((1, 3), 2.0), ((3, 2), 2.0), ((2, 0), 2.0), ((1, 7), 10.0)],
         corners=[(5, 3.0)]),
    dict(name="cylinder", points=CYL_PTS, faces=CYL_FACES, level=3,
         creases=[((CYL_FACES[-1][k], CYL_FACES[-1][(k + 1) % 7]), 1.5) for k in range(7)]),
    dict(name="open_edge_and_corner", points=PATCH_PTS, faces=PATCH_FACES, level=2,
         boundary="edgeAndCorner"),
    dict(name="open_edge_only", points=PATCH_PTS, faces=PATCH_FACES, level=2,
         boundary="edgeOnly"),
]


def evaluate(cage):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    mesh = bpy.data.meshes.new(cage["name"])
    mesh.from_pydata([tuple(map(float, p)) for p in cage["points"]], [], cage["faces"])
    mesh.update()
    if cage.get("creases"):
        attr = mesh.attributes.new("crease_edge", "FLOAT", "EDGE")
        index = {tuple(sorted(e.vertices)): e.index for e in mesh.edges}
        for (a, b), s in cage["creases"]:
            attr.data[index[tuple(sorted((a, b)))]].value = math.sqrt(min(s, 10.0) / 10.0)
    if cage.get("corners"):
        attr = mesh.attributes.new("crease_vert", "FLOAT", "POINT")
        for v, s in cage["corners"]:
            attr.data[v].value = math.sqrt(min(s, 10.0) / 10.0)
    obj = bpy.data.objects.new(cage["name"], mesh)
    bpy.context.scene.collection.objects.link(obj)
    mod = obj.modifiers.new("subdiv", "SUBSURF")
    mod.subdivision_type = "SIMPLE" if cage.get("scheme") == "bilinear" else "CATMULL_CLARK"
    mod.levels = mod.render_levels = cage["level"]
    mod.use_limit_surface = True
    mod.quality = 10
    mod.use_creases = True
    mod.boundary_smooth = "ALL" if cage.get("boundary") == "edgeOnly" else "PRESERVE_CORNERS"
    dg = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(dg).to_mesh()
    return [[round(c, 7) for c in v.co] for v in ev.vertices]


out = []
for cage in CAGES:
    out.append({
        "name": cage["name"],
        "scheme": cage.get("scheme", "catmullClark"),
        "boundary": cage.get("boundary", "edgeAndCorner"),
        "level": cage["level"],
        "points": [list(map(float, p)) for p in cage["points"]],
        "faces": [list(f) for f in cage["faces"]],
        "creases": [[a, b, s] for (a, b), s in cage.get("creases", [])],
        "corners": [[v, s] for v, s in cage.get("corners", [])],
        "blender": evaluate(cage),
    })
json.dump({"blender": bpy.app.version_string, "cages": out}, sys.stdout, separators=(",", ":"))
