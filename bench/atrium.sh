#!/bin/sh
# Issue 13's acceptance 2, the bench half: the atrium demonstration scene (scenes/atrium) at
# 1280x720 on a two-worker farm (a coordinator and 2 farm-worker processes of one thread,
# as `farm render` runs them but with the workers' logs kept). First, on the same farm, the
# baseline of the run: a 192x96 probe of the atrium as `farm import` samples it (1 sample
# per pixel, edge anti-aliasing, final gathering with 64 gather rays, 200,000 global
# photons, one round), with its textures and with every texture reference removed (what
# textures cost). Then the atrium at 1280x720 with the bench's sampling (below). Prints, for
# each render, the wall-clock seconds from submission to success and each worker's peak
# resident memory over the job's tasks (the largest `peak_memory_bytes` of its task lines,
# worker/README.md), the share of its pixels edge anti-aliasing supersampled (the mean of
# its edge layer), and the ratios. With PROBE_ONLY=1 in the environment, only the probes.
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
for size in 192x96 1280x720; do
  "$farm" import "$tmp/atrium/atrium.glb" --environment "$tmp/atrium/sky.hdr" \
    --width "${size%x*}" --height "${size#*x}" -o "$tmp/scene-$size/atrium.json" >/dev/null
done
# edit SCENE OUT PYTHON: OUT (beside SCENE, sharing its meshes and images) is SCENE with
# PYTHON applied to its JSON object `s`.
edit() {
  python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(s, open(sys.argv[2], "w"))' "$1" "$2" "$3"
}
edit "$tmp/scene-192x96/atrium.json" "$tmp/scene-192x96/untextured.json" '
for m in s["materials"]:
    for k in [k for k in m.get("principled", {}) if k.endswith("Texture")]:
        del m["principled"][k]'
# The bench's sampling at 1280x720, chosen for a few minutes on two cores: 1 sample per
# pixel and 4 on edges, 4 light samples, final gathering with 16 gather rays (4 after a
# glossy bounce), 200,000 global and 200,000 caustic photons (the defaults), one round.
edit "$tmp/scene-1280x720/atrium.json" "$tmp/scene-1280x720/bench.json" '
s["sampling"] = {"samplesPerPixel": 1, "lightSamples": 4}
s["antialiasing"] = {"edgeSamples": 4}
s["indirect"] = {"gatherRays": 16, "secondaryGatherRays": 4}
s["photons"] = {"globalPhotons": 200000, "causticPhotons": 200000}'

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

# render NAME FILE: submits, waits, prints and keeps the seconds in $tmp/NAME.s
render() {
  name=$1 file=$2
  start=$(date +%s.%N)
  job=$("$farm" submit "$file")
  "$farm" watch "$job" >"$tmp/$name.watch" 2>&1 || { cat "$tmp/$name.watch" >&2; exit 1; }
  end=$(date +%s.%N)
  "$farm" fetch "$job" -o "$out" --name "$name" >/dev/null
  awk "BEGIN { print $end - $start }" >"$tmp/$name.s"
  printf '%s: %.1f s' "$name" "$(cat "$tmp/$name.s")"
  for i in 1 2; do
    peak=$(grep "job=$job " "$tmp/worker-$i.log" | sed -n 's/.*peak_memory_bytes=\([0-9]*\).*/\1/p' | sort -n | tail -1)
    tasks=$(grep -c "job=$job .*peak_memory_bytes" "$tmp/worker-$i.log" || true)
    printf ', worker %d peak %.0f MiB over %d tasks' "$i" "$(awk "BEGIN { print ${peak:-0} / 1048576 }")" "$tasks"
  done
  edges=$(oiiotool "$out/$name.exr" --ch edge.Y --printstats 2>/dev/null | sed -n 's/.*Stats Avg: *\([0-9.e+-]*\).*/\1/p')
  printf ', edge pixels %.1f%%\n' "$(awk "BEGIN { print ${edges:-0} * 100 }")"
}
ratio() { awk "BEGIN { print $(cat "$tmp/$1.s") / $(cat "$tmp/$2.s") }"; }
render probe-192x96-untextured "$tmp/scene-192x96/untextured.json"
render probe-192x96 "$tmp/scene-192x96/atrium.json"
printf 'probe textured / untextured: time %.2fx\n' "$(ratio probe-192x96 probe-192x96-untextured)"
[ "${PROBE_ONLY:-0}" = 1 ] && exit 0
render atrium "$tmp/scene-1280x720/bench.json"
printf 'atrium 1280x720 / probe 192x96 (textured): time %.2fx for %.0fx the pixels\n' \
  "$(ratio atrium probe-192x96)" "$(awk 'BEGIN { print 1280 * 720 / (192 * 96) }')"
