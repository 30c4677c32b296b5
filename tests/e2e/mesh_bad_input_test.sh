#!/usr/bin/env bash
# `csgfit mesh` on bad meshes and voxel grids: every case must exit with status 2, print one
# line on stderr that names the problem, and leave no output file. A header that declares 10^12
# faces must fail at once. An open mesh is accepted with a one-line warning.
#
# usage: bash mesh_bad_input_test.sh <path-to-csgfit-cli> [source-dir]
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 1 "$@"
e2e_tmpdir
cd "$TMP" || exit 1

"$PY" - <<'EOF' || { echo "FAIL: could not write the fixtures" >&2; exit 1; }
import struct

V = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
T = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
     (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]

def binary_stl(tris, declared=None):
    out = b"solid binary".ljust(80, b" ") + struct.pack("<I", len(tris) if declared is None else declared)
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0)
        for v in t:
            out += struct.pack("<3f", *V[v])
        out += b"\0\0"
    return out

def ascii_stl(tris):
    s = "solid cube\n"
    for t in tris:
        s += "facet normal 0 0 0\nouter loop\n"
        s += "".join("vertex %g %g %g\n" % V[v] for v in t)
        s += "endloop\nendfacet\n"
    return s + "endsolid cube\n"

def off(tris):
    return "OFF\n%d %d 0\n" % (len(V), len(tris)) + "".join("%g %g %g\n" % v for v in V) + \
        "".join("3 %d %d %d\n" % t for t in tris)

def ply(tris):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n" % (len(V), len(tris))).encode()
    body = b"".join(struct.pack("<3f", *v) for v in V)
    body += b"".join(struct.pack("<B3i", 3, *t) for t in tris)
    return head + body

def npy(descr, shape, data):
    d = "{'descr': '%s', 'fortran_order': False, 'shape': %s, }" % (descr, shape)
    d += " " * ((64 - (10 + len(d) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(d)) + d.encode() + data

def write(name, data):
    with open(name, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)

write("empty.stl", b"")
write("cut_binary.stl", binary_stl(T)[:-70])
write("cut_ascii.stl", ascii_stl(T)[:400])
write("cut.ply", ply(T)[:-30])
write("cut.off", off(T).rsplit("3 ", 2)[0])
write("image.stl", b"\x89PNG\r\n\x1a\n" + b"\0\0\0\rIHDR" + bytes(200))
write("nan.obj", "".join("v %g %g %g\n" % v for v in V).replace("v 1 0 0", "v nan 0 0") +
      "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in T))
write("index.off", off(T).replace("3 1 7 5", "3 1 7 50"))
write("points.obj", "".join("v %g %g %g\n" % v for v in V))
write("huge.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      b"property float y\nproperty float z\nelement face 1000000000000\n"
      b"property list uchar int vertex_indices\nend_header\n")
write("huge.stl", binary_stl(T, declared=0xFFFFFFFF))
write("flat.npy", npy("|b1", "(8, 8)", bytes(64)))
write("complex.npy", npy("<c16", "(2, 2, 2)", bytes(128)))
write("cut.npy", npy("|u1", "(4, 4, 4)", bytes(40)))
write("cut.binvox", b"#binvox 1\ndim 4 4 4\ntranslate 0 0 0\nscale 1\ndata\n\x00\x10\x01\x05")
write("open.obj", "".join("v %g %g %g\n" % v for v in V) +
      "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in T[:2] + T[4:]))
EOF

# check_bad DESCRIPTION INPUT KEYWORD: exit status 2, one stderr line containing KEYWORD, no
# output file.
check_bad() {
  local what=$1 input=$2 keyword=$3
  rm -f out.scad err.txt
  "$CLI" mesh "$input" -o out.scad --time 1 --threads 1 -q 2>err.txt >/dev/null
  local rc=$?
  [ $rc -eq 2 ] || fail "$what: exit status $rc, expected 2 ($(head -c 300 err.txt))"
  [ "$(wc -l <err.txt)" -eq 1 ] || fail "$what: expected one line on stderr, got: $(cat err.txt)"
  grep -q -- "$keyword" err.txt || fail "$what: '$keyword' not in: $(cat err.txt)"
  [ ! -e out.scad ] || fail "$what: an output file was written"
}

check_bad "missing file" missing.stl "cannot open"
check_bad "empty file" empty.stl "empty"
check_bad "truncated binary STL" cut_binary.stl "truncated"
check_bad "truncated ASCII STL" cut_ascii.stl "truncated"
check_bad "truncated PLY" cut.ply "truncated"
check_bad "truncated OFF" cut.off "truncated"
check_bad "PNG renamed .stl" image.stl "PNG"
check_bad "NaN coordinate" nan.obj "non-finite"
check_bad "face index out of range" index.off "out of range"
check_bad "no triangles" points.obj "no triangles"
check_bad "2-D .npy" flat.npy "3-D"
check_bad "complex .npy" complex.npy "not supported"
check_bad "truncated .npy" cut.npy "truncated"
check_bad "truncated binvox" cut.binvox "truncated"

# Absurd declared counts are refused from the header, at once.
for input in huge.ply huge.stl; do
  start=$(date +%s%N)
  check_bad "$input (declares billions of faces)" "$input" "limit"
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  [ "$ms" -lt 3000 ] || fail "$input took $ms ms to refuse"
done

# An open mesh (a cube without its top) is fitted, with one warning line that says why.
rm -f out.scad err.txt
"$CLI" mesh open.obj -o out.scad --time 1 --threads 1 2>err.txt >/dev/null
rc=$?
[ $rc -eq 0 ] || fail "open mesh: exit status $rc ($(head -c 300 err.txt))"
[ -s out.scad ] || fail "open mesh: no .scad written"
grep -q "warning: .*open: 4 boundary edges" err.txt || fail "open mesh: no warning in: $(cat err.txt)"
[ "$(grep -c warning err.txt)" -eq 1 ] || fail "open mesh: expected one warning line: $(cat err.txt)"

e2e_finish "mesh bad input: all cases passed"
