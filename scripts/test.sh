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
cmake --build build/asan -j"$jobs" --target loosehair_sim_tests loosehair
echo "== solver tests under ASan + UBSan =="
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j"$jobs" -L 'sim|cli'
echo "== full test suite (release) =="
ctest --test-dir build/release --output-on-failure -j"$jobs"
