#!/bin/bash
# Smoke test of scripts/bench_3d.py: one small CAD model (011: 812 triangles, a 4-primitive
# InverseCSG program that CGAL renders in well under a second), 3 s of csgfit, through OpenSCAD
# and the independent voxel IoU. It checks that the pipeline runs and writes an ok CSV row, not
# the scores (docs/BENCHMARKS.md has the targets). Skips (exit 0) when the benchmark set or
# OpenSCAD is not there.
# Usage: bash bench3d_smoke_test.sh <path-to-csgfit-cli> <source-dir>
set -u
cli=${1:?usage: bench3d_smoke_test.sh CLI SOURCE_DIR}
src=${2:?usage: bench3d_smoke_test.sh CLI SOURCE_DIR}
bench="$src/../shared/benchmarks/3d/inversecsg"
if [ ! -f "$bench/manifest.json" ]; then
  echo "bench3d_smoke: $bench not found: skipped"
  exit 0
fi
if ! command -v openscad >/dev/null; then
  echo "bench3d_smoke: openscad not installed: skipped"
  exit 0
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

/usr/bin/python3 "$src/scripts/bench_3d.py" --cli "$cli" --bench-dir "$bench" \
  --only 011 --time 3 --out "$out" >"$out/table.md" 2>"$out/log.txt"
rc=$?
cat "$out/table.md"
if [ $rc -ne 0 ]; then
  echo "bench3d_smoke: bench_3d.py exited $rc" >&2
  cat "$out/log.txt" >&2
  exit 1
fi
if ! grep -q '^011,cad,ok,0\.[0-9]' "$out/results.csv" \
   && ! grep -q '^011,cad,ok,1' "$out/results.csv"; then
  echo "bench3d_smoke: no ok row with an IoU for 011 in results.csv" >&2
  cat "$out/results.csv" >&2
  exit 1
fi
grep -q '^| \*\*all\*\* | 1 |' "$out/table.md" || { echo "bench3d_smoke: no overall row" >&2; exit 1; }
echo "bench3d_smoke: ok"
