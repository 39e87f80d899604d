#!/usr/bin/env bash
# The main job on the embedded default scene: installs what is missing, builds, generates the
# procedural city (once), and renders a frame of it to out/city.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out
if [ ! -f out/city/city.json ]; then
  build/hlodr city -o out/city
fi
build/hlodr render out/city -o out/city.png --size 1280x720
echo "demo: wrote out/city.png"
