#!/usr/bin/env bash
# The service under a real load generator: wrk POSTs /api/render (640x480, a fixed camera, a warm
# session) for JPEG and PNG frames at 1, 4 and 16 connections, and prints p50/p99 latency,
# throughput, and the server's overhead beyond the frame's own render time (wrk's p50 latency
# minus the p50 of the Server-Timing render parts: select + upload + draw + readback + encode).
#   tests/bench/serve_bench.sh [STORE_FOLDER] [SECONDS]
# STORE_FOLDER holds NAME.hlod stores (default: out/, the demo's, or a 16-block city made once).
set -euo pipefail
cd "$(dirname "$0")/../.."
data=${1:-}
seconds=${2:-15}
command -v wrk >/dev/null || { echo "serve_bench: needs wrk (apt-get install wrk)" >&2; exit 1; }
[ -x build/hlodr ] || { echo "serve_bench: build first (scripts/build.sh)" >&2; exit 1; }
if [ -z "$data" ]; then
  if [ -f out/city.hlod/skeleton.bin ]; then
    data=out
  else
    data=build/serve_bench_data
    if [ ! -f "$data/city.hlod/skeleton.bin" ]; then
      build/hlodr city --blocks 16 -o "$data/src" --quiet
      build/hlodr build "$data/src" -o "$data/city.hlod" --quiet
    fi
  fi
fi
port=$((20000 + RANDOM % 20000))
build/hlodr serve --data "$data" --port "$port" --quiet --queue 64 --workers 2 \
  >build/serve_bench.log 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null; wait $pid 2>/dev/null || true' EXIT
for _ in $(seq 100); do
  curl -sf "http://127.0.0.1:$port/healthz" >/dev/null 2>&1 && break
  sleep 0.2
done
scene=$(curl -sf "http://127.0.0.1:$port/api/scenes" | sed -n 's/.*"id":"\([^"]*\)".*/\1/p' | head -n1)
echo "serve_bench: scene '$scene' from $data, ${seconds}s per run, $(nproc) cores"
printf "%-6s %5s %8s %9s %9s %11s %10s %12s %6s\n" format conns req/s p50_ms p99_ms render_p50 \
  queue_p50 overhead_p50 errors
for format in jpeg png; do
  # Warm the session (first frame loads the front) before timing.
  FORMAT=$format SCENE=$scene wrk -t1 -c1 -d2s -s tests/bench/serve/render.lua \
    "http://127.0.0.1:$port" >/dev/null
  for conns in 1 4 16; do
    threads=$(( conns < 2 ? 1 : 2 ))
    line=$(FORMAT=$format SCENE=$scene wrk -t"$threads" -c"$conns" -d"${seconds}s" --latency \
      -s tests/bench/serve/render.lua "http://127.0.0.1:$port" | grep '^RESULT')
    get() { echo "$line" | tr ' ' '\n' | sed -n "s/^$1=//p"; }
    printf "%-6s %5s %8s %9s %9s %11s %10s %12s %6s\n" "$format" "$conns" "$(get rps)" \
      "$(get p50_ms)" "$(get p99_ms)" "$(get render_p50_ms)" "$(get queue_p50_ms)" \
      "$(get overhead_p50_ms)" "$(get errors)"
  done
done
