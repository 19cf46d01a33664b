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
- **Light samples per pixel** (`--high K`, rendered with `--light-samples 1` and `K`): the
  variance split into the footprint's F (what is left with K light samples per light) and
  the lights' V (the rest, per light sample), and what choosing each pixel's light samples
  per light k ∈ {1, 2, 3, 4, 6, 8} with perfect knowledge would gain, cost per sample
  `a + b·k` fitted from the two renders' times: Σ√((F + V/k)·cost(k)) against k = 1.

The figures are per-pixel oracles: an upper bound on what any rule of that kind reaches.

    $PY tools/race/bound.py tools/race/shader_ball.usda 3 --lux target/release/lux --target 0.00645 --high 64
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


def samples_needed(v, sig, floor, mse):
    """Mean of n = max(floor, c·sig) over the pixels for the c at which mean(v/n) = mse."""
    sig = np.maximum(sig, 1e-30)
    lo, hi = 1e-6, 1e12
    for _ in range(200):
        c = (lo * hi) ** 0.5
        n = np.maximum(floor, c * sig) if floor > 0 else c * sig
        if (v / n).mean() > mse:
            lo = c
        else:
            hi = c
    return n.mean()


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
    ap.add_argument("--high", type=int, default=0, help="also split footprint and light variance with K light samples")
    a = ap.parse_args()
    mse = a.target ** 2
    with tempfile.TemporaryDirectory() as tmp:
        v, t1 = renders(a, ["--light-samples", "1"] if a.high else [], tmp, "k1")
        print(f"variance of one sample: {v.mean():.4e} (mean over pixels; {a.seeds} seeds at {a.spp} spp, "
              f"{t1:.3f} s a render)")
        print("| σ known from | samples a pixel, floor 1 | floor 2 | no floor |\n|---|---|---|---|")
        rows = [("the pixel itself", v), ("its 8 neighbours", box(v, 3, centre=False)),
                ("3 × 3 block", box(v, 3)), ("5 × 5 block", box(v, 5)), ("7 × 7 block", box(v, 7))]
        for name, est in rows:
            s = np.sqrt(est)
            print(f"| {name} | {samples_needed(v, s, 1, mse):.2f} | {samples_needed(v, s, 2, mse):.2f} | "
                  f"{samples_needed(v, s, 0, mse):.2f} |")
        if a.high:
            vh, th = renders(a, ["--light-samples", str(a.high)], tmp, "kh")
            f = vh
            vl = np.maximum(v - f, 0) * a.high / (a.high - 1)
            b = (th - t1) / (a.high - 1)
            c0 = t1 - b
            print(f"footprint F {f.mean():.4e}, lights V {vl.mean():.4e} (one light sample per light); "
                  f"cost a + b·k with a = {c0:.4f} s, b = {b:.4f} s a render")
            base = np.sqrt((f + vl) * (c0 + b)).mean() ** 2
            ks = [1, 2, 3, 4, 6, 8]
            eff = np.stack([np.sqrt((f + vl / k) * (c0 + b * k)) for k in ks])
            best = eff.min(0).mean() ** 2
            pick = np.array(ks)[eff.argmin(0)]
            share = ", ".join(f"k={k} {100 * (pick == k).mean():.0f} %" for k in ks)
            print(f"light samples per pixel, each pixel's best k: time × squared error {best / base:.3f} "
                  f"of k = 1 ({share})")


if __name__ == "__main__":
    main()
