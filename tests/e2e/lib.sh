# Sourced by every tests/e2e/*_test.sh (CTest runs each as `bash SCRIPT CLI SOURCE_DIR`): the
# arguments, the skips, the scratch folder and the failure count they all start with, and the
# run of a benchmark driver that both smoke tests make. Not a test itself: tests/CMakeLists.txt
# lists the tests (CSGFIT_E2E_TESTS), each NAME_test.sh here.

PY=/usr/bin/python3
E2E_NAME=$(basename "$0" _test.sh)
FAILURES=0

# e2e_args N "$@": CLI from $1 and SRC from $2, of which the first N are required (N = 1: the
# test needs no source tree and SRC may be empty). CLI is made absolute, since tests cd.
e2e_args() {
  local required=$1 usage="CSGFIT_CLI SOURCE_DIR"
  shift
  [ "$required" -ge 2 ] || usage="CSGFIT_CLI [SOURCE_DIR]"
  if [ -z "${1:-}" ] || { [ "$required" -ge 2 ] && [ -z "${2:-}" ]; }; then
    echo "usage: bash ${E2E_NAME}_test.sh $usage" >&2
    exit 1
  fi
  case $1 in
    /*) CLI=$1 ;;
    *) CLI=$PWD/$1 ;;
  esac
  SRC=${2:-}
}

# e2e_skip MESSAGE: the test cannot run here; that is not a failure.
e2e_skip() {
  echo "$*"
  exit 0
}

# e2e_need_tools TOOL...: skips the test when one of them is not on PATH.
e2e_need_tools() {
  local tool
  for tool in "$@"; do
    command -v "$tool" >/dev/null 2>&1 || e2e_skip "SKIP: $tool is not installed"
  done
}

# e2e_need_benchmarks [SUBDIR]: BENCH is ../shared/benchmarks[/SUBDIR] next to the source tree
# (read-only, not in the repository); skips the test when it is absent (with SUBDIR: when it has
# no manifest.json).
e2e_need_benchmarks() {
  BENCH="$SRC/../shared/benchmarks${1:+/$1}"
  if [ -n "${1:-}" ]; then
    [ -f "$BENCH/manifest.json" ]
  else
    [ -d "$BENCH" ]
  fi || e2e_skip "$E2E_NAME: $BENCH not found: skipped"
}

# e2e_tmpdir: TMP, a scratch folder removed when the test exits however it ends.
e2e_tmpdir() {
  TMP=$(mktemp -d "${TMPDIR:-/tmp}/csgfit-$E2E_NAME-XXXXXX") || exit 1
  trap 'rm -rf "$TMP"' EXIT
}

# e2e_temp_files DIR: the writers' temporary files left in DIR (hidden ".NAME.tmp-PID-..."
# files beside each output), one per line; empty when there are none.
e2e_temp_files() {
  find "$1" -maxdepth 1 -name '*.tmp-*' 2>/dev/null
}

# fail MESSAGE: one failed check; the test goes on, and e2e_finish reports the count.
fail() {
  echo "FAIL: $*" >&2
  FAILURES=$((FAILURES + 1))
}

# e2e_finish MESSAGE: exit status 1 when any check failed, else MESSAGE and status 0.
e2e_finish() {
  if [ "$FAILURES" -ne 0 ]; then
    echo "$FAILURES failure(s)" >&2
    exit 1
  fi
  echo "$*"
}

# e2e_run_bench SCRIPT ARGS...: runs scripts/SCRIPT on BENCH with the CLI, writing into TMP
# (its tables in TMP/table.md, which are printed); stops the test when the script fails.
e2e_run_bench() {
  local script=$1
  shift
  "$PY" "$SRC/scripts/$script" --cli "$CLI" --bench-dir "$BENCH" --out "$TMP" "$@" \
    >"$TMP/table.md" 2>"$TMP/log.txt"
  local rc=$?
  cat "$TMP/table.md"
  if [ $rc -ne 0 ]; then
    echo "$E2E_NAME: $script exited $rc" >&2
    cat "$TMP/log.txt" >&2
    exit 1
  fi
}

# e2e_bench_done N: the tables' overall row counts N inputs; the smoke test has passed.
e2e_bench_done() {
  grep -q "^| \*\*all\*\* | $1 |" "$TMP/table.md" || { echo "$E2E_NAME: no overall row" >&2; exit 1; }
  echo "$E2E_NAME: ok"
}
