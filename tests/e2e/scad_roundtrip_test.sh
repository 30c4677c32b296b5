#!/bin/bash
# OpenSCAD round trip through the CLI, independent of the search: hand-written and random JSON
# trees are exported with `csgfit export T.json -o T.scad`, rendered by OpenSCAD and sampled at
# pixel centres (scripts/scad_raster.py), and compared with the solver's own raster
# (`csgfit render T.json -o T.png`). They must agree on >= 99.5 % of the pixels, flat and
# extruded. Skipped (exit 0 with a message) when openscad is not installed.
#
# usage: bash scad_roundtrip_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
RASTER="$SRC/scripts/scad_raster.py"
MIN=0.995
e2e_need_tools openscad
e2e_tmpdir

# The hand-made tree of the brief: (rect - circle) + rotated ellipse + triangle +
# (circle & rotated rect), with a nested union, on a 96 x 80 canvas at 0.5 mm per pixel.
# Coordinates are model units (mm). $1 = thickness.
hand_tree() {
  cat <<EOF
{
 "schema": "csgfit/1", "dimension": 2, "units": "mm",
 "canvas": {"width_px": 96, "height_px": 80, "pixel_size": 0.5, "thickness": $1},
 "source": "roundtrip.png",
 "tree": {"op": "union", "children": [
   {"op": "difference", "children": [
     {"type": "rectangle", "cx": 15, "cy": 20, "w": 22, "h": 18, "angle": 0},
     {"type": "circle", "cx": 15, "cy": 20, "r": 4.65}]},
   {"op": "union", "children": [
     {"type": "ellipse", "cx": 35, "cy": 27.5, "rx": 8.75, "ry": 4.125, "angle": 35},
     {"type": "triangle", "cx": 24, "cy": 33, "w": 13, "h": 7.25, "angle": 10, "apex": 0.4}]},
   {"op": "intersection", "children": [
     {"type": "circle", "cx": 35, "cy": 11, "r": 7.6},
     {"type": "rectangle", "cx": 37, "cy": 12, "w": 11, "h": 15, "angle": 30}]}]},
 "stats": {"iou": 1, "primitives": 7},
 "alternatives": []
}
EOF
}

# Random trees with a fixed seed: $1 = seed, $2 = thickness.
random_tree() {
  "$PY" - "$1" "$2" <<'EOF'
import json, random, sys
rng = random.Random(int(sys.argv[1]))
W, H, S = 96, 80, 0.5

def prim():
    cx, cy = rng.uniform(0.2 * W, 0.8 * W) * S, rng.uniform(0.2 * H, 0.8 * H) * S
    size = lambda: rng.uniform(8, 40) * S
    kind = rng.choice(["rectangle", "circle", "ellipse", "triangle"])
    p = {"type": kind, "cx": cx, "cy": cy}
    if kind == "rectangle":
        p.update(w=size(), h=size(), angle=rng.uniform(0, 180))
    elif kind == "circle":
        p.update(r=size() / 2)
    elif kind == "ellipse":
        p.update(rx=size() / 2, ry=size() / 2, angle=rng.uniform(0, 180))
    else:
        p.update(w=size(), h=size(), angle=rng.uniform(0, 360), apex=rng.uniform(-1, 1))
    return p

def tree(depth):
    if depth == 0 or rng.random() < 0.3:
        return prim()
    op = rng.choice(["union", "union", "difference", "intersection"])
    return {"op": op, "children": [tree(depth - 1) for _ in range(rng.randint(2, 3))]}

# The first child of the root is a union, so the tree always covers something.
root = {"op": "union", "children": [tree(2), {"op": "difference",
        "children": [tree(1), tree(1)]}]}
print(json.dumps({"schema": "csgfit/1", "dimension": 2, "units": "mm",
                  "canvas": {"width_px": W, "height_px": H, "pixel_size": S,
                             "thickness": float(sys.argv[2])},
                  "source": "random_%s.png" % sys.argv[1], "tree": root}))
EOF
}

# Exports $1.json, renders both ways, compares.
check() {
  local name=$1
  if ! "$CLI" export "$TMP/$name.json" -o "$TMP/$name.scad" 2>"$TMP/$name.err"; then
    fail "$name: csgfit export: $(cat "$TMP/$name.err")"
    return
  fi
  if ! "$CLI" render "$TMP/$name.json" -o "$TMP/$name.png" 2>"$TMP/$name.err"; then
    fail "$name: csgfit render: $(cat "$TMP/$name.err")"
    return
  fi
  local out
  out=$("$PY" "$RASTER" "$TMP/$name.scad" --width 96 --height 80 --pixel-size 0.5 \
        --compare "$TMP/$name.png" --min-agreement "$MIN" 2>&1)
  local rc=$?
  printf '%-12s %s\n' "$name" "$out"
  if [ $rc -ne 0 ]; then
    fail "$name: OpenSCAD's rendering agrees with the solver's raster on less than $MIN"
  fi
}

hand_tree 0 >"$TMP/hand.json"
check hand
hand_tree 3 >"$TMP/hand_3d.json"
check hand_3d
grep -q "linear_extrude(height = thickness)" "$TMP/hand_3d.scad" || fail "hand_3d: no linear_extrude"
# The nested union is flattened into the top-level one.
[ "$(grep -c 'union()' "$TMP/hand.scad")" = 1 ] || fail "hand: nested unions not flattened"

for seed in 1 2 3 4 5 6; do
  thickness=0
  [ "$seed" = 4 ] && thickness=2.5
  random_tree "$seed" "$thickness" >"$TMP/random_$seed.json"
  check "random_$seed"
done

# Bad input: a one-line error, exit status 2, and no output file.
sed 's/"r": 4.65/"r": -1/' "$TMP/hand.json" >"$TMP/bad.json"
"$CLI" export "$TMP/bad.json" -o "$TMP/bad.scad" 2>"$TMP/bad.err"
rc=$?
[ $rc -eq 2 ] || fail "bad.json: exit status $rc, expected 2"
[ "$(wc -l <"$TMP/bad.err")" -eq 1 ] || fail "bad.json: error is not one line: $(cat "$TMP/bad.err")"
[ ! -e "$TMP/bad.scad" ] || fail "bad.json: a .scad was written anyway"
echo "bad input: $(cat "$TMP/bad.err")"

e2e_finish "OK: OpenSCAD round trip agrees on >= $MIN of the pixels"
