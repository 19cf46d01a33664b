"""RMSE against a ground truth and camera samples a pixel, over a list of --spp, for one luxtest
frame: how many samples lux needs for an error, whatever the machine's load (BENCHMARKS.md,
"Adaptive sampling").

usage: python scripts/spp_sweep.py SCENE GT.exr "LUX ARGS" 1,2,4,8 [--lux target/release/lux]
       [--scene-dir DIR] [--frame 1]

GT.exr is a ground truth of the race (tools/race: race.py writes
SCENE.0001.gt.spp2048.exr); renders use the race's settings (--profile hdembree, seed 7 + spp,
512 x 512). Needs numpy and OpenEXR (the race's peer venv has both).
"""
import argparse, os, re, subprocess, tempfile
import numpy as np
import OpenEXR


def load(path):
    ch = OpenEXR.File(path).channels()
    if "RGBA" in ch:
        return ch["RGBA"].pixels[..., :3].astype(np.float64)
    if "RGB" in ch:
        return ch["RGB"].pixels.astype(np.float64)
    return np.stack([ch[c].pixels for c in "RGB"], -1).astype(np.float64)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene"); ap.add_argument("gt"); ap.add_argument("args"); ap.add_argument("spp")
    ap.add_argument("--lux", default="target/release/lux")
    ap.add_argument("--scene-dir", default="../shared/testdata/luxtest/usd")
    ap.add_argument("--frame", default="1")
    a = ap.parse_args()
    gt = load(a.gt)
    out = os.path.join(tempfile.gettempdir(), "spp_sweep.exr")
    stage = os.path.join(a.scene_dir, f"{a.scene}.usda")
    for s in [int(x) for x in a.spp.split(",")]:
        cmd = [a.lux, "render", stage, "--frame", a.frame, "--spp", str(s), "--profile", "hdembree",
               "--seed", str(7 + s), "-o", out] + a.args.split()
        r = subprocess.run(cmd, capture_output=True, text=True, check=True)
        m = re.search(r"= (\d+) samples.*? in ([0-9.]+) s", r.stderr)
        img = load(out)
        rmse = float(np.sqrt(((img - gt) ** 2).mean()))
        per_px = int(m.group(1)) / (img.shape[0] * img.shape[1])
        print(f"| {a.scene} | {a.args or '(default)'} | {s} | {per_px:.2f} | {rmse:.6f} |", flush=True)


if __name__ == "__main__":
    main()
