#!/usr/bin/env bash
# OpenJD check of `lux farm`: writes the job template of a 2-frame × 2-tile render of a small
# luxtest scene, validates it with `openjd check`, runs its Render and Merge steps locally with
# `openjd run`, and compares every merged frame with the single-process render of that frame,
# bit for bit (python OpenEXR + numpy).
#
#   scripts/farm_check.sh
#
# Environment: LUX (the lux binary; default: `cargo build --profile test --bin lux`, the binary in
# $CARGO_TARGET_DIR or target/), OPENJD_VENV (a venv with openjd-cli, OpenEXR and numpy; default
# target/openjd-venv, created with pip when missing — a failed install fails the check).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
target=${CARGO_TARGET_DIR:-$root/target}

if [ -z "${LUX:-}" ]; then
    # (the test profile: after `cargo test` the binary is up to date, nothing rebuilds)
    cargo build --quiet --profile test --bin lux
    LUX=$target/debug/lux
fi
[ -x "$LUX" ] || { echo "farm_check: no lux binary at $LUX" >&2; exit 1; }

venv=${OPENJD_VENV:-$target/openjd-venv}
if ! "$venv/bin/python" -c 'import openjd.cli, OpenEXR, numpy' 2>/dev/null; then
    echo "farm_check: installing openjd-cli, OpenEXR and numpy into $venv" >&2
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --disable-pip-version-check openjd-cli OpenEXR numpy
fi
openjd=$venv/bin/openjd

work=$(mktemp -d "${TMPDIR:-/tmp}/lux-farm-check.XXXXXX")
trap 'rm -rf "$work"' EXIT
scene=$root/crates/lux-render/tests/data/luxtest/usd/sphere.usda
opts=(--spp 4 --resolution 48x32 --seed 3 --threads 1)

echo "== lux farm"
"$LUX" farm "$scene" --frames 1-2 --tiles 2 -o "$work/job.yaml" --output-dir "$work/frames" \
    -- "${opts[@]}"
cat "$work/job.yaml"

echo "== openjd check"
"$openjd" check "$work/job.yaml"

# OutputDir keeps its default (frames, next to the template); the scene is outside the
# template's directory, so it has no default.
params=(-p "ScenePath=$scene" -p "Lux=$LUX")
for step in Render Merge; do
    echo "== openjd run --step $step"
    "$openjd" run "$work/job.yaml" --step "$step" --no-run-dependencies "${params[@]}" \
        >"$work/$step.log" 2>&1 || { cat "$work/$step.log"; echo "farm_check: $step failed" >&2; exit 1; }
    tail -n 3 "$work/$step.log"
done

echo "== single-process renders"
for frame in 1 2; do
    "$LUX" render "$scene" --frame "$frame" "${opts[@]}" --quiet -o "$work/whole.$frame.exr"
done

echo "== compare"
"$venv/bin/python" - "$work" <<'EOF'
import sys, numpy as np, OpenEXR
work = sys.argv[1]

def load(path):
    with OpenEXR.File(path, separate_channels=True) as f:
        part = f.parts[0]
        channels = {k: np.array(v.pixels) for k, v in part.channels.items()}
        header = {k: v for k, v in part.header.items() if k.startswith("lux:")}
    return channels, header

frames = []
for frame in (1, 2):
    merged, mh = load(f"{work}/frames/sphere.{frame}.exr")
    whole, wh = load(f"{work}/whole.{frame}.exr")
    assert sorted(merged) == sorted(whole) == ["A", "B", "G", "R"], (sorted(merged), sorted(whole))
    for c in "RGBA":
        a, b = merged[c], whole[c]
        assert a.dtype == b.dtype == np.float32 and a.shape == b.shape == (32, 48), (c, a.shape, b.shape)
        diff = int(np.count_nonzero(a.view(np.uint32) != b.view(np.uint32)))
        assert diff == 0, f"frame {frame} channel {c}: {diff} pixels differ"
    assert mh == wh, (mh, wh)
    assert "lux:tile" not in mh
    frames.append(np.stack([merged[c] for c in "RGB"]))
    print(f"frame {frame}: merged == single-process render bit for bit "
          f"(48x32 RGBA, mean R {merged['R'].mean():.6g}); header {mh['lux:frame']}, {mh['lux:resolution']}")
print("farm_check: OK")
EOF
