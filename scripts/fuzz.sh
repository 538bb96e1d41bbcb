#!/usr/bin/env bash
# A long run of the randomized ("fuzz") native tests under AddressSanitizer and
# UndefinedBehaviorSanitizer. Usage: scripts/fuzz.sh [ITERATIONS] (default 20000).
# The test suite runs the same tests briefly (60 scenes).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHITTED_SANITIZE=ON \
  -DWHITTED_PYTHON=OFF -DWHITTED_TESTS=ON >/dev/null
cmake --build build-asan --parallel "$(nproc)"
WHITTED_FUZZ_ITERATIONS=${1:-20000} ./build-asan/whitted_tests --gtest_filter='Fuzz.*'
