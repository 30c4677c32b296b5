#!/bin/bash
# Smoke test of scripts/bench_2d.py: two bitmaps, 1 s each, through the CLI, OpenSCAD and
# potrace. It checks that the benchmark pipeline runs and writes its CSV, not the scores
# (docs/BENCHMARKS.md has the targets). Skips (exit 0) when the benchmark set is not there.
# Usage: bash bench_smoke_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_need_benchmarks 2d
e2e_need_tools potrace openscad
e2e_tmpdir

e2e_run_bench bench_2d.py --only glyph_P cad_0000 --time 1 --pictures 0
rows=$(tail -n +2 "$TMP/results.csv" | grep -c ',ok,')
if [ "$rows" -ne 2 ]; then
  echo "$E2E_NAME: expected 2 ok rows in results.csv, got $rows" >&2
  cat "$TMP/results.csv" >&2
  exit 1
fi
e2e_bench_done 2
