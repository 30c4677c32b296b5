#!/bin/bash
# Smoke test of scripts/bench_3d.py: one small CAD model (011: 812 triangles, a 4-primitive
# InverseCSG program that CGAL renders in well under a second), 3 s of csgfit, through OpenSCAD
# and the independent voxel IoU. It checks that the pipeline runs and writes an ok CSV row, not
# the scores (docs/BENCHMARKS.md has the targets). Skips (exit 0) when the benchmark set or
# OpenSCAD is not there.
# Usage: bash bench3d_smoke_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_need_benchmarks 3d/inversecsg
e2e_need_tools openscad
e2e_tmpdir

e2e_run_bench bench_3d.py --only 011 --time 3
if ! grep -q '^011,cad,ok,0\.[0-9]' "$TMP/results.csv" \
   && ! grep -q '^011,cad,ok,1' "$TMP/results.csv"; then
  echo "$E2E_NAME: no ok row with an IoU for 011 in results.csv" >&2
  cat "$TMP/results.csv" >&2
  exit 1
fi
e2e_bench_done 1
