#!/usr/bin/env bash
# The hostile-but-realistic inputs of the hardening issue, one check each: every refusal is exit
# status 2 with one printable line on stderr, leaves no output (nor a temporary file) behind,
# and comes before any work (a --time 60 run that is refused must not take the minute), with
# peak memory bounded where the input claims a huge size. The top-down BMP must work.
#
# usage: bash hardening_test.sh <path-to-csgfit-cli> [source-dir]
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 1 "$@"
e2e_tmpdir
cd "$TMP" || exit 1
mkdir out

# run_measured NAME ARGS...: runs the CLI, leaving NAME.err, NAME.rc, NAME.sec and NAME.kb
# (peak resident memory of the child, from getrusage).
run_measured() {
  local name=$1
  shift
  "$PY" - "$name" "$CLI" "$@" <<'EOF'
import resource, subprocess, sys, time
name, cmd = sys.argv[1], sys.argv[2:]
start = time.monotonic()
try:
    rc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=open(name + ".err", "wb"),
                        timeout=300).returncode
except subprocess.TimeoutExpired:
    rc = 124
open(name + ".rc", "w").write(str(rc))
open(name + ".sec", "w").write("%.2f" % (time.monotonic() - start))
open(name + ".kb", "w").write(str(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss))
EOF
}

