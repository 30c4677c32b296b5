#!/bin/bash
# The solver's source checks: its stages include only themselves and earlier stages
# (scripts/check_layers.py) and its files and functions stay within the size limits
# (scripts/check_sizes.py). Both pass on this tree and both catch a planted violation.
# Usage: bash source_checks_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_tmpdir

"$PY" "$SRC/scripts/check_layers.py" >"$TMP/layers.txt" || { cat "$TMP/layers.txt"; fail "layering of $SRC"; }
"$PY" "$SRC/scripts/check_sizes.py" >"$TMP/sizes.txt" || { cat "$TMP/sizes.txt"; fail "sizes of $SRC"; }

# A model file that includes the pipeline, and a 130-line function: each must be reported.
mkdir -p "$TMP/bad/native/src/model" "$TMP/bad/native/include/csgfit"
printf '#include "csgfit/pipeline/fit_bitmap.h"\n#include "scad_writer.h"\n' \
  >"$TMP/bad/native/src/model/late.cpp"
{
  echo "int long_one(int x) {"
  for i in $(seq 128); do echo "  x += $i;"; done
  echo "  return x;"
  echo "}"
} >"$TMP/bad/native/src/model/long.cpp"

out=$("$PY" "$SRC/scripts/check_layers.py" --repo "$TMP/bad")
[ $? -eq 1 ] || fail "check_layers passed a model file including the pipeline"
grep -q "late.cpp (model) includes csgfit/pipeline/fit_bitmap.h (pipeline), a later stage" <<<"$out" \
  || fail "check_layers did not name the later stage: $out"
grep -q "late.cpp: includes the writer scad_writer.h" <<<"$out" || fail "check_layers missed the writer: $out"

out=$("$PY" "$SRC/scripts/check_sizes.py" --repo "$TMP/bad" native)
[ $? -eq 1 ] || fail "check_sizes passed a function of 131 lines"
grep -q "long.cpp:1: a function of 131 lines (limit 120)" <<<"$out" || fail "check_sizes: $out"
"$PY" "$SRC/scripts/check_sizes.py" --repo "$TMP/bad" --max-function 140 native >/dev/null \
  || fail "check_sizes flagged a function within --max-function"

e2e_finish "source_checks: ok"
