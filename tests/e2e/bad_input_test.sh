#!/usr/bin/env bash
# `csgfit image` on bad input: every case must exit non-zero with one line on stderr that names
# the problem, and must leave no output file (nor a temporary one) behind. Plus the positive
# edge cases next to them: an all-black image is one rectangle, an oversize image is accepted
# with --max-size.
#
# usage: bash bad_input_test.sh <path-to-csgfit-cli> [source-dir]
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 1 "$@"
e2e_tmpdir

# make_png PATH WIDTH HEIGHT PATTERN: an 8-bit grey PNG; PATTERN is black, white or half
# (left half black, right half white).
make_png() {
  "$PY" - "$@" <<'EOF'
import struct, sys, zlib

path, width, height, pattern = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
if pattern == "black":
    row = bytes(width)
elif pattern == "white":
    row = b"\xff" * width
else:
    row = bytes(width // 2) + b"\xff" * (width - width // 2)
raw = (b"\x00" + row) * height  # filter byte 0 (none) before every row

def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

with open(path, "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n")
    f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)))
    f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
    f.write(chunk(b"IEND", b""))
EOF
}

# expect_failure NAME KEYWORD OUTPUT ARGS...: runs `csgfit ARGS...` and checks the failure.
expect_failure() {
  local name=$1 keyword=$2 output=$3
  shift 3
  local err="$TMP/$name.stderr"
  timeout 120 "$CLI" "$@" >"$TMP/$name.stdout" 2>"$err"
  local rc=$?
  local lines
  lines=$(wc -l <"$err")
  if [ "$rc" -eq 0 ]; then
    fail "$name: exit status 0, expected a failure"
  elif [ "$rc" -eq 124 ]; then
    fail "$name: timed out"
  elif [ "$rc" -ge 128 ]; then
    fail "$name: killed by signal $((rc - 128))"
  fi
  if [ "$lines" -ne 1 ]; then
    fail "$name: expected one line on stderr, got $lines: $(head -c 500 "$err")"
  fi
  if ! grep -qiF -- "$keyword" "$err"; then
    fail "$name: stderr does not mention '$keyword': $(head -c 500 "$err")"
  fi
  if [ -e "$output" ]; then
    fail "$name: output '$output' exists after a failure"
  fi
  local left
  left=$(e2e_temp_files "$(dirname "$output")")
  [ -z "$left" ] || fail "$name: temporary file left behind: $left"
  echo "ok: $name: $(cat "$err")"
}

# expect_success NAME OUTPUT ARGS...
expect_success() {
  local name=$1 output=$2
  shift 2
  timeout 120 "$CLI" "$@" >"$TMP/$name.stdout" 2>"$TMP/$name.stderr"
  local rc=$?
  if [ "$rc" -ne 0 ]; then
    fail "$name: exit status $rc: $(head -c 500 "$TMP/$name.stderr")"
    return 1
  fi
  if [ ! -s "$output" ]; then
    fail "$name: no output '$output'"
    return 1
  fi
  echo "ok: $name"
}

out="$TMP/out.scad"

# Missing, unreadable and non-image inputs.
expect_failure missing "No such file" "$out" image "$TMP/missing.png" -o "$out" --time 1

mkdir "$TMP/folder.png"
expect_failure directory "directory" "$out" image "$TMP/folder.png" -o "$out" --time 1

: >"$TMP/empty.png"
expect_failure empty "empty" "$out" image "$TMP/empty.png" -o "$out" --time 1

make_png "$TMP/full.png" 64 64 half
size=$(stat -c %s "$TMP/full.png")
head -c $((size / 2)) "$TMP/full.png" >"$TMP/truncated.png"
expect_failure truncated_png "truncated" "$out" image "$TMP/truncated.png" -o "$out" --time 1

echo "this is a text file, not a picture" >"$TMP/notes.png"
expect_failure text_as_png "not an image" "$out" image "$TMP/notes.png" -o "$out" --time 1

# A header that declares 100000 x 100000 pixels must be refused from the header alone.
printf 'P5 100000 100000 255\n' >"$TMP/huge.pgm"
expect_failure huge_header "over the limit" "$out" image "$TMP/huge.pgm" -o "$out" --time 1

# Nothing to fit.
make_png "$TMP/white.png" 16 16 white
expect_failure all_white "no shape found" "$out" image "$TMP/white.png" -o "$out" --time 1

# Over the default limit of 4096 x 4096 pixels: refused, then accepted with --max-size.
make_png "$TMP/oversize.png" 4100 4100 half
expect_failure oversize "over the limit" "$out" image "$TMP/oversize.png" -o "$out" --time 1
if expect_success oversize_max_size "$out" image "$TMP/oversize.png" -o "$out" --time 1 \
    --max-size 64; then
  grep -q 'square(' "$out" || fail "oversize_max_size: no rectangle in $out"
fi
rm -f "$out"

# Bad options and outputs.
make_png "$TMP/black.png" 16 16 black
expect_failure unknown_option "bogus" "$out" image "$TMP/black.png" -o "$out" --time 1 --bogus
expect_failure unknown_extension "unknown output format" "$TMP/out.xyz" \
  image "$TMP/black.png" -o "$TMP/out.xyz" --time 1
expect_failure missing_output_folder "cannot write" "$TMP/nowhere/out.scad" \
  image "$TMP/black.png" -o "$TMP/nowhere/out.scad" --time 1

# The positive edge case: an all-black image is exactly one rectangle.
if expect_success all_black "$out" image "$TMP/black.png" -o "$out" --time 1; then
  squares=$(grep -o 'square(' "$out" | wc -l)
  [ "$squares" -eq 1 ] || fail "all_black: expected exactly one square( in $out, found $squares"
fi
left=$(e2e_temp_files "$TMP")
[ -z "$left" ] || fail "temporary files left behind: $left"

e2e_finish "all bad-input checks passed"
