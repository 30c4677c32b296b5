#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (docs/FUZZING.md):
#   scripts/fuzz.sh TARGET SECONDS [RUNS]   one target (e.g. stl, or fuzz_stl), for SECONDS
#                                           (0 = no limit) or RUNS executions, whichever first
#   scripts/fuzz.sh all SECONDS [RUNS]      every target, two at a time (CSGFIT_FUZZ_JOBS)
#   scripts/fuzz.sh list                    the targets
# Builds the fuzz tree in ${CSGFIT_FUZZ_BUILD_DIR:-build-fuzz} first (clang-14, ASan + UBSan,
# only what the targets need) unless that folder is already configured with CSGFIT_FUZZ=ON (CI
# passes its sanitized build). Each run works on a scratch copy of fuzz/corpus/TARGET, so the
# repository's corpus grows only by deliberate commits; crashing inputs are kept in
# ${CSGFIT_FUZZ_OUT:-BUILD/fuzz-out}/TARGET/. Prints runs, exec/s and crashes per target; exits
# 1 if any target crashed (an exception other than InputError, a sanitizer report, a leak, a
# timeout or an out-of-memory).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CSGFIT_FUZZ_BUILD_DIR:-$repo/build-fuzz}"
case "$build" in /*) ;; *) build="$repo/$build" ;; esac
out="${CSGFIT_FUZZ_OUT:-$build/fuzz-out}"
jobs="${CSGFIT_FUZZ_JOBS:-2}"

all_targets() {
  sed -n '/^set(CSGFIT_FUZZ_TARGETS/,/)/p' "$repo/fuzz/CMakeLists.txt" |
    sed -e 's/set(CSGFIT_FUZZ_TARGETS//' -e 's/)//' | tr -s ' \n' '\n' | grep -v '^$'
}

usage() {
  echo "usage: scripts/fuzz.sh TARGET|all SECONDS [RUNS]   (targets: $(all_targets | tr '\n' ' '))" >&2
  exit 2
}

build_targets() {  # the cmake targets to build
  if [ -f "$build/CMakeCache.txt" ]; then
    if ! grep -q '^CSGFIT_FUZZ:BOOL=ON' "$build/CMakeCache.txt"; then
      echo "fuzz: $build is configured without CSGFIT_FUZZ=ON; set CSGFIT_FUZZ_BUILD_DIR to a fuzz build" >&2
      exit 2
    fi
  else
    command -v clang++-14 >/dev/null || { echo "fuzz: needs clang++-14 (apt-get install clang-14 libfuzzer-14-dev)" >&2; exit 2; }
    cmake -S "$repo" -B "$build" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Debug \
      -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DCSGFIT_FUZZ=ON -DCSGFIT_BUILD_TESTS=OFF \
      -DCSGFIT_BUILD_OCCT=OFF -DCSGFIT_BUILD_PYTHON=OFF >/dev/null
  fi
  nice -n 10 cmake --build "$build" -j "${CSGFIT_FUZZ_BUILD_JOBS:-2}" --target "$@"
}

# One target: runs it, then prints "TARGET: runs N, exec/s X, crashes K" (and the artifact).
run_target() {
  local t="$1" seconds="$2" runs="$3"
  local bin="$build/fuzz/fuzz_$t" dir="$out/$t" scratch log rc=0
  [ -x "$bin" ] || { echo "fuzz: no target $t ($bin)" >&2; return 2; }
  mkdir -p "$dir"
  scratch="$(mktemp -d "${TMPDIR:-/tmp}/csgfit-fuzz-corpus-$t.XXXXXX")"
  cp "$repo/fuzz/corpus/$t/"* "$scratch/"
  log="$dir/fuzz.log"
  # detect_leaks: a reader that leaks on some input is a finding too.
  # (The braces keep the shell's own "Aborted" line out of the output: the log has the report.)
  { ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:symbolize=1" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
      nice -n 10 "$bin" -max_total_time="$seconds" -runs="$runs" -rss_limit_mb=2048 \
        -malloc_limit_mb=1024 -timeout=10 -print_final_stats=1 -artifact_prefix="$dir/" \
        "$scratch" >"$log" 2>&1; } 2>/dev/null || rc=$?
  rm -rf "$scratch"
  local n eps artifacts crashes
  n="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  eps="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)"
  artifacts="$(find "$dir" -maxdepth 1 -type f -newer "$dir/.start" \( -name 'crash-*' \
    -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \))"
  crashes="$(printf '%s' "$artifacts" | grep -c . || true)"
  [ "$rc" -ne 0 ] && [ "$crashes" -eq 0 ] && crashes=1
  printf 'fuzz: %-14s runs %9s  exec/s %6s  crashes %s\n' "$t" "${n:-?}" "${eps:-?}" "$crashes"
  if [ "$crashes" -ne 0 ]; then
    grep -m1 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error|uncaught exception|terminate called' "$log" || true
    [ -n "$artifacts" ] && printf '%s\n' "$artifacts" | sed 's/^/fuzz:   input /'
    echo "fuzz:   log $log"
    return 1
  fi
}

[ $# -ge 1 ] || usage
if [ "$1" = list ]; then all_targets; exit 0; fi
[ $# -ge 2 ] || usage
target="${1#fuzz_}" seconds="$2" runs="${3:--1}"
[[ "$seconds" =~ ^[0-9]+$ && "$runs" =~ ^-?[0-9]+$ ]] || usage

if [ "$target" = all ]; then
  mapfile -t targets < <(all_targets)
  build_targets csgfit_fuzz
else
  all_targets | grep -qx "$target" || usage
  targets=("$target")
  build_targets "fuzz_$target"
fi

for t in "${targets[@]}"; do
  mkdir -p "$out/$t"
  touch "$out/$t/.start"
  rm -f "$out/$t/status"
done
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  (rc=0; run_target "$t" "$seconds" "$runs" || rc=$?; echo "$rc" >"$out/$t/status") &
done
wait
failed=0
for t in "${targets[@]}"; do
  [ "$(cat "$out/$t/status" 2>/dev/null)" = 0 ] || failed=1
done
[ $failed -eq 0 ] || echo "fuzz: some targets crashed (inputs and logs under $out)" >&2
exit $failed
