#!/bin/bash
# Same seed, same tree: the fixed-seed runs of scripts/golden.py (2D and 3D, each ending by
# convergence) must give the JSON and .scad recorded in tests/golden/expected/. A change that
# alters them on purpose re-records them (golden.py record) and says why in its commit.
# Skips (exit 0) when the benchmark set is not there.
# Usage: bash golden_test.sh <path-to-csgfit-cli> <source-dir>
set -u
cli=${1:?usage: golden_test.sh CLI SOURCE_DIR}
src=${2:?usage: golden_test.sh CLI SOURCE_DIR}
if [ ! -d "$src/../shared/benchmarks" ]; then
  echo "golden: $src/../shared/benchmarks not found: skipped"
  exit 0
fi
exec /usr/bin/python3 "$src/scripts/golden.py" check --cli "$cli" --jobs 2
