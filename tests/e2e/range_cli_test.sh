#!/usr/bin/env bash
# `csgfit range` end to end: object_b's view A becomes seed 002's five primitives with the
# paper's precedence graph, the .scad renders in OpenSCAD, two views go in one call; every bad
# input exits with status 2, one stderr line naming the problem, and no output file.
#
# usage: bash range_cli_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
e2e_need_benchmarks range
e2e_tmpdir
cd "$TMP" || exit 1

B=$BENCH/object_b_ortho.png
"$CLI" range "$B" -o ob.json --report --preview ob.png --time 20 >report.txt 2>err.txt ||
  fail "object_b: exit $? ($(cat err.txt))"
grep -q "There are 2 subobjects" report.txt || fail "object_b: report: $(head -3 report.txt)"
"$PY" - ob.json <<'PY' || fail "object_b: the precedence graph is not the paper's"
import json, sys
g = json.load(open(sys.argv[1]))["precedence_graph"]
nodes = g["nodes"]
assert len(nodes) == 5, len(nodes)
box = [n for n in nodes if n["kind"] == "box"]
cyl = sorted((n for n in nodes if n["kind"] == "cylinder"), key=lambda n: -n["dims"][0])
assert len(box) == 1 and box[0]["order"] == 1 and box[0]["sign"] == "positive"
big, top, small = cyl[0], cyl[1], cyl[2:]
assert big["sign"] == "negative" and big["order"] == 2 and abs(big["dims"][0] - 2.5) < 0.125
assert all(c["order"] == 3 and c["sign"] == "positive" and abs(c["dims"][0] - 0.5) < 0.025 for c in small)
assert top["subobject"] != box[0]["subobject"] and abs(top["dims"][0] - 0.75) < 0.0375
assert sorted(box[0]["dims"]) == sorted(box[0]["dims"]) and all(
    abs(a - b) < 0.05 * b for a, b in zip(sorted(box[0]["dims"]), [1.5, 3.0, 3.0]))
PY
[ -s ob.png ] || fail "object_b: no preview"

# The .scad renders, and the two views of one part go in one call.
"$CLI" range "$B" "$BENCH/object_b_pinhole.png" -o two.scad --time 20 -q || fail "two views: exit $?"
if command -v openscad >/dev/null 2>&1; then
  openscad -o two.stl two.scad >/dev/null 2>&1 || fail "two views: OpenSCAD cannot render the .scad"
  [ -s two.stl ] || fail "two views: OpenSCAD wrote no STL"
fi

# Bad inputs.
cp "$B" nosidecar.png
"$PY" - "$BENCH" <<'PY' || { echo "FAIL: could not write the fixtures" >&2; exit 1; }
import json, shutil, sys
from PIL import Image
bench = sys.argv[1]
side = json.load(open(bench + "/object_b_ortho.json"))
def variant(name, **change):
    shutil.copy(bench + "/object_b_ortho.png", name + ".png")
    s = dict(side, **change)
    json.dump(s, open(name + ".json", "w"))
m = [row[:] for row in side["camera_to_world"]]
m[0][0] *= 2
variant("stretched", camera_to_world=m)
variant("zeropixel", pixel_size=0.0)
variant("nanpixel", pixel_size=float("nan"))
# Another part: object_b's view moved far away.
far = [row[:] for row in side["camera_to_world"]]
far[0][3] += 1000
variant("far", camera_to_world=far)
Image.new("L", (192, 192), 128).save("grey8.png")
json.dump(side, open("grey8.json", "w"))
Image.new("I;16", (192, 192), 0).save("noreturn.png")
json.dump(side, open("noreturn.json", "w"))
PY

check_bad() {
  local what=$1 keyword=$2
  shift 2
  rm -f out.scad err.txt
  "$CLI" range "$@" -o out.scad --time 2 -q 2>err.txt >/dev/null
  local rc=$?
  [ $rc -eq 2 ] || fail "$what: exit status $rc, expected 2 ($(head -c 300 err.txt))"
  [ "$(wc -l <err.txt)" -eq 1 ] || fail "$what: expected one line on stderr, got: $(cat err.txt)"
  grep -qi -- "$keyword" err.txt || fail "$what: '$keyword' not in: $(cat err.txt)"
  [ ! -e out.scad ] || fail "$what: an output file was written"
}

check_bad "no sidecar, no intrinsics" "sidecar" nosidecar.png
check_bad "non-rigid camera_to_world" "orthonormal" stretched.png
check_bad "zero pixel size" "pixel" zeropixel.png
check_bad "NaN pixel size" "json" nanpixel.png
check_bad "8-bit PNG as depth" "8-bit" grey8.png
check_bad "no returns" "no return" noreturn.png
check_bad "views of different parts" "overlap" "$B" far.png
check_bad "missing file" "cannot open" missing.png
check_bad "unknown option" "--frobnicate" "$B" --frobnicate
check_bad "NaN --pixel-size" "pixel" nosidecar.png --pixel-size nan
check_bad "huge image (--max-size)" "limit" "$B" --max-size 100

e2e_finish "range_cli: ok"
