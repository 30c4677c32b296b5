#!/bin/bash
# Smoke test of scripts/bench_optimize.py: two small ground-truth programs (lock: a cube and a
# sphere minus three cylinders; two_cuboids), as they are and inflated once, optimised, rendered
# by OpenSCAD and compared by the independent voxel IoU. Checks that every run is an ok row and
# that the report's acceptance lines pass on these (docs/BENCHMARKS.md has the full run). Skips
# (exit 0) when the benchmark set or OpenSCAD is not there.
# Usage: bash optimize_bench_smoke_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_need_benchmarks 3d/inversecsg
e2e_need_tools openscad
e2e_tmpdir

e2e_run_bench bench_optimize.py --only lock two_cuboids --programs gt --seeds 1 --grid 64
rows=$(grep -c ',ok,' "$TMP/results.csv")
if [ "$rows" -ne 4 ] || grep -q 'FAIL' "$TMP/table.md"; then
  echo "$E2E_NAME: expected 4 ok runs and no failed acceptance line" >&2
  cat "$TMP/results.csv" >&2
  exit 1
fi
echo "$E2E_NAME: ok"
