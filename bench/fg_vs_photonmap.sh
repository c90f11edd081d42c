#!/bin/sh
# Acceptance 1 of issue 4: final gathering against the global photon map seen directly, at
# equal wall-clock budgets, on scenes/cornell-box.json through a real local farm (a
# coordinator and 2 farm-worker processes). Renders a converged reference first (final
# gathering, progressive rounds for REF_BUDGET), then each method at 10 s and 60 s with the
# reference set, and prints the farm-reported RMSE of both and their ratio. About 5 minutes.
#   bench/fg_vs_photonmap.sh BUILD_DIR [REF_BUDGET]     e.g. bench/fg_vs_photonmap.sh build 150s
# Needs farm (Go) and farm-worker (C++) built in BUILD_DIR/bin.
set -eu
build=${1:-build}
ref_budget=${2:-150s}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
case $build in /*) ;; *) build="$root/$build" ;; esac
echo "== final gathering vs photon map seen directly (Cornell box, equal wall-clock budgets)"
go run ./bench/cmd/fgbench -bin "$build/bin" -scene scenes/cornell-box.json \
  -reference-budget "$ref_budget" -budgets 10s,60s
