#!/usr/bin/env bash
# Builds and runs the whole test suite, then the solver tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

scripts/build.sh
echo "== sanitizer build (ASan + UBSan) =="
cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=Release -DLOOSEHAIR_SANITIZE=ON \
  -DLOOSEHAIR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/asan -j"$jobs" --target loosehair_sim_tests loosehair loosehair_fuzz
echo "== solver tests under ASan + UBSan =="
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j"$jobs" -L 'sim|cli'
echo "== baseline code paths: no SSE intrinsics, no multiversioned kernels =="
# The scalar fallbacks of the gathers and the neighbour search, and the
# baseline kernels, must give the same bits as the vector paths: the
# golden state hashes and the determinism tests check it.
cmake -S . -B build/baseline -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-U__SSE2__ \
  -DLOOSEHAIR_MULTIVERSION=OFF -DLOOSEHAIR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/baseline -j"$jobs" --target loosehair_sim_tests
build/baseline/tests/loosehair_sim_tests \
  --gtest_filter='Golden.*:Determinism*:NeighborGrid.*'
echo "== full test suite (release) =="
ctest --test-dir build/release --output-on-failure -j"$jobs"
