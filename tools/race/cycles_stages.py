#!/usr/bin/env python3
"""The small stages behind CYCLES.md's experiments.

  cycles_stages.py OUTDIR [--clutter DIR]

OUTDIR/edge.usda   a floor under a distant light whose edges fall at column 70.25 and row 40.6 of the 128² image
                   (pixel centre and filter: read the edge pixels' coverage in each renderer's image);
OUTDIR/back.usda   the same floor with its winding reversed, lit from behind (one-sided receivers: black);
OUTDIR/<scene>_<light>.usda   with --clutter DIR (make_scenes.py output): each clutter_mix light alone, and
                   clutter_many's lights l10 and l25 alone, over the same clutter at 256² (units and shapes per light).
"""
import argparse, os, re, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import stage_head  # noqa: E402

HALF = 30 * 0.20955  # half the image width on the floor: make_scenes' camera 30 units up, tan(fov/2) = 0.20955
EDGE = """def Mesh "floor"
{{
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = {idx}
    point3f[] points = [(-9, 0, {ez:.6f}), ({ex:.6f}, 0, {ez:.6f}), ({ex:.6f}, 0, 9), (-9, 0, 9)]
    color3f[] primvars:displayColor = [(0.5, 0.5, 0.5)]
}}
def DistantLight "sun"
{{
    float inputs:angle = 0
    float inputs:intensity = 2
    matrix4d xformOp:transform = ( (1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 5, 0, 1) )
    uniform token[] xformOpOrder = ["xformOp:transform"]
}}
"""


def split_lights(src, keep, res):
    head, lights = src.split('def Xform "lights"\n{\n')
    blocks = [b for b in re.split(r'(?=    def \w+Light ")', lights.rstrip().rstrip("}")) if b.strip()]
    head = head.replace("int2 resolution = (512, 512)", f"int2 resolution = ({res}, {res})")
    for b in blocks:
        name = re.search(r'def \w+Light "(\w+)"', b).group(1)
        if keep is None or name in keep:
            yield name, head + 'def Xform "lights"\n{\n' + b + "}\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out"); ap.add_argument("--clutter")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    ex = (70.25 - 64) / 64 * HALF  # column 70.25 of 128
    ez = -(64 - 40.6) / 64 * HALF  # row 40.6 from the top (image up = world -Z)
    open(os.path.join(a.out, "edge.usda"), "w").write(stage_head(128) + EDGE.format(idx="[0, 3, 2, 1]", ex=ex, ez=ez))
    open(os.path.join(a.out, "back.usda"), "w").write(stage_head(128) + EDGE.format(idx="[0, 1, 2, 3]", ex=ex, ez=ez))
    if a.clutter:
        for scene, keep, res in (("clutter_mix", None, 128), ("clutter_many", ("l10", "l25"), 256)):
            for name, text in split_lights(open(os.path.join(a.clutter, scene + ".usda")).read(), keep, res):
                open(os.path.join(a.out, f"{scene}_{name}.usda"), "w").write(text)
    print("\n".join(sorted(os.listdir(a.out))))


if __name__ == "__main__":
    main()
