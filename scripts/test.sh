#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit, GL, service and browser tests).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
# The browser test's node module, playwright-core, is kept in the repository (tests/web/vendor/):
# installed from there when missing, with no network at all.
if command -v npm >/dev/null; then
  (cd tests/web && { npm ls --offline >/dev/null 2>&1 || npm ci --offline --no-audit --no-fund; })
else
  echo "test: no npm, the browser test (web.page) will be skipped"
fi
# Software GL here: tests that render use Mesa's llvmpipe through EGL surfaceless or OSMesa.
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 600
