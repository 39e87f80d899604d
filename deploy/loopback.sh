#!/usr/bin/env bash
# Starts N `hlodr serve` on loopback behind HAProxy (deploy/haproxy.cfg), in the foreground:
# SIGTERM or Ctrl-C stops them all (each server drains first, --drain-s).
#
#   deploy/loopback.sh [--servers N] [--port P] [--data DIR] [--run DIR] [--hlodr BIN] [-- SERVE-OPTIONS]
#
# The balancer listens on 127.0.0.1:P (default 8080), server i on P+i. All servers share the data
# folder (stores are only read; each has its own jobs folder, DATA/jobs-sI). The run folder
# (default a fresh temporary one) gets haproxy.cfg as used and `servers`: one line "NAME PID PORT"
# per server, then "haproxy PID PORT"; "ready" is printed once the balancer sees every server up.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
servers=3
port=8080
data=hlodr-data
run=""
hlodr=${HLODR_BINARY:-hlodr}
while [ $# -gt 0 ]; do
  case "$1" in
    --servers) servers=$2; shift 2 ;;
    --port) port=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --run) run=$2; shift 2 ;;
    --hlodr) hlodr=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "loopback.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
case "$servers" in '' | *[!0-9]* | 0) echo "loopback.sh: --servers must be 1 or more" >&2; exit 2 ;; esac
[ -n "$run" ] || run=$(mktemp -d -t hlodr-lb.XXXXXX)
mkdir -p "$run" "$data"
command -v haproxy >/dev/null || { echo "loopback.sh: haproxy is not installed" >&2; exit 2; }

# The shipped config with one server line per server between its markers.
awk -v n="$servers" -v p="$port" '
  /# servers begin/ { print; for (i = 1; i <= n; i++) printf "    server s%d 127.0.0.1:%d check\n", i, p + i; skip = 1; next }
  /# servers end/ { skip = 0 }
  !skip { print }' "$here/haproxy.cfg" > "$run/haproxy.cfg"

pids=()  # the servers'
lb=""
stop_all() {
  trap - TERM INT
  # Servers first: they drain (their /healthz turns 503) while the balancer still runs.
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  [ -z "$lb" ] || { kill -TERM "$lb" 2>/dev/null || true; wait "$lb" 2>/dev/null || true; }
  exit 0
}
trap stop_all TERM INT

: > "$run/servers"
for i in $(seq 1 "$servers"); do
  sport=$((port + i))
  # Behind a proxy every client has the proxy's address: no per-address cap.
  "$hlodr" serve --data "$data" --jobs-dir "$data/jobs-s$i" --bind 127.0.0.1 --port "$sport" \
    --max-connections-per-address 0 --drain-s 2 --quiet "$@" > "$run/s$i.log" 2>&1 &
  pids+=($!)
  echo "s$i $! $sport" >> "$run/servers"
done

# True once 127.0.0.1:$1 answers /healthz with "ok" (bash's /dev/tcp: no curl needed).
healthy() {
  bash -c "exec 3<>/dev/tcp/127.0.0.1/$1 && printf 'GET /healthz HTTP/1.0\r\n\r\n' >&3 && grep -q '\"ok\"' <&3" 2>/dev/null
}

# Each server answers /healthz once it has opened its stores.
for i in $(seq 1 "$servers"); do
  until healthy $((port + i)); do
    kill -0 "${pids[$((i - 1))]}" 2>/dev/null || { echo "loopback.sh: server s$i exited (see $run/s$i.log)" >&2; stop_all; }
    sleep 0.1
  done
done

HLODR_LB_BIND="127.0.0.1:$port" haproxy -db -f "$run/haproxy.cfg" > "$run/haproxy.log" 2>&1 &
lb=$!
echo "haproxy $lb $port" >> "$run/servers"
until healthy "$port"; do
  kill -0 "$lb" 2>/dev/null || { echo "loopback.sh: haproxy exited (see $run/haproxy.log)" >&2; stop_all; }
  sleep 0.1
done
echo "ready: http://127.0.0.1:$port/ ($servers servers, run folder $run)"
wait
