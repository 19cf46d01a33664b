#!/usr/bin/env python3
"""Mitsuba ground truth of one stage frame, as race.py makes it, without the lux runs.

  make_gt.py STAGE FRAME OUT.exr [--spp 2048] [--res W] [--path DEPTH]

Two halves of spp/2 (ldsampler, the direct integrator with light sampling only, lights hidden from the
camera; --path D: Mitsuba `path` with max_depth D+1, independent sampler), their mean written to OUT.exr and
{"spp", "sigma" (the halves' RMSE / 2: the GT's own noise), "seconds"} to OUT.exr.json. --res W renders a
W x W (or the stage's aspect) picture instead of the stage's resolution, for quick experiments.
"""
import argparse, json, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_mitsuba as pm  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("stage"); ap.add_argument("frame", type=int); ap.add_argument("out")
    ap.add_argument("--spp", type=int, default=2048); ap.add_argument("--res", type=int)
    ap.add_argument("--path", type=int, help="path tracing depth (lux's counting)")
    a = ap.parse_args()
    desc = pm.extract_scene(a.stage, a.frame)
    if a.res:
        w, h = desc["resolution"]
        desc["resolution"] = (a.res, max(1, round(a.res * h / w)))
    pm.set_variant("scalar_rgb")
    if a.path:
        sc = pm.build_mitsuba_scene(desc, 16, 1, 1, 0, sampler="independent",
                                    integrator={"type": "path", "max_depth": a.path + 1, "hide_emitters": True})
    else:
        sc = pm.build_mitsuba_scene(desc, 16, 1, 1, 0, sampler="ldsampler")
    half = a.spp // 2
    h1, t1 = pm.render(sc, half, 100003)
    h2, t2 = pm.render(sc, half, 200003)
    gt = 0.5 * (h1 + h2); sig = pm._rmse(h1, h2) / 2
    pm.write_exr_rgb(a.out, gt)
    json.dump(dict(spp=2 * half, sigma=sig, seconds=t1 + t2, stage=os.path.abspath(a.stage),
                   resolution=list(desc["resolution"]), path_depth=a.path), open(a.out + ".json", "w"))
    print(f"ground truth {a.out}: {2 * half} spp in {t1 + t2:.1f} s, noise {sig:.6f}")


if __name__ == "__main__":
    main()
