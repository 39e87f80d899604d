#!/usr/bin/env bash
# Installs what is missing, then configures and builds hlodr into build/ (Release with debug info).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHLODR_WERROR=ON >/dev/null
cmake --build build -j"$(nproc)"
