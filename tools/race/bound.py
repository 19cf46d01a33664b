#!/usr/bin/env python3
"""How few samples a pixel could reach an RMSE target with: the bounds of adaptive sampling.

Renders a stage N times (seeds 1..N) with every pixel at `--spp S` (`--no-adaptive`, the
`hdembree` profile, lux's other defaults), measures each pixel's variance of one sample
(the sample variance over the seeds times S, averaged over R, G, B as the RMSE is), and answers:

- **Allocation bounds.** The average samples a pixel needs for the target when a pixel takes
  `n = max(m, c·σ̂)` samples (the allocation that minimises the summed squared error, with a
  floor of m first samples), for σ̂ the pixel's own σ (what no rule can know before sampling
  the pixel), its 8 neighbours' σ pooled (what a rule that reads only neighbours can know at
  best: lux's adaptive sampling keeps pixels unbiased so), or a 3 × 3, 5 × 5, 7 × 7 block's.
- **Light samples a light per pixel** (`--light-samples 1,2,4,8`): the same for each count of
  light samples a light (`--light-samples K`, its own variance and render time), with σ known from
  the 8 neighbours and each sample at its count's cost, then with each pixel taking the count whose
  neighbours' variance × cost is least.

The figures are per-pixel oracles: an upper bound on what any rule of that kind reaches.

    $PY tools/race/bound.py tools/race/shader_ball.usda 3 --lux target/release/lux --target 0.00645 --light-samples 1,2,4,8
"""
import argparse, os, re, subprocess, sys, tempfile
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_mitsuba as pm  # noqa: E402


def renders(a, extra, tmp, tag):
    """Per-pixel variance of one sample and the mean render seconds over the seeds."""
    imgs, secs = [], []
    for s in range(1, a.seeds + 1):
        out = os.path.join(tmp, f"{tag}_{s}.exr")
        cmd = [a.lux, "render", a.scene, "--frame", str(a.frame), "--profile", "hdembree", "--no-adaptive",
               "--spp", str(a.spp), "--seed", str(s), "--quiet", "-o", out, *extra]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"lux failed ({' '.join(cmd)}): {r.stderr[-600:]}")
        secs.append(float(re.search(r"in ([0-9.]+) s", r.stderr).group(1)))
        imgs.append(pm.read_exr_rgb(out).astype(np.float64))
    v = np.stack(imgs).var(0, ddof=1).mean(-1) * a.spp
    return v, sum(secs) / len(secs)


def samples_needed(v, est, floor, mse, cost=None):
    """(mean n, mean n·cost) over the pixels for n = max(floor, c·√(est/cost)) at the c where
    mean(v/n) = mse: the allocation that minimises the time for the summed squared error when a
    pixel's samples have variance v and cost `cost` each (1: samples a pixel)."""
    cost = np.ones_like(v) if cost is None else cost
    s = np.sqrt(np.maximum(est, 1e-30) / cost)
    lo, hi = 1e-6, 1e12
    for _ in range(200):
        c = (lo * hi) ** 0.5
        n = np.maximum(floor, c * s) if floor > 0 else c * s
        if (v / n).mean() > mse:
            lo = c
        else:
            hi = c
    return n.mean(), (n * cost).mean()


def box(x, w, centre=True):
    """Mean over the w × w block around each pixel (edges replicated), without the pixel itself
    when `centre` is false."""
    p = w // 2
    xp = np.pad(x, p, mode="edge")
    h, wd = x.shape
    acc = np.zeros_like(x)
    for dy in range(w):
        for dx in range(w):
            if not centre and dy == p and dx == p:
                continue
            acc += xp[dy:dy + h, dx:dx + wd]
    return acc / (w * w - (0 if centre else 1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("frame", type=float)
    ap.add_argument("--lux", required=True)
    ap.add_argument("--target", type=float, required=True, help="RMSE to reach (e.g. Mitsuba's at 64 spp)")
    ap.add_argument("--seeds", type=int, default=12)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--light-samples", default="", help="counts of light samples a light to compare, e.g. 1,2,4,8")
    a = ap.parse_args()
    mse = a.target ** 2
    with tempfile.TemporaryDirectory() as tmp:
        v, t1 = renders(a, [], tmp, "default")
        print(f"variance of one sample: {v.mean():.4e} (mean over pixels; {a.seeds} seeds at {a.spp} spp, "
              f"{t1:.3f} s a render)")
        print("| σ known from | samples a pixel, floor 1 | floor 2 | no floor |\n|---|---|---|---|")
        rows = [("the pixel itself", v), ("its 8 neighbours", box(v, 3, centre=False)),
                ("3 × 3 block", box(v, 3)), ("5 × 5 block", box(v, 5)), ("7 × 7 block", box(v, 7))]
        for name, est in rows:
            print(f"| {name} | {samples_needed(v, est, 1, mse)[0]:.2f} | {samples_needed(v, est, 2, mse)[0]:.2f} | "
                  f"{samples_needed(v, est, 0, mse)[0]:.2f} |")
        if a.light_samples:
            ks = [int(k) for k in a.light_samples.split(",")]
            print("| light samples a light | variance of one sample | render s | samples a pixel | "
                  "render s at the target |\n|---|---|---|---|---|")
            vs, cs = [], []
            for k in ks:
                vk, tk = renders(a, ["--light-samples", str(k)], tmp, f"k{k}")
                cost = np.full_like(vk, tk / a.spp)  # seconds of one sample in every pixel
                n, t = samples_needed(vk, box(vk, 3, centre=False), 1, mse, cost)
                print(f"| {k} | {vk.mean():.4e} | {tk:.3f} | {n:.2f} | {t:.3f} |")
                vs.append(vk)
                cs.append(cost)
            pick = np.stack([box(vk, 3, centre=False) * c for vk, c in zip(vs, cs)]).argmin(0)
            v_p, c_p = np.choose(pick, vs), np.choose(pick, cs)
            est = np.choose(pick, [box(vk, 3, centre=False) for vk in vs])
            n, t = samples_needed(v_p, est, 1, mse, c_p)
            share = ", ".join(f"{k}: {100 * (pick == i).mean():.0f} %" for i, k in enumerate(ks))
            print(f"each pixel's count by its neighbours ({share}): {n:.2f} samples a pixel, "
                  f"render {t:.3f} s at the target")


if __name__ == "__main__":
    main()
