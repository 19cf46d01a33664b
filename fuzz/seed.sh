#!/usr/bin/env bash
# Seeds the `parse` fuzz target with the lux-ies test corpus (crates/lux-ies/tests/data: the 24
# LM-63 files, malformed ones included). corpus/parse/ is git-ignored apart from .gitkeep.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/parse
find ../crates/lux-ies/tests/data -name '*.ies' | while read -r f; do
    cp "$f" "corpus/parse/seed_$(basename "$(dirname "$f")")_$(basename "$f")"
done
ls corpus/parse | grep -c '^seed_'
