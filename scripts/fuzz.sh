#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz/) for SECONDS each (default 60), as many at once as
# there are cores (FUZZ_JOBS=N to change), from the seed corpus in tests/fuzz/corpus/NAME plus what earlier runs found; prints per target
# the executions, the edges covered (cov) and the features (ft). Builds build-asan/ first
# (scripts/build.sh --sanitize).
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 600 obj gltf
# Found inputs go to build-asan/fuzz/corpus/NAME; a crash, leak, timeout (10 s) or memory blow-up
# (2 GB) is saved as build-asan/fuzz/crashes/NAME-crash-HASH (or -leak-, -timeout-, -oom-), and
# the script then exits 1. tests/fuzz/README.md says how to make one a regression test.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: scripts/fuzz.sh [SECONDS] [TARGET...]" >&2; exit 2; }

all=$(sed -n 's/^hlodr_fuzz_target(\([a-z_]*\) .*/\1/p' tests/fuzz/CMakeLists.txt)
targets=${*:-$all}
scripts/build.sh --sanitize >/dev/null
. scripts/sanitize-env.sh

out=build-asan/fuzz
mkdir -p "$out/crashes" "$out/logs"
# One target: its run, into its log and the rc file beside it.
run_target() {
  local t=$1 bin=build-asan/tests/fuzz/fuzz_$1 rc=0
  local dict=()
  [ -f "tests/fuzz/dict/$t.dict" ] && dict=(-dict="tests/fuzz/dict/$t.dict")
  # The first folder receives new inputs; the seed corpus in the repository is only read.
  "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/crashes/$t-" "${dict[@]}" "$out/corpus/$t" "tests/fuzz/corpus/$t" \
    >"$out/logs/$t.log" 2>&1 || rc=$?
  echo "$rc" >"$out/logs/$t.rc"
}

jobs_max=${FUZZ_JOBS:-$(nproc)}
for t in $targets; do
  [ -x "build-asan/tests/fuzz/fuzz_$t" ] || { echo "fuzz: no target $t (known: $(echo $all))" >&2; exit 2; }
done
for t in $targets; do
  mkdir -p "$out/corpus/$t"
  rm -f "$out/logs/$t.rc"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  run_target "$t" &
done
wait

printf '%-14s %12s %9s %7s %7s %7s  %s\n' target execs exec/s cov ft corpus result
failed=0
for t in $targets; do
  log=$out/logs/$t.log
  rc=$(cat "$out/logs/$t.rc" 2>/dev/null || echo "?")
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n1)
  last=$(grep -E '^#[0-9]+' "$log" | grep 'cov:' | tail -n1 || true)
  cov=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.*ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.*corp: \([0-9]*\).*/\1/p' <<<"$last")
  result=ok
  if [ "$rc" != 0 ]; then
    failed=1
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n1)
    result="FAILED (rc $rc): ${artifact:-see $log}"
  fi
  printf '%-14s %12s %9s %7s %7s %7s  %s\n' "$t" "${execs:-?}" "${speed:-?}" "${cov:-?}" \
    "${ft:-?}" "${corp:-?}" "$result"
  if [ "$rc" != 0 ]; then grep -E 'ERROR|SUMMARY|runtime error' "$log" | head -n 5 | sed 's/^/    /'; fi
done
echo "fuzz: logs in $out/logs, found inputs in $out/corpus, crashes in $out/crashes"
exit $failed
