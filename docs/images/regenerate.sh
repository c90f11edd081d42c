#!/bin/sh
# Regenerates the README's pictures from the project's own scenes, so none is a hand-made
# file: docs/images/atrium.png, the atrium demonstration scene (scenes/atrium) at 480x270
# as `farm render` renders the .glb on a local two-worker farm, with the sampling `farm
# import` gives it (the PNG preview: exposure 0, the filmic tone map, docs/output.md); and
# docs/images/prism.png and docs/images/crystal-sphere.png, scenes/prism.json and
# scenes/crystal-sphere.json as `farm render` renders them (about 3 and 2 minutes on two
# cores: ten and eight million caustic photon paths); docs/images/god-rays.png,
# scenes/god-rays.json likewise (about 7 minutes); docs/images/smoke.png, the grid-medium
# scene scenes/smoke generates (its plume computed, not committed). docs/images/cornell-fog-compare.png is
# bench/crosscheck/fog.py's (make bench).
#   docs/images/regenerate.sh BUILD_DIR
set -eu
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
case $build in /*) ;; *) build="$root/$build" ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
cd "$root"
go run ./scenes/atrium/gen -o "$tmp/atrium"
"$build/bin/farm" render "$tmp/atrium/atrium.glb" --environment "$tmp/atrium/sky.hdr" --width 480 --height 270 \
  --workers 2 --no-dashboard -o "$tmp/out"
cp "$tmp/out/atrium.png" docs/images/atrium.png
echo "wrote docs/images/atrium.png"
"$build/bin/farm" render scenes/prism.json --workers 2 --no-dashboard -o "$tmp/prism"
cp "$tmp/prism/prism.png" docs/images/prism.png
echo "wrote docs/images/prism.png"
"$build/bin/farm" render scenes/crystal-sphere.json --workers 2 --no-dashboard -o "$tmp/crystal"
cp "$tmp/crystal/crystal-sphere.png" docs/images/crystal-sphere.png
echo "wrote docs/images/crystal-sphere.png"
"$build/bin/farm" render scenes/god-rays.json --workers 2 --no-dashboard -o "$tmp/god-rays"
cp "$tmp/god-rays/god-rays.png" docs/images/god-rays.png
echo "wrote docs/images/god-rays.png"
go run ./scenes/smoke/gen -o "$tmp/smoke"
"$build/bin/farm" render "$tmp/smoke/smoke.json" --workers 2 --no-dashboard -o "$tmp/smoke/out"
cp "$tmp/smoke/out/smoke.png" docs/images/smoke.png
echo "wrote docs/images/smoke.png"
