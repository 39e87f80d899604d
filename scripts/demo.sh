#!/usr/bin/env bash
# The main job on the embedded default scene: installs what is missing, builds, generates the
# procedural city and its HLOD node store (once each), renders a frame of it to out/city.png,
# then runs the walk-to-fly camera path at a 33 ms budget in real time: out/walk.mp4 with its
# per-frame statistics (out/walk.stats.json, .csv) and the three plots of Lakhia's section IV.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out
if [ ! -f out/city/city.json ]; then
  build/hlodr city -o out/city
fi
build/hlodr render out/city -o out/city.png --size 1280x720
echo "demo: wrote out/city.png"
# A store from an older hlodr (another format version) is rebuilt.
if ! build/hlodr info out/city.hlod >/dev/null 2>&1; then
  build/hlodr build out/city -o out/city.hlod
fi
build/hlodr path out/city.hlod --kind walk-fly -o out/walk.json
build/hlodr render out/city.hlod --path out/walk.json -o out/walk.mp4 --budget-ms 33 \
  --prefetch --plots
echo "demo: wrote out/walk.mp4, out/walk.stats.json, out/walk.stats.csv and out/walk.*.svg"
