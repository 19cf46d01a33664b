#!/usr/bin/env bash
# Seeds the `parse` fuzz target with the lux-ies test corpus (crates/lux-ies/tests/data: the 24
# LM-63 files, malformed ones included). corpus/ is git-ignored: the script creates it.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/parse
find ../crates/lux-ies/tests/data -name '*.ies' | while read -r f; do
    cp "$f" "corpus/parse/seed_$(basename "$(dirname "$f")")_$(basename "$f")"
done
ls corpus/parse | grep -c '^seed_'

# Seeds the `usda` target with every .usda of the lux-render tests: the luxtest scenes and the
# loader's own scene tests (composition, time samples, transforms, bad input…).
mkdir -p corpus/usda
find ../crates/lux-render/tests/data -name '*.usda' | while read -r f; do
    rel="${f#../crates/lux-render/tests/data/}"
    cp "$f" "corpus/usda/seed_${rel//\//_}"
done
ls corpus/usda | grep -c '^seed_'
