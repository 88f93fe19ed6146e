#!/usr/bin/env bash
# Set-up of hexmesh on Debian 12: installs the packages, builds, then runs the bundled
# example (`bash setup.sh example`) or the whole test suite (`bash setup.sh test`).
# Run as root, or as a user with sudo.
set -euo pipefail
cd "$(dirname "$0")"
mode=${1:-example}

build_packages=(
  cmake g++ make pkg-config
  libeigen3-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libcgal-dev libvtk9-dev libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libcgns-dev
)
# Independent readers and checkers the end-to-end tests compare against.
test_packages=(python3-vtk9 openfoam gmsh cgns-convert)

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
  *)
    echo "usage: bash setup.sh example|test" >&2
    exit 2
    ;;
esac
