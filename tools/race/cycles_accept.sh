#!/usr/bin/env bash
# The measurements of CYCLES.md: Cycles against the Mitsuba ground truth on the clutter scenes (seeds 1, 2) and the
# Cornell box, before (the importer alone; the earlier peer) and after peer_cycles.py's corrections.
#   tools/race/cycles_accept.sh GTDIR CLUTTERDIR_PREFIX CORNELL_GT [quick|final|all]
# GTDIR holds s{1,2}.{one,mix,many}.gt.exr (make_gt.py), CLUTTERDIR_PREFIX{1,2}/clutter_*.usda (make_scenes.py
# --seed 1, 2), CORNELL_GT a make_gt.py --path 8 ground truth of tests/data/cornell/cornell.usda at 256².
# quick: cycles_probe.py at 256² x 256 spp with --fixes none / lambert (the earlier peer) / all;
# final: peer_cycles.py itself (1024-spp picture check at the GT's resolution, then its race rows) with all fixes
# and with the earlier peer's, which the check must refuse. One render at a time; 2 threads.
set -u
here=$(cd "$(dirname "$0")" && pwd)
gt=$1; cl=$2; cgt=$3; what=${4:-all}
BPY=${BPY:-$HOME/.cache/lux-peer-bpy/bin/python}
out=${OUT:-/tmp/cycles_accept}; mkdir -p "$out"
cornell=$here/../../tests/data/cornell/cornell.usda
if [ "$what" != final ]; then
  for s in 1 2; do for k in one mix many; do for f in none lambert all; do
    $BPY "$here/cycles_probe.py" "$cl$s/clutter_$k.usda" 1 --gt "$gt/s$s.$k.gt.exr" --res 256 --spp 256 --fixes $f \
      --out "$out" --tag "s$s.$k.$f" 2>&1 | grep "^s$s\|Error"
  done; done; done
  for f in none lambert all; do
    $BPY "$here/cycles_probe.py" "$cornell" 1 --gt "$cgt" --res 256 --spp 256 --bounces 7 --fixes $f --out "$out" \
      --tag "cornell.$f" 2>&1 | grep "^cornell\|Error"
  done
fi
if [ "$what" != quick ]; then
  for s in 1 2; do for k in one mix many; do for f in all lambert; do
    echo "== seed $s clutter_$k, fixes $f"
    $BPY "$here/peer_cycles.py" clutter_$k 1 --scene-dir "$cl$s" --gt "$gt/s$s.$k.gt.exr" --spp 4,16 --fixes $f \
      --out "$out/final.s$s.$k.$f" --json "$out/final.s$s.$k.$f.json" 2>&1 | grep "^cycles\|^|\|no race\|Error"
  done; done; done
  for f in all lambert; do
    echo "== cornell (path, 7 bounces), fixes $f"
    $BPY "$here/peer_cycles.py" cornell 1 --scene-dir "$(dirname "$cornell")" --gt "$cgt" --bounces 7 --spp 4,16 \
      --fixes $f --out "$out/final.cornell.$f" --json "$out/final.cornell.$f.json" 2>&1 | grep "^cycles\|^|\|no race\|Error"
  done
fi
