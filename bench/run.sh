#!/bin/sh
# Runs every benchmark and prints the figures (`make bench`).
#   bench/run.sh BUILD_DIR [SIZES]     e.g. bench/run.sh build "1000000 10000000"
# Needs farm_bench_photons, farm_bench_caustic_emission, farm_bench_knn, farm_bench_specular, farm_bench_spectral, farm_bench_bias_layer and farm_bench_edge_aa built in BUILD_DIR, and
# $BENCH_PYTHON (default python3) a Python with mitsuba and numpy (make bench makes one:
# scripts/install-deps.sh --bench; without them the Mitsuba comparisons are skipped with a
# message). Snapshots and renders go to a temporary folder, removed at exit; Mitsuba
# references are cached in BUILD_DIR/bench-cache.
set -eu
build=${1:-build}
sizes=${2:-"1000000 10000000"}
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
cd "$root"
echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "== worker photon tracing (C++, scenes/cornell-caustics.json)"
"$build/bin/farm_bench_photons"
echo "== caustic emission with 10 and with 10,000 specular spheres, same paths (C++, in-process; target: aiming at most 2x)"
"$build/bin/farm_bench_caustic_emission"
echo "== coordinator kd-tree build (Go, coordinator/photonmap.Build)"
go build -o "$tmp/mksnapshot" ./bench/cmd/mksnapshot
snaps=""
for dist in uniform surfaces; do
  for n in $sizes; do
    "$tmp/mksnapshot" -n "$n" -dist "$dist" -o "$tmp/$dist-$n.snap"
    snaps="$snaps $tmp/$dist-$n.snap"
  done
done
echo "== worker nearest-k (C++, the Go-built snapshot mapped) vs nanoflann, same points and queries"
echo "   (target 1.5x in every row, MISSED when below: not an error; exits 1 only when neighbours differ)"
# shellcheck disable=SC2086
"$build/bin/farm_bench_knn" $snaps
echo "== glass at one sample per pixel: camera paths split at glass vs one Fresnel choice (C++, in-process, scenes/cornell-caustics.json)"
"$build/bin/farm_bench_specular"
echo "== what the error estimate's bias layer costs a round: each photon estimate's companion (C++, in-process, 64x64; issue 14, acceptance 5; target a round at most 1.30x)"
"$build/bin/farm_bench_bias_layer"
echo "== spectral mode (eight wavelengths a path) against RGB on scenes without dispersion: converged relMSE (target 0.005) and time to equal error (C++, in-process; issue 18)"
"$build/bin/farm_bench_spectral" scenes/cornell-box.json
"$build/bin/farm_bench_spectral" scenes/cornell-caustics.json
echo "== final gathering vs the photon map seen directly at equal wall-clock budgets (through a local farm)"
"$root/bench/fg_vs_photonmap.sh" "$build"
echo "== edge anti-aliasing vs full 12x supersampling (C++, in-process; exits 1 when the RMSE fails; the time ratio is a figure, MISSED when over 1/3)"
"$build/bin/farm_bench_edge_aa"
echo "== coordinator load: N simulated gRPC workers on real coordinators and redis-server (issue 17; target at N=1000: 5,000 leases/s, LeaseTask p99 < 20 ms, MISSED when below)"
go build -o "$tmp/loadsim" ./bench/cmd/loadsim
"$tmp/loadsim" -bin "$build/bin" -workers 10,100,1000 -replicas 1 -duration "${LOADSIM_DURATION:-15s}"
"$tmp/loadsim" -bin "$build/bin" -workers 1000 -replicas 2 -duration "${LOADSIM_DURATION:-15s}"
"$tmp/loadsim" -bin "$build/bin" -workers 1000 -replicas 1 -upload=false -duration "${LOADSIM_DURATION:-15s}"
echo "== the atrium demonstration scene at 1280x720 on a two-worker farm, the Cornell box as the baseline"
"$root/bench/atrium.sh" "$build"
python=${BENCH_PYTHON:-python3}
if ! "$python" -c 'import mitsuba, numpy' 2>/dev/null; then
  echo "== the Mitsuba 3 comparisons: skipped, $python has no mitsuba or numpy (make bench installs them: scripts/install-deps.sh --bench DIR)"
  exit 0
fi
echo "== the farm against Mitsuba 3 (scalar_rgb) on a textured glTF and on metallic and rough materials"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/run.py" "$build" "$tmp/crosscheck"
echo "== the Cornell box light's edge, box against Gaussian and Mitchell pixel filters, each against Mitsuba 3 with the matching filter"
"${BENCH_PYTHON:-python3}" "$root/bench/filters/light_edge.py" "$build" "$tmp/filters"
echo "== the farm against a long Mitsuba reference on the Cornell scenes: regions, rounds, equal time (issue 14)"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/converge.py" "$build" "$tmp/converge"
echo "== adaptive against uniform sampling on the caustics scene at equal time, against the same reference (issue 14)"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/adaptive.py" "$build" "$tmp/adaptive"
echo "== the error estimate against the error measured against the same references, round by round over three seeds, on the Cornell box, the caustics box and the fog box (issue 14, acceptance 5; target within 25% from round 3, the mean estimate falling)"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/estimate.py" "$build" "$tmp/estimate"
echo "== the fog Cornell box against Mitsuba 3's volumetric path tracer: relMSE of the converged images (target 0.01; issue 15)"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/fog.py" "$build" "$tmp/fog"
echo "== the god-rays room, error against time: the farm and Mitsuba 3's volpath, time to relMSE 0.01 against a long Mitsuba reference (issue 15)"
"${BENCH_PYTHON:-python3}" "$root/bench/crosscheck/god_rays.py" "$build" "$tmp/god-rays"
