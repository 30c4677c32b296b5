#!/bin/bash
# Same seed, same tree: the fixed-seed runs of scripts/golden.py (2D and 3D, each ending by
# convergence) must give the JSON and .scad recorded in tests/golden/expected/. A change that
# alters them on purpose re-records them (golden.py record) and says why in its commit.
# Skips (exit 0) when the benchmark set is not there.
# Usage: bash golden_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_need_benchmarks
exec "$PY" "$SRC/scripts/golden.py" check --cli "$CLI" --jobs 2