# refused NAME KEYWORD MAX_SECONDS MAX_MB ARGS...: exit 2, one printable line naming KEYWORD,
# within MAX_SECONDS and MAX_MB, and nothing in out/.
refused() {
  local name=$1 keyword=$2 max_sec=$3 max_mb=$4
  shift 4
  run_measured "$name" "$@"
  local rc lines sec kb
  rc=$(cat "$name.rc") sec=$(cat "$name.sec") kb=$(cat "$name.kb")
  lines=$(wc -l <"$name.err")
  [ "$rc" -eq 2 ] || fail "$name: exit status $rc, expected 2: $(head -c 300 "$name.err")"
  [ "$lines" -eq 1 ] || fail "$name: $lines lines on stderr: $(head -c 600 "$name.err")"
  grep -qiF -- "$keyword" "$name.err" || fail "$name: no '$keyword' in: $(head -c 300 "$name.err")"
  if LC_ALL=C grep -q '[^ -~]' "$name.err"; then
    fail "$name: unprintable bytes on stderr: $(od -c "$name.err" | head -5)"
  fi
  "$PY" -c "import sys; sys.exit(not float('$sec') <= $max_sec)" ||
    fail "$name: took $sec s (bound $max_sec s)"
  [ "$kb" -le $((max_mb * 1024)) ] || fail "$name: peak memory $((kb / 1024)) MB (bound $max_mb MB)"
  [ -z "$(ls -A out)" ] || fail "$name: left in the output folder: $(ls -A out)"
  rm -f out/* out/.[!.]* 2>/dev/null
  echo "ok: $name ($sec s, $((kb / 1024)) MB): $(cat "$name.err")"
}

# Inputs: a bracket-like PNG, a closed cube, a fitted 2D result and copies of it with absurd
# canvases, top-down and bottom-up BMPs of one picture, and the broken files.
"$PY" - <<'EOF'
import json, struct, zlib

def png(path, w, h, black):
    rows = b"".join(b"\x00" + bytes(0 if black(x, y) else 255 for x in range(w)) for y in range(h))
    chunk = lambda k, d: struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d))
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))

shape = lambda x, y: 8 <= x < 40 and 6 <= y < 26 and not (20 <= x < 28 and 12 <= y < 20)
png("part.png", 48, 32, shape)

def bmp(path, w, h, black, top_down):
    row = (w + 3) // 4 * 4
    order = range(h) if top_down else range(h - 1, -1, -1)
    pixels = b"".join(bytes(0 if black(x, y) else 255 for x in range(w)) + bytes(row - w) for y in order)
    palette = b"".join(bytes((g, g, g, 0)) for g in range(256))
    offset = 14 + 40 + len(palette)
    head = b"BM" + struct.pack("<IHHI", offset + len(pixels), 0, 0, offset)
    info = struct.pack("<IiiHHIIiiII", 40, w, -h if top_down else h, 1, 8, 0, len(pixels), 2835, 2835, 256, 0)
    open(path, "wb").write(head + info + palette + pixels)

bmp("top_down.bmp", 48, 32, shape, True)
bmp("bottom_up.bmp", 48, 32, shape, False)

def obj(path, s):
    v = [(x * s, y * s, z * s) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    f = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
         (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    open(path, "w").write("".join("v %r %r %r\n" % p for p in v) +
                          "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in f))

obj("cube.obj", 10)
obj("cube_1e307.obj", 1e307)
obj("cube_1e-300.obj", 1e-300)
# A face that names vertex 9 of 8: the count must read "8 vertices".
open("bad_index.obj", "w").write(open("cube.obj").read() + "f 1 2 9\n")
open("quad.stl", "w").write("solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                            "vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid q\n")
# Terminal escape codes and invalid UTF-8 in a PLY header.
# The reader quotes the unknown keyword, which must reach the terminal as printable text.
open("escape.ply", "wb").write(b"ply\nformat ascii 1.0\nelement vertex 3\n"
                               b"\x1b[31mred\x1b[2J\xff\xfe float x\nend_header\n0 0 0\n")
EOF
"$CLI" image part.png -o result.json --time 1 -q || fail "setup: could not fit part.png"
"$PY" - <<'EOF'
import json
doc = json.load(open("result.json"))
sizes = {"canvas_huge": (100000, 100000), "canvas_zero": (0, 0), "canvas_large": (30000, 30000)}
for name, (w, h) in sizes.items():
    doc["canvas"]["width_px"], doc["canvas"]["height_px"] = w, h
    json.dump(doc, open(name + ".json", "w"))
EOF
truncate -s 1G sparse.obj

# Rasters and canvases.
refused render_huge_canvas "canvas" 10 200 render canvas_huge.json -o out/r.png
refused render_zero_canvas "canvas" 10 200 render canvas_zero.json -o out/r.png
refused render_jpg "png" 10 200 render result.json -o out/r.jpg
refused raster_txt "png" 10 200 image part.png -o out/o.json --time 60 --raster out/r.txt

# Threads and memory.
refused threads_100000 "--threads" 10 200 mesh cube.obj -o out/o.json --time 60 --threads 100000
refused threads_int_max "--threads" 10 200 mesh cube.obj -o out/o.json --time 60 --threads 2147483647
refused max_memory_tiny "--max-memory" 10 200 mesh cube.obj -o out/o.json --max-memory 1K
refused max_memory_budget "memory budget" 10 200 render canvas_large.json -o out/r.png --max-memory 64M
run_measured threads_256 mesh cube.obj -o out/t.json --time 2 --threads 256 -q
[ "$(cat threads_256.rc)" -eq 0 ] || fail "threads_256: exit $(cat threads_256.rc): $(cat threads_256.err)"
[ "$(cat threads_256.kb)" -le $((1024 * 1024)) ] ||
  fail "threads_256: peak memory $(($(cat threads_256.kb) / 1024)) MB, over 1 GB"
echo "ok: threads_256 ($(cat threads_256.sec) s, $(($(cat threads_256.kb) / 1024)) MB)"
rm -f out/t.json

# Outputs: nothing is kept when another output, or the output's folder, fails.
refused preview_unwritable "/proc/p.png" 10 200 image part.png -o out/o.json --time 1 --preview /proc/p.png
refused output_unwritable "/proc/o.json" 10 200 image part.png -o /proc/o.json --time 60

# FreeCAD saves through a temporary file too (tests/cpp/output_batch_test.cpp: the batch of
# outputs); the document keeps OUT's name.
if command -v freecadcmd >/dev/null 2>&1; then
  if "$CLI" image part.png -o out/part.FCStd --time 1 -q; then
    label=$("$PY" -c "import re, sys, zipfile; d = zipfile.ZipFile(sys.argv[1]).read('Document.xml').decode()
print(re.search(r'name=\"Label\"[^>]*>\\s*<String value=\"([^\"]*)\"', d).group(1))" out/part.FCStd)
    [ "$label" = "part" ] || fail "fcstd_label: the document is labelled '$label', not 'part'"
    echo "ok: fcstd_label"
  else
    fail "fcstd_label: could not write out/part.FCStd"
  fi
  rm -f out/part.FCStd
fi

# Numbers: checked up front, one short line.
refused k_nan "--k" 10 200 image part.png -o out/o.json --time 60 --k nan
refused pixel_size_nan "--pixel-size" 10 200 image part.png -o out/o.json --time 60 --pixel-size nan
refused pixel_size_huge "--pixel-size" 10 200 image part.png -o out/o.json --time 60 --pixel-size 1e300
refused thickness_nan "--thickness" 10 200 image part.png -o out/o.scad --time 60 --thickness nan
refused time_negative "--time" 10 200 image part.png -o out/o.json --time -1
[ "$(wc -c <time_negative.err)" -le 120 ] || fail "time_negative: message longer than 120 bytes"
refused seed_negative "--seed" 10 200 image part.png -o out/o.json --time 60 --seed -1
refused range_fx_nan "--fx" 10 200 range part.png -o out/o.json --fx nan

# Files: their bytes never reach the terminal raw; sizes outside what can be fitted are named.
refused ply_escapes "unknown keyword" 10 200 mesh escape.ply -o out/o.json --time 60
refused quad_facet "no solid" 30 500 mesh quad.stl -o out/o.json --time 2
refused cube_1e307 "units across" 10 200 mesh cube_1e307.obj -o out/o.json --time 60
refused cube_1e-300 "units across" 10 200 mesh cube_1e-300.obj -o out/o.json --time 60
refused obj_vertex_count "8 vertices" 10 200 mesh bad_index.obj -o out/o.json --time 60
refused sparse_obj "binary data" 10 200 mesh sparse.obj -o out/o.json --time 60

# The valid top-down BMP reads as the same picture as its bottom-up twin.
if "$CLI" image top_down.bmp -o out/td.json --time 1 -q --raster out/td.png &&
   "$CLI" image bottom_up.bmp -o out/bu.json --time 1 -q --raster out/bu.png; then
  cmp -s out/td.png out/bu.png || fail "top_down_bmp: its raster differs from the bottom-up BMP's"
  echo "ok: top_down_bmp"
else
  fail "top_down_bmp: refused"
fi
left=$(e2e_temp_files out)
[ -z "$left" ] || fail "temporary files left behind: $left"

e2e_finish "all hardening checks passed"
