#!/bin/bash
# STEP output end to end (issue 4): a fitted part's .step opens in FreeCAD (headless) as one valid
# solid whose volume is within 1 % of OpenSCAD's rendering of the .scad of the same tree (the
# .scad has $fn = 64 facets, the STEP exact surfaces); then the 2D path and bad inputs.
# Both files come from one fit: `csgfit mesh -o .json`, then `csgfit export` to .scad and .step
# (two fits under a time limit need not give the same tree).
# Usage: step_export_test.sh CSGFIT_CLI SOURCE_DIR
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
# The first failure ends this test: each step works on the files of the one before.
fail() { echo "FAIL: $*"; exit 1; }

# A csgfit built without STEP (CSGFIT_BUILD_OCCT=OFF) says so in its --version line; it must
# refuse .step / .stp before any fit (exit 2, one line, no file), and the rest of this test is
# skipped.
if "$CLI" --version | grep -q "without STEP"; then
  e2e_tmpdir
  refuses_step() {
    local start rc
    start=$(date +%s)
    "$CLI" "$@" -o "$TMP/x.STP" --time 30 -q 2>"$TMP/err.txt"
    rc=$?
    [ $rc -eq 2 ] || fail "$1 without STEP support: exit $rc, expected 2"
    { [ "$(wc -l <"$TMP/err.txt")" -eq 1 ] && grep -q "without STEP support" "$TMP/err.txt"; } ||
      { cat "$TMP/err.txt"; fail "$1 without STEP support: not one line that says so"; }
    [ ! -e "$TMP/x.STP" ] || fail "$1 without STEP support: a file was written"
    [ $(( $(date +%s) - start )) -lt 20 ] || fail "$1 without STEP support: refused after the fit"
  }
  $PY "$SRC/tests/fixtures/holed_block_stl.py" "$TMP/part.stl" || fail "could not write the test mesh"
  refuses_step image "$SRC/examples/bracket.png" --thickness 3
  refuses_step mesh "$TMP/part.stl"
  e2e_skip "SKIP: this csgfit was built without STEP support ($(cat "$TMP/err.txt"))"
fi

e2e_need_tools openscad
[ -d /usr/lib/freecad-python3/lib ] || e2e_skip "SKIP: FreeCAD is not installed"
e2e_tmpdir
cd "$TMP" || exit 1

# FreeCAD reads the STEP; the OpenSCAD STL's volume is summed from its facets (divergence
# theorem), and its pieces are its facets connected through shared vertices. The STEP must be
# one solid per piece: one solid for a part in one piece (a fitted tree may leave a disjoint
# piece, which OpenSCAD renders too; slivers under 1e-6 of the volume are not pieces; pieces that
# touch only through T-junctions may be one solid).
cat >compare.py <<'PYEOF'
import sys
sys.path.append('/usr/lib/freecad-python3/lib')
import FreeCAD, Part
step, stl, label = sys.argv[1], sys.argv[2], sys.argv[3]
shape = Part.read(step)
assert shape.isValid(), "%s: FreeCAD says the STEP shape is not valid" % label
assert all(s.isValid() for s in shape.Solids), "%s: an invalid solid" % label
keys, v = {}, []
for line in open(stl):
    w = line.split()
    if w and w[0] == 'vertex':
        v.append(tuple(map(float, w[1:4])))
