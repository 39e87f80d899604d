#!/usr/bin/env bash
# The main job on the embedded default scenes: installs what is missing, builds, generates the
# procedural city and the procedural power plant and their HLOD node stores (once each), renders
# a first frame of the city to out/city.png, then serves the HTTP API and the web page over out/
# (`hlodr serve`): open the printed URL to orbit and walk through the city or the plant (the
# scene picker) under the frame budget, run camera-path jobs
# with a live timing dashboard, download their MP4 and stats, and run accuracy studies.
# Ctrl-C stops the server (running jobs close their files first).
#   HLODR_PORT=8080 HLODR_BIND=127.0.0.1 scripts/demo.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out
if [ ! -f out/city/city.json ]; then
  build/hlodr city -o out/city
fi
# A store from an older hlodr (another format version) is rebuilt.
if ! build/hlodr info out/city.hlod >/dev/null 2>&1; then
  build/hlodr build out/city -o out/city.hlod
fi
# The second scene: the procedural power plant (docs/objects.md), a CAD scene of 20,000 objects
# built with the object hierarchy; the page offers its catwalk walk and fly-around.
if [ ! -f out/plant/plant.glb ]; then
  build/hlodr plant -o out/plant
fi
if ! build/hlodr info out/plant.hlod >/dev/null 2>&1; then
  build/hlodr build out/plant/plant.glb -o out/plant.hlod
fi
# The default city scene: textures, lambert, a sun, a sky and light haze (scenes/city.json).
build/hlodr render out/city -o out/city.png --scene scenes/city.json --size 1280x720 --quiet
echo "demo: wrote out/city.png (the whole city at full detail, scenes/city.json)"
# The scene files, for the API's "scene": "city.json" / "city-shadows.json".
cp scenes/city.json scenes/city-shadows.json out/
exec build/hlodr serve --data out --port "${HLODR_PORT:-8080}" --bind "${HLODR_BIND:-127.0.0.1}"
