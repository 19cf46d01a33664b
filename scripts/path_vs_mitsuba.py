#!/usr/bin/env python3
"""path_vs_mitsuba.py -- lux's `path` integrator against Mitsuba 3's `path` integrator.

Run with the peer venv (tools/race/setup.sh makes it):

  PY=~/.cache/lux-peer/bin/python
  $PY scripts/path_vs_mitsuba.py compare --lux target/release/lux            # depths 1, 2, 8
  $PY scripts/path_vs_mitsuba.py race --lux target/release/lux [--gt GT.exr]  # time to equal RMSE
  $PY scripts/path_vs_mitsuba.py means --res 64 --spp 8192 --json tests/data/cornell/mitsuba_path_means.json

The scene (default tests/data/cornell/cornell.usda) is read by usd-core and rebuilt in Mitsuba by
the race peer (tools/race/peer_mitsuba.py: extract_scene, build_mitsuba_scene), with
integrator {"type": "path", "max_depth": D + 1, "hide_emitters": True}: lux's depth D counts lit
surface vertices (1 = direct lighting), Mitsuba's max_depth counts path segments including the
one to the emitter. Lights are hidden from the camera in both (lux's spec profile shows a
RectLight only with inputs:visibility:camera; Mitsuba >= 3.7.1 skips emitter shapes along camera
rays when hide_emitters is set). Box filter, the stage's resolution, the scalar_rgb variant.

compare: per depth, both renderers render the same spp in two halves of different seeds; the
table gives the image means (RGB), the relative difference lux/Mitsuba - 1 per channel with its
1-sigma noise (from the two halves: var(mean) = mean((h1 - h2)^2) / (4 N) for each renderer),
HDR-FLIP (mean, Mitsuba as reference; peer_mitsuba.flip_hdr) and RMSE. --json writes it all.

race: a Mitsuba `path` ground truth at depth 8 (two halves of --gt-spp; their difference gives its
own noise sigma, removed from every RMSE), then lux (timed as a whole process: load, BVH, render,
what a user waits for) and Mitsuba (mi.render alone, scene built: a lower bound for it, as race.py
does) at several spp; the time each needs to reach each target RMSE (race.fit: log-log
interpolation of noise against spp, time piecewise linear in spp). Targets: Mitsuba's own noise
at 16 spp and a third of it, unless --targets. Prints `race: lux/mitsuba(path) time ratio at T = R`.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
RACE_DIR = os.environ.get("LUX_RACE_DIR", os.path.join(REPO, "tools", "race"))
sys.path.insert(0, RACE_DIR)
import peer_mitsuba as pm  # noqa: E402
import race  # noqa: E402

DEFAULT_SCENE = os.path.join(REPO, "tests", "data", "cornell", "cornell.usda")


def mitsuba_integrator(depth: int) -> dict:
    """Mitsuba's path integrator for lux's --max-depth `depth` (race.py's)."""
    return race.mitsuba_path_integrator(depth)


def lux_render(lux, scene, depth, spp, out, seed, extra=()):
    """One lux process (spec profile, path integrator, Lambertian surfaces as the peer builds
    them; race.py's, at frame 1 as the peer reads the stage); (image, wall seconds, lux's own render s)."""
    img, wall, own, _ = race.lux_render(lux, scene, 1, spp, out, seed, extra, depth)
    return img, wall, own


def mean_rgb(img) -> np.ndarray:
    return np.asarray(img, dtype=np.float64).mean(axis=(0, 1))


def mean_se(h1, h2) -> np.ndarray:
    """1-sigma noise of the image mean of (h1 + h2)/2, per channel, from the two halves."""
    d = np.asarray(h1, dtype=np.float64) - np.asarray(h2, dtype=np.float64)
    n = d.shape[0] * d.shape[1]
    return np.sqrt((d * d).mean(axis=(0, 1)) / (4.0 * n))


def fmt3(v, f="{:.5f}"):
    return "(" + ", ".join(f.format(x) for x in v) + ")"


def cmd_compare(a):
    os.makedirs(a.out, exist_ok=True)
    desc = pm.extract_scene(a.scene, 1.0)
    pm.set_variant("scalar_rgb")
    print(pm.describe(desc))
    W, H = desc["resolution"]
    rows = []
    for depth in [int(x) for x in a.depths.split(",")]:
        mspp = a.spp
        lspp = a.lux_spp or a.spp
        sc = pm.build_mitsuba_scene(desc, mspp, a.seed, 1, 1, sampler=a.sampler,
                                    integrator=mitsuba_integrator(depth))
        m1, tm1 = pm.render(sc, mspp // 2, a.seed + 1)
        m2, tm2 = pm.render(sc, mspp // 2, a.seed + 2)
        mit = 0.5 * (m1 + m2)
        l1, tl1, rl1 = lux_render(a.lux, a.scene, depth, lspp // 2,
                                  os.path.join(a.out, f"lux.d{depth}.h1.exr"), a.seed + 1)
        l2, tl2, rl2 = lux_render(a.lux, a.scene, depth, lspp // 2,
                                  os.path.join(a.out, f"lux.d{depth}.h2.exr"), a.seed + 2)
        lux = 0.5 * (l1 + l2)
        pm.write_exr_rgb(os.path.join(a.out, f"mitsuba.d{depth}.spp{mspp}.exr"), mit)
        pm.write_exr_rgb(os.path.join(a.out, f"lux.d{depth}.spp{lspp}.exr"), lux)
        pm.write_preview(os.path.join(a.out, f"d{depth}.preview.png"),
                         [mit, lux, np.abs(lux - mit) * 4])
        mm, ml = mean_rgb(mit), mean_rgb(lux)
        sm, sl = mean_se(m1, m2), mean_se(l1, l2)
        rel = ml / mm - 1.0
        rel_se = np.sqrt((sl / mm) ** 2 + (ml * sm / mm ** 2) ** 2)
        r = dict(depth=depth, mitsuba_max_depth=depth + 1, mitsuba_spp=mspp, lux_spp=lspp,
                 resolution=[W, H], mean_mitsuba=mm.tolist(), mean_lux=ml.tolist(),
                 se_mitsuba=sm.tolist(), se_lux=sl.tolist(), rel_diff=rel.tolist(),
                 rel_diff_se=rel_se.tolist(), flip=pm.flip_hdr(mit, lux), rmse=pm._rmse(lux, mit),
                 mitsuba_s=tm1 + tm2, lux_wall_s=tl1 + tl2, lux_render_s=rl1 + rl2,
                 mitsuba_self_rmse=pm._rmse(m1, m2) / 2, lux_self_rmse=pm._rmse(l1, l2) / 2)
        rows.append(r)
        print(f"depth {depth} (mitsuba max_depth {depth + 1}): mitsuba {fmt3(mm)} ±{fmt3(sm, '{:.1e}')}"
              f" [{mspp} spp, {tm1 + tm2:.1f} s]; lux {fmt3(ml)} ±{fmt3(sl, '{:.1e}')}"
              f" [{lspp} spp, {tl1 + tl2:.1f} s process, {rl1 + rl2:.1f} s render]; "
              f"rel diff {fmt3(100 * rel, '{:+.3f}')} % ±{fmt3(100 * rel_se, '{:.3f}')} %; "
              f"HDR-FLIP {r['flip']:.4f}; RMSE {r['rmse']:.5f}", flush=True)
    print()
    print("| lux depth | Mitsuba max_depth | spp (each) | Mitsuba mean RGB | lux mean RGB "
          "| lux/Mitsuba − 1 (±1σ) | HDR-FLIP | RMSE | Mitsuba s | lux s (process) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        rel = ", ".join(f"{100 * x:+.2f}" for x in r["rel_diff"])
        se = max(100 * x for x in r["rel_diff_se"])
        print(f"| {r['depth']} | {r['mitsuba_max_depth']} | {r['mitsuba_spp']} / {r['lux_spp']} | "
              f"{fmt3(r['mean_mitsuba'], '{:.4f}')} | {fmt3(r['mean_lux'], '{:.4f}')} | "
              f"({rel}) % ±{se:.2f} % | {r['flip']:.4f} | {r['rmse']:.5f} | "
              f"{r['mitsuba_s']:.1f} | {r['lux_wall_s']:.1f} |")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(scene=a.scene, rows=rows), f, indent=1)


def cmd_means(a):
    """Converged Mitsuba image means per depth at --res (the regression test's reference)."""
    desc = pm.extract_scene(a.scene, 1.0)
    desc["resolution"] = (a.res, a.res) if a.res else desc["resolution"]
    pm.set_variant("scalar_rgb")
    out = dict(scene=os.path.relpath(a.scene, REPO), resolution=list(desc["resolution"]),
               spp=a.spp, sampler=a.sampler, variant="scalar_rgb", rfilter="box",
               command="~/.cache/lux-peer/bin/python scripts/path_vs_mitsuba.py " +
               " ".join(sys.argv[1:]), depths={})
    for depth in [int(x) for x in a.depths.split(",")]:
        sc = pm.build_mitsuba_scene(desc, a.spp, a.seed, 1, 1, sampler=a.sampler,
                                    integrator=mitsuba_integrator(depth))
        h1, t1 = pm.render(sc, a.spp // 2, a.seed + 1)
        h2, t2 = pm.render(sc, a.spp // 2, a.seed + 2)
        m, se = mean_rgb(0.5 * (h1 + h2)), mean_se(h1, h2)
        out["depths"][str(depth)] = dict(mitsuba_integrator=mitsuba_integrator(depth),
                                         mean=m.tolist(), sigma=se.tolist(), seconds=t1 + t2)
        print(f"depth {depth}: mean {fmt3(m, '{:.6f}')} ±{fmt3(se, '{:.1e}')} ({t1 + t2:.1f} s)",
              flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


def cmd_race(a):
    os.makedirs(a.out, exist_ok=True)
    desc = pm.extract_scene(a.scene, 1.0)
    pm.set_variant("scalar_rgb")
    depth = a.depth
    integ = mitsuba_integrator(depth)
    if a.gt:
        gt = pm.read_exr_rgb(a.gt)
        sig_gt = json.load(open(a.gt + ".json"))["sigma"]
        print(f"ground truth {a.gt}: noise {sig_gt:.6f}")
    else:
        gsc = pm.build_mitsuba_scene(desc, 16, 1, 1, 1, sampler=a.gt_sampler, integrator=integ)
        half = a.gt_spp // 2
        h1, t1 = pm.render(gsc, half, 100003)
        h2, t2 = pm.render(gsc, half, 200003)
        gt = 0.5 * (h1 + h2)
        sig_gt = pm._rmse(h1, h2) / 2
        gtp = os.path.join(a.out, f"cornell.path.d{depth}.gt.spp{2 * half}.exr")
        pm.write_exr_rgb(gtp, gt)
        json.dump(dict(spp=2 * half, sigma=sig_gt, seconds=t1 + t2, sampler=a.gt_sampler,
                       integrator=integ), open(gtp + ".json", "w"))
        print(f"ground truth {gtp}: {2 * half} spp ({a.gt_sampler}) in {t1 + t2:.1f} s, "
              f"noise {sig_gt:.6f}", flush=True)

    lux_rows = []
    lux_render(a.lux, a.scene, depth, 4, os.path.join(a.out, "warm.exr"), 99)  # warm caches
    # entries S or S@T (S spp at lux's --adaptive-threshold T), as race.py's --lux-spp
    for s, t in race.lux_ladder(a.lux_spp):
        more = ["--adaptive-threshold", str(t)] if t is not None else []
        name = f"lux{s}" + (f"_t{t}" if t is not None else "")
        img, wall, own, px = race.lux_render(a.lux, a.scene, 1, s, os.path.join(a.out, f"{name}.exr"),
                                             7 + s, more, depth)
        lux_rows.append(dict(spp=s, threshold=t, px=px, seconds=wall, render_s=own,
                             rmse=pm._rmse(img, gt)))
    sc = pm.build_mitsuba_scene(desc, 16, 1, 1, 1, sampler=a.mi_sampler, integrator=integ)
    pm.render(sc, 4, 7)  # warm-up
    mi_rows = []
    for s in [int(x) for x in a.mi_spp.split(",")]:
        img, secs = pm.render(sc, s, 11 + s)
        mi_rows.append(dict(spp=s, seconds=secs, rmse=pm._rmse(img, gt)))

    if a.targets:
        targets = [float(t) for t in a.targets.split(",")]
    else:
        r16 = min(mi_rows, key=lambda r: abs(r["spp"] - 16))
        n16 = math.sqrt(max(r16["rmse"] ** 2 - sig_gt ** 2, 0.0))
        targets = [n16, n16 / 3]
    print(f"depth {depth} (Mitsuba path max_depth {depth + 1}, {a.mi_sampler}); "
          f"GT noise {sig_gt:.6f}; targets {', '.join(f'{t:.6f}' for t in targets)}")
    print("| renderer | spp | seconds | RMSE vs GT |")
    print("|---|---|---|---|")
    for r in lux_rows:
        at = f" at t = {r['threshold']}" if r["threshold"] is not None else ""
        print(f"| lux (process; render {r['render_s']:.2f} s; {r['px']:.2f} a pixel) | {r['spp']}{at} | "
              f"{r['seconds']:.2f} | {r['rmse']:.6f} |")
    for r in mi_rows:
        print(f"| mitsuba path {a.mi_sampler} | {r['spp']} | {r['seconds']:.2f} | {r['rmse']:.6f} |")
    lf = race.fit(lux_rows, sig_gt, targets)
    mf = race.fit(mi_rows, sig_gt, targets)
    for tg in targets:
        (ls, lt), (ms, mt) = lf[tg], mf[tg]
        print(f"target noise {tg:.6f}: lux {ls:.0f} spp {lt:.2f} s; mitsuba path {ms:.0f} spp "
              f"{mt:.2f} s")
    for tg in targets:
        print(f"race: lux/mitsuba(path) time ratio at {tg:.6f} = {lf[tg][1] / mf[tg][1]:.3f}")
    if a.json:
        json.dump(dict(depth=depth, gt_sigma=sig_gt, targets=targets, lux=lux_rows,
                       mitsuba=mi_rows, ratio={str(t): lf[t][1] / mf[t][1] for t in targets}),
                  open(a.json, "w"), indent=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    for name in ("compare", "race", "means"):
        p = sub.add_parser(name)
        p.add_argument("--lux", required=name != "means", help="the lux binary")
        p.add_argument("--scene", default=DEFAULT_SCENE)
        p.add_argument("--out", default=os.path.join(tempfile.gettempdir(), f"path_vs_mitsuba_{name}"))
        p.add_argument("--json")
    c = sub.choices["compare"]
    c.add_argument("--depths", default="1,2,8")
    c.add_argument("--spp", type=int, default=1024, help="Mitsuba spp (two halves)")
    c.add_argument("--lux-spp", type=int, default=0, help="lux spp (two halves; default --spp)")
    c.add_argument("--sampler", default="independent", help="Mitsuba sampler")
    c.add_argument("--seed", type=int, default=1)
    m = sub.choices["means"]
    m.add_argument("--depths", default="1,2,8")
    m.add_argument("--res", type=int, default=64, help="square resolution (0: the stage's)")
    m.add_argument("--spp", type=int, default=8192, help="Mitsuba spp (two halves)")
    m.add_argument("--sampler", default="independent")
    m.add_argument("--seed", type=int, default=1)
    r = sub.choices["race"]
    r.add_argument("--depth", type=int, default=8)
    r.add_argument("--gt", help="a ground truth EXR written by an earlier run (with its .json)")
    r.add_argument("--gt-spp", type=int, default=4096)
    r.add_argument("--gt-sampler", default="independent")
    r.add_argument("--mi-sampler", default="ldsampler")
    r.add_argument("--lux-spp", default="4,16,64,256",
                   help="lux runs: S (spp) or S@T (spp at --adaptive-threshold T), comma separated")
    r.add_argument("--mi-spp", default="4,16,64,256")
    r.add_argument("--targets", default="")
    a = ap.parse_args()
    a.scene = os.path.abspath(a.scene)
    {"compare": cmd_compare, "race": cmd_race, "means": cmd_means}[a.cmd](a)


if __name__ == "__main__":
    main()
