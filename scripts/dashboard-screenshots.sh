#!/usr/bin/env bash
# Regenerates the README's pictures of the dashboard (docs/images/dashboard-running.png and
# dashboard-done.png): runs the dashboard's browser test against a real farm, which saves
# the job page mid-job (round 2 of 4 read, the mosaic converging) and after it.
# Needs a build (make build) for the farm's binaries.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
shots="$(mktemp -d)"
trap 'rm -rf "$shots"' EXIT
FARM_BIN_DIR="$PWD/build/bin" DASHBOARD_SCREENSHOT_DIR="$shots" \
  go test -count=1 -run 'TestDashboardInABrowser$' ./tests/dashboard/ >&2
cp "$shots/job-page-running.png" docs/images/dashboard-running.png
cp "$shots/job-page-done.png" docs/images/dashboard-done.png
echo "wrote docs/images/dashboard-running.png and docs/images/dashboard-done.png"
