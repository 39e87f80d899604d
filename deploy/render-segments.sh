#!/usr/bin/env bash
# Renders a camera path as N segments in N local processes at once, then joins them:
#   deploy/render-segments.sh N STORE PATH.json OUT [render options...]
# OUT is a folder (PNG sequence) or a file ending .mp4, as for `hlodr render --path`; the
# options (--size, --mode, --selector, --budget-ms, --fps, --frames, --warmup ...) go to every
# segment alike. The parts go to OUT.parts/ and are removed after a successful join.
# HLODR names the executable (default: hlodr on the PATH). docs/cli.md, "Segments".
set -euo pipefail
if [[ $# -lt 4 ]]; then
  echo "usage: $0 N STORE PATH.json OUT [render options...]" >&2
  exit 2
fi
n=$1 store=$2 path=$3 out=$4
shift 4
hlodr=${HLODR:-hlodr}
if ! [[ $n =~ ^[1-9][0-9]*$ ]]; then
  echo "$0: N must be a whole number >= 1, not '$n'" >&2
  exit 2
fi
parts_dir="$out.parts"
rm -rf "$parts_dir"
mkdir -p "$parts_dir"
ext=""
[[ $out == *.mp4 || $out == *.MP4 ]] && ext=".mp4"
pids=()
parts=()
for ((i = 0; i < n; i++)); do
  part="$parts_dir/part-$i$ext"
  parts+=("$part")
  "$hlodr" render "$store" --path "$path" --segment "$i/$n" -o "$part" --quiet "$@" \
    >"$parts_dir/part-$i.log" 2>&1 &
  pids+=($!)
done
failed=0
for ((i = 0; i < n; i++)); do
  if ! wait "${pids[$i]}"; then
    echo "$0: segment $i/$n failed:" >&2
    tail -n 5 "$parts_dir/part-$i.log" >&2
    failed=1
  fi
done
[[ $failed == 0 ]] || exit 1
"$hlodr" concat "${parts[@]}" -o "$out"
rm -rf "$parts_dir"
