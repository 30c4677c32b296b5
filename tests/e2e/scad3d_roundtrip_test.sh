#!/bin/bash
# OpenSCAD round trip of the 3D .scad writer, independent of any search: the C++ test
# ScadWriter3DRoundTrip.DumpFilesForOpenScad writes random 3D trees (each primitive kind alone,
# then small trees under union, difference and intersection, rotated) as .scad, with the
# solver's own voxelisation of each as .npy (64^3 voxels of 0.5 units; the polygonal cylinder
# and cone among them, drawn as their own $fn-gons, and the rounded box, drawn by offset());
# ScadSweepRoundTrip.DumpFilesForOpenScad writes trees that are sweeps (hand-made parts, a
# rounded plate with a slot among them, and random ones, rounded boxes among their prisms, a new
# seed each run), written as linear_extrude and rotate_extrude of their profiles. OpenSCAD
# renders each .scad to STL; scripts/stl_voxelize.py voxelises the STL by ray parity along z at
# the voxel centres; the two must agree on >= 99 % of the voxels in the bounding box of either
# shape, with IoU >= 0.98. Skipped (exit 0 with a message) when openscad is not installed.
#
# usage: bash scad3d_roundtrip_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
VOXELIZE="$SRC/scripts/stl_voxelize.py"
TESTS="$(dirname "$CLI")/csgfit_tests"
MIN_AGREEMENT=0.99
MIN_IOU=0.98

e2e_need_tools openscad
if [ ! -x "$TESTS" ]; then
  echo "FAIL: the C++ test binary $TESTS (which writes the trees) is missing"
  exit 1
fi
e2e_tmpdir

if ! CSGFIT_SCAD3D_DUMP="$TMP" "$TESTS" --gtest_filter='ScadWriter3DRoundTrip.*:ScadSweepRoundTrip.*' \
    >"$TMP/dump.log" 2>&1; then
  cat "$TMP/dump.log"
  echo "FAIL: writing the trees failed"
  exit 1
fi

grep -m1 'CSGFIT_TEST_SEED' "$TMP/dump.log"
count=0
for scad in "$TMP"/tree_*.scad "$TMP"/sweep_*.scad; do
  name=$(basename "$scad" .scad)
  count=$((count + 1))
  if ! openscad -o "$TMP/$name.stl" "$scad" >"$TMP/$name.log" 2>&1; then
    fail "$name: OpenSCAD could not render it: $(grep -m1 -E 'ERROR|WARNING' "$TMP/$name.log")"
    continue
  fi
  if grep -q -E "^(ERROR|WARNING)" "$TMP/$name.log"; then
    fail "$name: OpenSCAD complained: $(grep -m1 -E '^(ERROR|WARNING)' "$TMP/$name.log")"
  fi
  out=$("$PY" "$VOXELIZE" "$TMP/$name.stl" --grid 64 64 64 --origin 0 0 0 --size 0.5 \
        --compare "$TMP/$name.npy" --min-agreement "$MIN_AGREEMENT" 2>&1)
  rc=$?
  printf '%-8s %s   %s\n' "$name" "$out" "$(grep -m1 '^// Fit:' "$scad" | cut -c9-)"
  if [ $rc -ne 0 ]; then
    fail "$name: OpenSCAD's rendering agrees with the solver's voxels on less than $MIN_AGREEMENT"
    continue
  fi
  iou=$(echo "$out" | sed -n 's/.*IoU \([0-9.]*\).*/\1/p')
  if ! "$PY" -c "import sys; sys.exit(0 if float('$iou') >= $MIN_IOU else 1)"; then
    fail "$name: IoU $iou < $MIN_IOU"
  fi
done
[ "$count" -ge 33 ] || fail "expected 33 trees, found $count"

e2e_finish "OK: $count 3D trees, OpenSCAD agrees with the solver's voxels on >= $MIN_AGREEMENT (IoU >= $MIN_IOU)"
