#!/usr/bin/env bash
# Bit-identity check of two lux binaries: renders a fixed set of stages and options with both
# and compares the EXRs byte for byte, else their pixels' bits (examples/exr_same_pixels.rs: a
# header attribute may be renamed; a refactoring that keeps the pictures keeps every bit).
#
#   scripts/bit_check.sh BASE_LUX NEW_LUX [OUT_DIR]
#
# The set: every luxtest stage at frames 1 and 20 in both conformance profiles, reference
# sampling, the light-selection strategies, a crop, 1 and 2 threads, path tracing of the Cornell
# box and the demo, and real USD files (subdivided, skinned, curved, instanced). Prints one line
# per render ("same" or "DIFF") and a count; exits 1 when any differs.
set -uo pipefail
cd "$(dirname "$0")/.."
base=$1
new=$2
out=${3:-$(mktemp -d "${TMPDIR:-/tmp}/lux-bit-check.XXXXXX")}
mkdir -p "$out"
lt=crates/lux-render/tests/data/luxtest/usd
ru=tests/data/realusd
renders=()
for s in cylinder disk distant dome iesDown iesLibPreview iesTest iesUp ies_scale rect sphere visibleRect; do
    for f in 1 20; do
        renders+=("$lt/$s.usda --frame $f --profile hdembree --spp 4 --resolution 96x54")
        renders+=("$lt/$s.usda --frame $f --profile spec --spp 2 --resolution 64x36")
    done
done
renders+=(
    "$lt/sphere.usda --frame 1 --profile hdembree --sampling reference --spp 4 --resolution 96x54"
    "$lt/rect.usda --frame 5 --profile hdembree --light-selection power --spp 4 --resolution 96x54"
    "$lt/rect.usda --frame 5 --profile hdembree --light-selection bvh --spp 4 --resolution 96x54"
    "$lt/disk.usda --frame 1 --profile hdembree --crop 20,10,70,40 --spp 8 --resolution 96x54"
    "$lt/sphere.usda --frame 1 --profile hdembree --spp 16 --penumbra-samples 4 --resolution 96x54"
    "$lt/cylinder.usda --frame 1 --profile hdembree --spp 4 --threads 1 --resolution 96x54"
    "tests/data/cornell/cornell.usda --integrator path --spp 4 --resolution 64x64"
    "tests/data/cornell/cornell.usda --profile hdembree --spp 4 --resolution 64x64"
    "scenes/demo/demo.usda --spp 4 --resolution 96x54"
    "$ru/usdwg/full_assets/Teapot/Teapot.usd --spp 2 --resolution 64x36"
    "$ru/usdwg/full_assets/StandardShaderBall/standard_shader_ball_scene.usda --spp 1 --resolution 64x36"
    "$ru/usdwg/full_assets/SubdivisionSurfaces/Creases_SpinningPyramids.usda --spp 2 --resolution 64x36"
    "$ru/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPointInstancer/pi_basic.usda --spp 2 --resolution 64x36"
    "$ru/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLInstancing/instance.usda --spp 2 --resolution 64x36"
    "$ru/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLBasicLighting/basicDrawing.usda --spp 2 --resolution 64x36"
    "$ru/usdwg/test_assets/RoughnessTest/RoughnessTest.usdz --spp 2 --resolution 64x36"
    "crates/lux-usd/tests/data/skel/usdwg/test_assets/USDZ/RiggedFigure/RiggedFigure.usdz --spp 2 --resolution 64x36"
    "tests/data/realusd/Autodesk-maya-usd/test/lib/usd/translators/UsdImportLightTest/LightsTest.usda --spp 2 --resolution 64x36"
)
cargo build --release --quiet --example exr_same_pixels
same=target/release/examples/exr_same_pixels
diffs=0
i=0
for r in "${renders[@]}"; do
    i=$((i + 1))
    # shellcheck disable=SC2086
    "$base" render $r --seed 7 --quiet -o "$out/$i.base.exr" 2>/dev/null
    # shellcheck disable=SC2086
    "$new" render $r --seed 7 --quiet -o "$out/$i.new.exr" 2>/dev/null
    if cmp -s "$out/$i.base.exr" "$out/$i.new.exr"; then
        echo "same  $r"
    elif "$same" "$out/$i.base.exr" "$out/$i.new.exr" >/dev/null; then
        echo "same pixels  $r"
    else
        echo "DIFF  $r"
        diffs=$((diffs + 1))
    fi
done
echo "bit_check: $((i - diffs)) of $i renders identical"
[ "$diffs" -eq 0 ]
