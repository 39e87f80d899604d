#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit + GL + service tests).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
# Software GL here: tests that render use Mesa's llvmpipe through EGL surfaceless or OSMesa.
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 600
