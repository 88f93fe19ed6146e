#!/usr/bin/env bash
# Builds the readers' libFuzzer targets with clang (AddressSanitizer, UndefinedBehaviorSanitizer,
# leak checks) in build-fuzz/ and runs each for SECONDS (default 600) from its seed corpus in
# tests/fuzz/corpus/NAME (new inputs go to build-fuzz/corpus/NAME; crashes to
# build-fuzz/findings/). Prints one line per target; exits 1 if any target found a crash,
# leak or timeout. Usage: bash tests/fuzz/run.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-600}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(surface case vtk gmsh medit plot3d points sections vts vtu)
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHEXMESH_FUZZ=ON \
  -DHEXMESH_BUILD_TESTS=OFF -DHEXMESH_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" > build-fuzz.log
cmake --build build-fuzz -j"$(nproc)" $(printf -- '--target fuzz_%s ' "${targets[@]}") >> build-fuzz.log
mkdir -p build-fuzz/findings
failed=0
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t"
  log="build-fuzz/fuzz_$t.log"
  if ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=0 LSAN_OPTIONS=suppressions=tests/fuzz/lsan.supp ./build-fuzz/tests/fuzz/fuzz_"$t" "build-fuzz/corpus/$t" "tests/fuzz/corpus/$t" \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -artifact_prefix="build-fuzz/findings/$t-" > "$log" 2>&1; then
    status=ok
  else
    status=FOUND
    failed=1
  fi
  runs=$(grep -o 'Done [0-9]* runs' "$log" | grep -o '[0-9]*' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
  echo "$t: $status, $runs runs in ${seconds} s, coverage $cov edges, corpus $(ls "build-fuzz/corpus/$t" | wc -l) inputs"
done
exit $failed
