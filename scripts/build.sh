#!/usr/bin/env bash
# Installs what is missing, then configures and builds hlodr into build/ (Release with debug info).
#   scripts/build.sh             gcc, into build/ (tests and benchmarks included)
#   scripts/build.sh --sanitize  clang with AddressSanitizer + UndefinedBehaviorSanitizer and the
#                                libFuzzer targets, into build-asan/ (tests, no benchmarks;
#                                asserts on)
#   scripts/build.sh --tsan      clang with ThreadSanitizer, into build-tsan/: the service tests
#                                only (hlodr_service_tests, asserts on)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [ "${1:-}" = "--sanitize" ]; then
  # Line tables only: faster to build than -g, and stack traces keep their file:line (-O1 was
  # no faster to build or to run). No NDEBUG: the sanitizer suite runs the asserts too. A unity
  # build (8 sources per compiler run): the sanitizer tree is built whole, seldom edited.
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE= -DHLODR_WERROR=ON -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_C_FLAGS="-O2 -gline-tables-only" -DCMAKE_CXX_FLAGS="-O2 -gline-tables-only" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DHLODR_SANITIZE=ON -DHLODR_BUILD_BENCHES=OFF >/dev/null
  cmake --build build-asan -j"$(nproc)"
  exit 0
fi
if [ "${1:-}" = "--tsan" ]; then
  # The service tests alone: their threads (HTTP, render workers, job runners, loaders) are what
  # ThreadSanitizer checks, and a unity build of what they link keeps it short.
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE= -DHLODR_WERROR=ON -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_C_FLAGS="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DHLODR_TSAN=ON -DHLODR_BUILD_BENCHES=OFF >/dev/null
  cmake --build build-tsan -j"$(nproc)" --target hlodr_service_tests
  exit 0
fi
# Under CI (a clean clone, built once) a unity build too: 8 sources per compiler run took the
# clean build from about 640 s to 420 s here. Developers keep one compiler run per source, for
# quick rebuilds after an edit.
# CI leaves the benchmarks out too (no test runs them; about 3 of its 40 minutes): developers'
# builds keep them, so a change that breaks one shows at the next local build.
# CI's debug information is line tables only (-g1): a unity source compiled in 26 s instead of
# 34 s with -g, and a failure's stack trace still names file and line.
unity=OFF
benches=ON
debug="-O2 -g -DNDEBUG"
[ -n "${CI:-}" ] && unity=ON && benches=OFF && debug="-O2 -g1 -DNDEBUG"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHLODR_WERROR=ON \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="$debug" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$debug" \
  -DCMAKE_UNITY_BUILD="$unity" -DHLODR_BUILD_BENCHES="$benches" >/dev/null
cmake --build build -j"$(nproc)"
