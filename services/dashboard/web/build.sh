#!/usr/bin/env bash
# Builds the dashboard's front end into web/dist (embedded by the Go server).
#
#   build.sh          npm ci (when node_modules is missing or stale), tsc, copy static files
#   build.sh --check  build into a temporary directory and fail if it differs from the
#                     committed dist (run it in CI: dist is committed so that `go build`
#                     works in a fresh clone without npm)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

check=0
case "${1:-}" in
  "") ;;
  --check) check=1 ;;
  *) echo "usage: $0 [--check]" >&2; exit 2 ;;
esac

# npm ci only when the installed tree does not match the lock file.
if ! cmp -s package-lock.json node_modules/.package-lock.json 2>/dev/null &&
   ! { [ -f node_modules/.package-lock.json ] &&
       node -e 'const a=require("./package-lock.json").packages,b=require("./node_modules/.package-lock.json").packages;for(const k of Object.keys(a)){if(k&&(!b[k]||b[k].version!==a[k].version))process.exit(1)}' ; }; then
  npm ci --no-audit --no-fund --loglevel=error
fi

if [ "$check" = 1 ]; then
  out="$(mktemp -d)"
  trap 'rm -rf "$out"' EXIT
else
  out=dist
  rm -rf "$out"
fi

npx --no-install tsc -p . --outDir "$out"
cp static/index.html static/style.css static/favicon.svg "$out"/

if [ "$check" = 1 ]; then
  if ! diff -r "$out" dist >&2; then
    echo "web/dist is stale: run services/dashboard/web/build.sh and commit web/dist" >&2
    exit 1
  fi
  echo "web/dist is up to date"
fi