parent = list(range(len(v)))
def find(i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i
for i, p in enumerate(v):
    j = keys.setdefault(p, i)
    parent[find(i)] = find(j)
for i in range(0, len(v), 3):
    parent[find(i + 1)] = find(i)
    parent[find(i + 2)] = find(i)
piece = {}
for i in range(0, len(v), 3):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = v[i:i + 3]
    t = (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6
    piece[find(i)] = piece.get(find(i), 0.0) + t
scad = sum(piece.values())
big = [r for r, p in piece.items() if p > 1e-6 * scad]
pieces = len(big)
# Pieces joined only through a T-junction (a vertex of one on an edge or face of the other) are
# one solid in exact geometry but share no STL vertex: pieces whose boxes touch (within eps) are grouped,
# and the STEP may have as few solids as there are such groups, as many as there are pieces.
box = {}
for i in range(0, len(v), 3):
    r = find(i)
    for p in v[i:i + 3]:
        lo, hi = box.get(r, (list(p), list(p)))
        box[r] = ([min(a, b) for a, b in zip(lo, p)], [max(a, b) for a, b in zip(hi, p)])
group = {r: r for r in big}
def gfind(r):
    while group[r] != r:
        r = group[r]
    return r
# The tolerance is that of OpenSCAD's polygons, not of rounding: where a face is (nearly)
# tangent to a round primitive, the exact circle in the STEP can close a gap that the 64-gon
# leaves open (model 011: a 0.005-thick plate beside a cylinder, 0.008 from it in the STL, one
# solid with it in the STEP).
eps = 1e-3 * max(max(h - l for l, h in zip(*b)) for b in box.values())
for x in big:
    for y in big:
        (lx, hx), (ly, hy) = box[x], box[y]
        if x < y and all(lx[k] <= hy[k] + eps and ly[k] <= hx[k] + eps for k in range(3)):
            group[gfind(x)] = gfind(y)
groups = len(set(gfind(r) for r in big))
step_v = shape.Volume
rel = abs(step_v - scad) / scad
print("%s: STEP %d solid(s), volume %.6g (FreeCAD); OpenSCAD %d piece(s), %.6g; difference %.4f %%"
      % (label, len(shape.Solids), step_v, pieces, scad, 100 * rel))
assert groups <= len(shape.Solids) <= pieces, "%s: %d solids for %d pieces (%d touching groups)" % (
    label, len(shape.Solids), pieces, groups)
assert rel <= 0.01, "%s: STEP and .scad volumes differ by %.3f %% > 1 %%" % (label, 100 * rel)
PYEOF

# A 40 x 30 x 12 block with a through hole of radius 7, as a closed, outward-oriented mesh.
$PY "$SRC/tests/fixtures/holed_block_stl.py" part.stl || fail "could not write the test mesh"

check_model() {
  local label=$1 mesh=$2
  # No ellipsoids: OpenCASCADE can write a boolean face on its B-spline sphere that does not
  # read back (csgfit then refuses the .step, tested below); every other kind must round-trip.
  "$CLI" mesh "$mesh" -o "$label.json" --time 5 --threads 1 --seed 1 -q \
    --primitives box,sphere,cylinder,cone,prism || fail "$label: csgfit mesh exited $?"
  "$CLI" export "$label.json" -o "$label.scad" || fail "$label: export to .scad exited $?"
  "$CLI" export "$label.json" -o "$label.step" || fail "$label: export to .step exited $?"
  grep -q "segments = 64;" "$label.scad" || fail "$label: the .scad does not have the mesh command's \$fn = 64"
  openscad -o "$label.stl" "$label.scad" >openscad.log 2>&1 || { cat openscad.log; fail "$label: OpenSCAD could not render"; }
  $PY compare.py "$label.step" "$label.stl" "$label" || fail "$label: STEP check failed"
}
check_model part part.stl
MODEL011="$SRC/../shared/benchmarks/3d/inversecsg/011/csg_high_res.off"
if [ -f "$MODEL011" ]; then
  check_model model011 "$MODEL011"
else
  echo "SKIP model 011: $MODEL011 is not present"
fi

# csgfit mesh writes .step directly too.
"$CLI" mesh part.stl -o direct.step --time 2 --threads 1 -q || fail "csgfit mesh -o .step exited $?"
$PY -c "
import sys; sys.path.append('/usr/lib/freecad-python3/lib')
import FreeCAD, Part
s = Part.read('direct.step')
assert s.isValid() and len(s.Solids) >= 1, (s.isValid(), len(s.Solids))
# The part is 40 x 30 x 12 less a hole of radius 7: 14400 - 1847 = 12553 mm^3; the fit is close.
assert abs(s.Volume - 12553) < 0.05 * 12553, s.Volume
print('mesh -o .step: valid, volume %.1f' % s.Volume)
" || fail "csgfit mesh -o .step: not the part"

# 2D: a bitmap fit extruded by --thickness; the .scad's linear_extrude and the STEP agree.
"$CLI" image "$SRC/examples/bracket.png" -o bracket.json --time 2 --threads 1 -q --thickness 3 --pixel-size 0.5 \
  || fail "csgfit image exited $?"
"$CLI" export bracket.json -o bracket.scad || fail "2D export to .scad exited $?"
"$CLI" export bracket.json -o bracket.step || fail "2D export to .step exited $?"
openscad -o bracket.stl bracket.scad >openscad.log 2>&1 || { cat openscad.log; fail "OpenSCAD could not render the 2D .scad"; }
$PY compare.py bracket.step bracket.stl bracket || fail "2D STEP check failed"

# Bad inputs: exit 2, one line on stderr, no output file.
check_bad() {
  local what=$1 out=$2 words=$3; shift 3
  rm -f "$out"
  "$@" 2>err.txt
  local rc=$?
  [ $rc -eq 2 ] || fail "$what: exit $rc, expected 2"
  [ "$(wc -l <err.txt)" -eq 1 ] || { cat err.txt; fail "$what: expected one line on stderr"; }
  grep -q "$words" err.txt || { cat err.txt; fail "$what: the message does not say '$words'"; }
  [ ! -e "$out" ] || fail "$what: an output file was written"
  echo "$what: $(cat err.txt)"
}
check_bad "unwritable path" "$TMP/no/such/dir/x.step" "does not exist" \
  "$CLI" mesh part.stl -o "$TMP/no/such/dir/x.step" --time 1 -q
START=$(date +%s)
check_bad "2D without thickness" flat.step "STEP needs a thickness" \
  "$CLI" image "$SRC/examples/bracket.png" -o flat.step --time 30 -q
# Refused before the 30 s fit, not after it (a generous bound: no timing is measured otherwise).
[ $(( $(date +%s) - START )) -lt 20 ] || fail "2D without thickness: refused only after the fit"
"$CLI" image "$SRC/examples/bracket.png" -o flat.json --time 1 --threads 1 -q || fail "csgfit image (flat) exited $?"
check_bad "2D export without thickness" flat.step "STEP needs a thickness" "$CLI" export flat.json -o flat.step
check_bad "3D export to .json" again.json "exports to .scad or .step" "$CLI" export part.json -o again.json
# A cylinder minus a turned ellipsoid (from a fit of model 011) whose STEP does not read back as
# the solid OpenCASCADE built: refused with one line, nothing written.
cat > ell.json <<'JSONEOF'
{"schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "ell",
 "tree": {"op": "difference", "children": [
  {"type": "cylinder", "center": [-0.000623782899082797, 0.0002591971542785448, 4.742123893252386],
   "rotation": [1, 0, 0, 0], "r": 0.41901160188279896, "h": 0.508894562100317},
  {"type": "ellipsoid", "center": [0, 0, 4.890597031622912],
   "rotation": [0.024520743581762938, -0.7166784897800258, 0.02640445977346765, 0.6964721673727461],
   "radii": [0.438016618813746, 0.23022781328939262, 0.2509453476431168]}]}}
JSONEOF
check_bad "STEP that does not read back" ell.step "does not read back" "$CLI" export ell.json -o ell.step
echo "PASS"
