#!/usr/bin/env bash
# Seed 000's Table 2 ("--preset paper") beside our defaults on one bitmap, each run until its own
# stopping rule ends it (a generous --time), same seed and threads. Prints a Markdown table.
#   bash scripts/bench_presets.sh [BITMAP] [CLI]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bitmap="${1:-$repo/../shared/benchmarks/2d/glyph_P.png}"
cli="${2:-$repo/build/bin/csgfit}"
if [ ! -f "$bitmap" ]; then
  echo "bench_presets: $bitmap not found: skipped"
  exit 0
fi
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| preset | IoU | primitives | trees searched | evaluations | seconds | stopped by |"
echo "|---|--:|--:|--:|--:|--:|---|"
for preset in default paper; do
  line="$("$cli" image "$bitmap" -o "$out/$preset.scad" --preset "$preset" --time 300 --seed 1 2>&1 | tail -n 1)"
  # csgfit: IoU 0.9818, 4 primitives, 5123 trees, 2392879 evaluations, 36.70 s (converged)
  echo "$line" | sed -E "s/^csgfit: IoU ([0-9.]+), ([0-9]+) primitives, ([0-9]+) trees, ([0-9]+) evaluations, ([0-9.]+) s \((.*)\)$/| $preset | \1 | \2 | \3 | \4 | \5 | \6 |/"
done
