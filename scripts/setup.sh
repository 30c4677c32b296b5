#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine (README "Quick start"):
#   bash scripts/setup.sh example   install what is missing, build, convert examples/bracket.png
#   bash scripts/setup.sh test      install what is missing, build, run every test
# Idempotent: packages already installed are not touched, the build is incremental.
set -euo pipefail

mode="${1:-example}"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CSGFIT_BUILD_DIR:-$repo/build}"
jobs="$(nproc 2>/dev/null || echo 2)"

# Debian packages: build tools and libraries, then what the integration tests drive.
packages=(
  build-essential cmake pkg-config
  libstb-dev nlohmann-json3-dev libcli11-dev libeigen3-dev libcgal-dev
  libgtest-dev libbenchmark-dev
  clang-14 libfuzzer-14-dev  # the sanitized build and the fuzz targets (docs/FUZZING.md)
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev
  libtbb-dev  # OCCT's CMake targets link libtbb.so, which libocct-*-dev does not pull in
  python3 python3-dev python3-numpy python3-pytest python3-pil pybind11-dev python3-pybind11
  openscad potrace freecad xvfb xauth
)

install_packages() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "setup: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}

build_all() {
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCSGFIT_BUILD_TESTS=ON \
    -DCSGFIT_BUILD_PYTHON=ON -DPython3_EXECUTABLE=/usr/bin/python3
  cmake --build "$build" -j "$jobs"
  CSGFIT_BUILD_DIR="$build" bash "$repo/scripts/install_workbench.sh"
}

# The GoogleTest suite built with ASan + UBSan. -O1 -g1 (line tables for the reports) builds in
# half the time of RelWithDebInfo. Built by clang with CSGFIT_FUZZ=ON, so that the same tree also
# builds the libFuzzer targets (fuzz/, docs/FUZZING.md), which run after the suite: 10 s each, two
# at a time (longer campaigns: scripts/fuzz.sh all SECONDS).
run_sanitized_tests() {
  local asan="$build-asan" failed=0
  # A tree that another compiler configured (gcc, before the fuzz targets) is started afresh.
  if [ -f "$asan/CMakeCache.txt" ] && ! grep -q '^CSGFIT_FUZZ:BOOL=ON' "$asan/CMakeCache.txt"; then
    rm -rf "$asan"
  fi
  cmake -S "$repo" -B "$asan" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DCSGFIT_SANITIZE=ON -DCSGFIT_FUZZ=ON \
    -DCSGFIT_BUILD_TESTS=ON -DCSGFIT_BUILD_PYTHON=OFF >/dev/null
  cmake --build "$asan" -j "$jobs" --target csgfit_tests csgfit csgfit_fuzz
  run_sanitized_shards "$asan" || failed=1
  echo "== fuzz targets under ASan and UBSan (10 s each, two at a time)"
  CSGFIT_FUZZ_BUILD_DIR="$asan" CSGFIT_FUZZ_JOBS=2 bash "$repo/scripts/fuzz.sh" all 10 || failed=1
  return $failed
}

# Twice as many shards as cores, one per core at a time: a few long tests land in one shard, and
# smaller shards even out the cores' loads.
run_sanitized_shards() {
  local asan="$1" shards=$((2 * jobs)) shard failed=0
  for ((shard = 0; shard < shards; shard++)); do
    ((shard < jobs)) || wait -n || true
    (
      # OpenCASCADE keeps its STEP tables for the life of the process (tests/lsan_occt.supp).
      GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$shard \
      LSAN_OPTIONS="suppressions=$repo/tests/lsan_occt.supp" \
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        "$asan/bin/csgfit_tests" --gtest_brief=1 >"$asan/shard_$shard.log" 2>&1
      echo $? >"$asan/shard_$shard.rc"
    ) &
  done
  wait
  for ((shard = 0; shard < shards; shard++)); do
    if [ "$(cat "$asan/shard_$shard.rc" 2>/dev/null)" = 0 ]; then
      grep -h "PASSED" "$asan/shard_$shard.log"
    else
      cat "$asan/shard_$shard.log"
      failed=1
    fi
  done
  return $failed
}

run_tests() {
  local failed=0
  echo "== C++ and end-to-end tests (ctest)"
  (cd "$build" && ctest --output-on-failure -j "$jobs") || failed=1

  echo "== Python module and FreeCAD tests (pytest on /usr/bin/python3)"
  # FreeCAD's GUI (Qt WebEngine) refuses to start as root without this.
  QTWEBENGINE_DISABLE_SANDBOX=1 CSGFIT_BUILD_DIR="$build" /usr/bin/python3 -m pytest -q "$repo/tests/python" "$repo/tests/freecad" || failed=1

  echo "== C++ tests and fuzz targets under AddressSanitizer and UndefinedBehaviorSanitizer"
  run_sanitized_tests || failed=1

  if [ $failed -ne 0 ]; then
    echo "setup: some tests failed" >&2
    exit 1
  fi
  echo "setup: all tests passed"
}

case "$mode" in
  example)
    install_packages
    build_all
    "$build/bin/csgfit" image "$repo/examples/bracket.png" -o "$repo/bracket.scad" --time 2 \
      --pixel-size 0.5 --preview "$repo/bracket_preview.png"
    echo "setup: wrote $repo/bracket.scad (open it in OpenSCAD) and $repo/bracket_preview.png"
    ;;
  test)
    install_packages
    build_all
    run_tests
    ;;
  *)
    echo "usage: bash scripts/setup.sh [example|test]" >&2
    exit 2
    ;;
esac
