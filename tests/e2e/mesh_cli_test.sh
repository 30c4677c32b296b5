#!/bin/bash
# `csgfit mesh` end to end: a box-minus-cylinder part written here as an STL, fitted, the .scad
# rendered by OpenSCAD and compared with the input by volume IoU on a voxel grid computed
# independently of the solver (scripts/stl_voxelize.py); then bad inputs.
# Usage: mesh_cli_test.sh CSGFIT_CLI SOURCE_DIR
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
# The first failure ends this test: each step works on the files of the one before.
fail() { echo "FAIL: $*"; exit 1; }
e2e_need_tools openscad
e2e_tmpdir
cd "$TMP" || exit 1

# A 40 x 30 x 12 block with a through hole of radius 7, as a closed, outward-oriented mesh.
$PY "$SRC/tests/fixtures/holed_block_stl.py" part.stl || fail "could not write the test mesh"

"$CLI" mesh part.stl -o part.scad --time 5 --threads 1 --seed 1 -q || fail "csgfit mesh exited $?"
[ -s part.scad ] || fail "no .scad written"
"$CLI" mesh part.stl -o part.json --time 2 --threads 1 -q || fail "csgfit mesh (.json) exited $?"
$PY - <<'PYEOF' || fail "bad JSON"
import json
d = json.load(open("part.json"))
assert d["schema"] == "csgfit/1" and d["dimension"] == 3, d.get("dimension")
assert d["stats"]["primitives"] >= 1 and d["stats"]["iou"] > 0.9, d["stats"]
assert "op" in d["tree"] or "type" in d["tree"]
PYEOF

openscad -o fitted.stl part.scad >openscad.log 2>&1 || { cat openscad.log; fail "OpenSCAD could not render the .scad"; }
GRID="--grid 96 76 36 --origin -24 -19 -3 --size 0.5"
$PY "$SRC/scripts/stl_voxelize.py" part.stl $GRID --out input.npy >/dev/null || fail "voxelising the input failed"
OUT=$($PY "$SRC/scripts/stl_voxelize.py" fitted.stl $GRID --compare input.npy --min-agreement 0) \
  || fail "voxelising the rendering failed: $OUT"
IOU=$(echo "$OUT" | sed -n 's/.*IoU \([0-9.]*\).*/\1/p')
echo "rendered .scad vs input mesh: $OUT"
$PY -c "import sys; sys.exit(0 if float('$IOU') >= 0.95 else 1)" || fail "IoU $IOU < 0.95"

# Bad inputs: exit 2, one line on stderr, no output file.
check_bad() {
  local what=$1 input=$2
  rm -f bad.scad
  "$CLI" mesh "$input" -o bad.scad --time 1 -q 2>err.txt
  local rc=$?
  [ $rc -eq 2 ] || fail "$what: exit $rc, expected 2"
  [ "$(wc -l <err.txt)" -eq 1 ] || { cat err.txt; fail "$what: expected one line on stderr"; }
  [ ! -e bad.scad ] || fail "$what: an output file was written"
  echo "$what: $(cat err.txt)"
}
check_bad "missing file" "$TMP/does_not_exist.stl"
: >empty.stl
check_bad "empty file" empty.stl
printf 'this is not an STL file at all\n\x01\x02\x03 garbage\n' >garbage.stl
check_bad "garbage .stl" garbage.stl
check_bad "unknown format" part.json
echo "PASS"
