#!/bin/bash
# Smoke test of scripts/bench_2d.py: two bitmaps, 1 s each, through the CLI, OpenSCAD and
# potrace. It checks that the benchmark pipeline runs and writes its CSV, not the scores
# (docs/BENCHMARKS.md has the targets). Skips (exit 0) when the benchmark set is not there.
# Usage: bash bench_smoke_test.sh <path-to-csgfit-cli> <source-dir>
set -u
cli=${1:?usage: bench_smoke_test.sh CLI SOURCE_DIR}
src=${2:?usage: bench_smoke_test.sh CLI SOURCE_DIR}
bench="$src/../shared/benchmarks/2d"
if [ ! -f "$bench/manifest.json" ]; then
  echo "bench_smoke: $bench not found: skipped"
  exit 0
fi
for tool in potrace openscad; do
  if ! command -v "$tool" >/dev/null; then
    echo "bench_smoke: $tool not installed: skipped"
    exit 0
  fi
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

/usr/bin/python3 "$src/scripts/bench_2d.py" --cli "$cli" --bench-dir "$bench" \
  --only glyph_P cad_0000 --time 1 --pictures 0 --out "$out" >"$out/table.md" 2>"$out/log.txt"
rc=$?
cat "$out/table.md"
if [ $rc -ne 0 ]; then
  echo "bench_smoke: bench_2d.py exited $rc" >&2
  cat "$out/log.txt" >&2
  exit 1
fi
rows=$(tail -n +2 "$out/results.csv" | grep -c ',ok,')
if [ "$rows" -ne 2 ]; then
  echo "bench_smoke: expected 2 ok rows in results.csv, got $rows" >&2
  cat "$out/results.csv" >&2
  exit 1
fi
grep -q '^| \*\*all\*\* | 2 |' "$out/table.md" || { echo "bench_smoke: no overall row" >&2; exit 1; }
echo "bench_smoke: ok"
