#!/bin/sh
# Issue 13's acceptance 2, the bench half: the atrium demonstration scene (scenes/atrium) at
# 1280x720 on a two-worker farm (a coordinator and 2 farm-worker processes of one thread,
# as `farm render` runs them but with the workers' logs kept), after the Cornell box at the
# same size on the same farm as the baseline of the same run. Prints, for each, the
# wall-clock time from submission to success (import and upload included for the atrium:
# `farm submit` of the .glb) and each worker's peak resident memory over the job's tasks
# (the largest `peak_memory_bytes` of its task lines, worker/README.md), and the atrium's
# ratios to the baseline. The scene is rendered with the sampling `farm import` gives it.
#   bench/atrium.sh BUILD_DIR [OUT_DIR]     OUT_DIR keeps atrium.exr and atrium.png
set -eu
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
case $build in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
out=${2:-$tmp/out}
pids=""
cleanup() {
  for p in $pids; do kill "$p" 2>/dev/null || true; done
  for p in $pids; do wait "$p" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT INT TERM
cd "$root"
farm=$build/bin/farm
go run ./scenes/atrium/gen -o "$tmp/atrium"
# The baseline: the Cornell box's scene file with the atrium's film.
python3 -c 'import json, sys
s = json.load(open(sys.argv[1])); s["film"]["width"], s["film"]["height"] = 1280, 720
json.dump(s, open(sys.argv[2], "w"))' scenes/cornell-box.json "$tmp/cornell-box.json"

"$farm" coordinator --listen 127.0.0.1:0 --data-dir "$tmp/data" 2>"$tmp/coordinator.log" &
pids="$!"
addr=""
for _ in $(seq 200); do
  addr=$(sed -n 's/.*coordinator listening on //p' "$tmp/coordinator.log")
  [ -n "$addr" ] && break
  sleep 0.1
done
[ -n "$addr" ] || { echo "atrium.sh: the coordinator did not start" >&2; cat "$tmp/coordinator.log" >&2; exit 1; }
export FARM_COORDINATOR=$addr
for i in 1 2; do
  "$build/bin/farm-worker" --coordinator "$addr" --threads 1 --cache-dir "$tmp/cache-$i" --name "bench-$i" \
    2>"$tmp/worker-$i.log" &
  pids="$! $pids"
done

# render NAME FILE [SUBMIT FLAGS]: submits, waits, prints and keeps the seconds in $tmp/NAME.s
render() {
  name=$1 file=$2
  shift 2
  start=$(date +%s.%N)
  job=$("$farm" submit "$file" "$@")
  "$farm" watch "$job" >"$tmp/$name.watch" 2>&1 || { cat "$tmp/$name.watch" >&2; exit 1; }
  end=$(date +%s.%N)
  "$farm" fetch "$job" -o "$out" --name "$name" >/dev/null
  awk "BEGIN { print $end - $start }" >"$tmp/$name.s"
  printf '%s: %.1f s' "$name" "$(cat "$tmp/$name.s")"
  for i in 1 2; do
    peak=$(grep "job=$job " "$tmp/worker-$i.log" | sed -n 's/.*peak_memory_bytes=\([0-9]*\).*/\1/p' | sort -n | tail -1)
    tasks=$(grep -c "job=$job .*peak_memory_bytes" "$tmp/worker-$i.log" || true)
    echo "${peak:-0}" >"$tmp/$name.peak-$i"
    printf ', worker %d peak %.0f MiB over %d tasks' "$i" "$(awk "BEGIN { print ${peak:-0} / 1048576 }")" "$tasks"
  done
  echo
}
render cornell-box "$tmp/cornell-box.json"
render atrium "$tmp/atrium/atrium.glb" --environment "$tmp/atrium/sky.hdr" --width 1280 --height 720
ratio() { awk "BEGIN { print $(cat "$tmp/$1") / $(cat "$tmp/$2") }"; }
printf 'atrium / cornell-box: time %.2fx' "$(ratio atrium.s cornell-box.s)"
for i in 1 2; do
  printf ', worker %d peak memory %.2fx' "$i" "$(ratio "atrium.peak-$i" "cornell-box.peak-$i")"
done
echo
