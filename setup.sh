#!/usr/bin/env bash
# Set-up of hexmesh on Debian 12: installs the packages, builds, then runs the bundled
# example (`bash setup.sh example`) or the whole test suite (`bash setup.sh test`); `bash setup.sh
# sanitize` builds the unit tests with the address and undefined-behaviour sanitizers and runs them.
# Run as root, or as a user with sudo.
set -euo pipefail
cd "$(dirname "$0")"
mode=${1:-example}

build_packages=(
  cmake g++ make pkg-config
  libeigen3-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libcgal-dev libvtk9-dev libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libcgns-dev libnetcdf-dev liblzma-dev
  libopenmpi-dev openmpi-bin
)
# Independent readers and checkers the end-to-end tests compare against, and the formatter
# whose rules the sources follow (a test checks them).
test_packages=(python3-vtk9 python3-meshio python3-netcdf4 openfoam gmsh cgns-convert chromium clang-format)

install_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]} == 0)) && return 0
  local sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}

jobs=$(nproc)
case "$mode" in
  example)
    install_packages "${build_packages[@]}"
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
    cmake --build build --target hexmesh -j"$jobs"
    ./build/hexmesh/cli/hexmesh run cases/sphere/case.json -o out/sphere
    ;;
  test)
    install_packages "${build_packages[@]}" "${test_packages[@]}"
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
    cmake --build build -j"$jobs"
    ctest --test-dir build --output-on-failure -j"$jobs"
    ;;
  sanitize)
    # The unit tests built with AddressSanitizer and UndefinedBehaviorSanitizer (any report
    # fails the test); the end-to-end tests, which run the command-line program on whole
    # bodies, are left to `test` (ten times slower under the sanitizers).
    install_packages "${build_packages[@]}" "${test_packages[@]}"
    flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
    cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags"
    cmake --build build-sanitize -j"$jobs"
    # Each module's test executable (not tests/e2e's), without the export tests that run the
    # command-line program.
    for module in core surface volume untangle io pipeline export; do
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
        "build-sanitize/tests/$module/test_$module" --gtest_filter='-ExportCli*' --gtest_brief=1
    done
    ;;
  *)
    echo "usage: bash setup.sh example|test|sanitize" >&2
    exit 2
    ;;
esac
