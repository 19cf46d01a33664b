#!/usr/bin/env python3
"""One Cycles render of a stage compared with a Mitsuba ground truth: the experiments behind CYCLES.md.

  cycles_probe.py STAGE FRAME --gt GT.exr [--res 256] [--spp 256] [--fixes lights,cylinder,...|none|all]
                  [--bounces 0] [--show-lights] [--pixel-shift DX,DY] [--out DIR] [--tag NAME]

Run with the bpy venv. Renders two halves of --spp (seeds 1, 2: Cycles' own noise), compares their mean with the
ground truth box-downsampled to the render's resolution (exact for a box pixel filter) and prints
picture_check()'s numbers; writes DIR/TAG.exr and DIR/TAG.json.
"""
import argparse, json, os, sys, time
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_cycles as pc  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("stage"); ap.add_argument("frame", type=int); ap.add_argument("--gt", required=True)
    ap.add_argument("--res", type=int, default=256); ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--fixes", default="all"); ap.add_argument("--bounces", type=int, default=0)
    ap.add_argument("--show-lights", action="store_true"); ap.add_argument("--pixel-shift")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="/tmp/cycles_probe"); ap.add_argument("--tag", default="probe")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    gt = pc.read_rgb(a.gt); sig_gt = json.load(open(a.gt + ".json"))["sigma"]
    H, W = gt.shape[:2]
    k = W // a.res
    w, h = W // k, H // k
    fixes = pc.FIXES if a.fixes == "all" else () if a.fixes == "none" else tuple(a.fixes.split(","))
    shift = tuple(float(x) for x in a.pixel_shift.split(",")) if a.pixel_shift else None
    sc = pc.setup(a.stage, a.frame, w, h, a.threads, assist=a.fixes != "none", hide_lights=not a.show_lights,
                  bounces=a.bounces, fixes=fixes, pixel_shift=shift)
    t = time.perf_counter()
    h1, _ = pc.render(sc, a.spp // 2, 1, os.path.join(a.out, a.tag + ".h1.exr"))
    h2, _ = pc.render(sc, a.spp // 2, 2, os.path.join(a.out, a.tag + ".h2.exr"))
    secs = time.perf_counter() - t
    img = 0.5 * (h1 + h2); sig_c = pc.rmse(h1, h2) / 2
    pc.write_rgb(os.path.join(a.out, a.tag + ".exr"), img)
    gtk = pc.downsample(gt, k); sig_gtk = sig_gt / k  # the GT's pixel noise averages down over k*k pixels
    res = pc.picture_check(img, gtk, sig_c, sig_gtk)
    res.update(stage=a.stage, res=[w, h], spp=a.spp, fixes=list(fixes), seconds=secs, bounces=a.bounces)
    print(f"{a.tag}: {w}x{h} {a.spp} spp {secs:.1f} s; " + pc.format_check(res))
    json.dump(res, open(os.path.join(a.out, a.tag + ".json"), "w"), indent=1)


if __name__ == "__main__":
    main()
