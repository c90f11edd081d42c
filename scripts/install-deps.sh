#!/usr/bin/env bash
# Installs everything the build and the tests need on Debian bookworm, and nothing that is
# already there. Safe to run again; the Makefile runs it before building.
set -euo pipefail

# `--bench VENV` also makes VENV a Python virtual environment holding what `make bench`
# alone needs (bench/crosscheck/requirements.txt: the Mitsuba 3 reference renderer); the
# build and make test never ask for it. `--python VENV` makes VENV the virtual environment
# of make test-python: the Python SDK installed as a user installs it, and pytest.
# `--blender VENV` makes one for `make test-blender` (client/blender/requirements.txt: bpy,
# Blender as a Python module, a 374 MB wheel that installs to about 1 GB, so it is kept
# out of make test).
bench_venv=""
python_venv=""
blender_venv=""
while [ $# -gt 0 ]; do
  case "$1" in
    --bench) bench_venv=${2:?"install-deps: --bench needs the virtual environment's folder"} ;;
    --python) python_venv=${2:?"install-deps: --python needs the virtual environment's folder"} ;;
    --blender) blender_venv=${2:?"install-deps: --blender needs the virtual environment's folder"} ;;
    *) echo "install-deps: unknown option $1 (--bench VENV, --python VENV, --blender VENV)" >&2; exit 2 ;;
  esac
  shift 2
done

debian_packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libembree-dev libopenexr-dev libopenimageio-dev openimageio-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libtbb-dev libtinyobjloader-dev libgtest-dev libgmock-dev libbenchmark-dev libnanoflann-dev
  redis-server
  chromium
)
[ -z "$bench_venv$python_venv$blender_venv" ] || debian_packages+=(python3-venv)

missing=()
for pkg in "${debian_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
# Node drives the dashboard's browser test (tests/dashboard). Any node and npm on PATH will
# do (a machine may carry them from elsewhere than Debian, whose npm would conflict).
command -v node >/dev/null 2>&1 || missing+=(nodejs)
command -v npm >/dev/null 2>&1 || missing+=(npm)

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Go is the machine's toolchain (Debian's golang-go is too old for gRPC-Go); go.mod names
# the minimum version.
need_go=$(awk '/^go /{print $2}' "$(dirname "$0")/../go.mod")
if ! command -v go >/dev/null 2>&1; then
  echo "install-deps: no Go toolchain on PATH; install Go $need_go or newer" >&2
  exit 1
fi
have_go=$(go env GOVERSION | sed 's/^go//')
if [ "$(printf '%s\n%s\n' "$need_go" "$have_go" | sort -V | head -n1)" != "$need_go" ]; then
  echo "install-deps: Go $have_go is older than the $need_go that go.mod needs" >&2
  exit 1
fi

# SeaweedFS's weed: the S3-compatible object store the blob store's tests run against
# (coordinator/blobstore/s3test; MinIO is AGPL). Built from its Go module at the version
# scripts/seaweedfs.version pins, into a cache folder the tests look in. Its go.mod has
# replace directives, which `go install MODULE@VERSION` refuses, so it is built inside the
# downloaded module instead. The first build took 7 min of CPU here (30 min of wall time on
# a 2-core machine shared with other builds); nothing after.
seaweed_version=$(cat "$(dirname "$0")/seaweedfs.version")
tools_dir=${FARM_TOOLS_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/photonfarm/tools}
weed="$tools_dir/seaweedfs-$seaweed_version/weed"
if [ ! -x "$weed" ]; then
  echo "install-deps: building SeaweedFS weed $seaweed_version into $(dirname "$weed")"
  seaweed_src=$(cd / && go mod download -json "github.com/seaweedfs/seaweedfs@$seaweed_version" |
    sed -n 's/^[[:space:]]*"Dir": "\(.*\)",$/\1/p')
  mkdir -p "$(dirname "$weed")"
  (cd "$seaweed_src" && GOFLAGS=-buildvcs=false nice -n 15 go build -p 2 -o "$weed.partial" ./weed)
  mv "$weed.partial" "$weed"
fi

# The dashboard's browser test: playwright-core, pinned in tests/dashboard/e2e/package-lock.json,
# drives Debian's /usr/bin/chromium (installed above). playwright-core never downloads a
# browser; the variable says so to anything else that might. npm ci runs only when an
# installed package differs from the lock file.
e2e="$(dirname "$0")/../tests/dashboard/e2e"
if ! (cd "$e2e" && node -e '
  const fs = require("fs");
  const lock = JSON.parse(fs.readFileSync("package-lock.json", "utf8"));
  for (const [path, p] of Object.entries(lock.packages)) {
    if (!path) continue;
    const got = JSON.parse(fs.readFileSync(path + "/package.json", "utf8")).version;
    if (got !== p.version) process.exit(1);
  }' 2>/dev/null); then
  echo "install-deps: npm ci in tests/dashboard/e2e"
  (cd "$e2e" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi

requirements="$(dirname "$0")/../bench/crosscheck/requirements.txt"
if [ -n "$bench_venv" ] && ! "$bench_venv/bin/python" -c 'import mitsuba, numpy' 2>/dev/null; then
  echo "install-deps: Python virtual environment $bench_venv for make bench"
  python3 -m venv "$bench_venv"
  "$bench_venv/bin/pip" install -q -r "$requirements"
fi

# The SDK goes in by `pip install ./client/python[test]`, which generates its protobuf and
# gRPC modules from proto/ (client/python/setup.py), again whenever a tracked file of
# client/python or proto/ has changed since: the digest of their contents is kept in VENV.
if [ -n "$python_venv" ]; then
  root="$(cd "$(dirname "$0")/.." && pwd)"
  sources=$(cd "$root" && git ls-files -z client/python proto | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)
  if [ "$(cat "$python_venv/.photonfarm-sources" 2>/dev/null)" != "$sources" ] ||
     ! "$python_venv/bin/python" -c 'import photonfarm, pytest' 2>/dev/null; then
    echo "install-deps: the Python SDK into $python_venv for make test-python"
    [ -x "$python_venv/bin/python" ] || python3 -m venv "$python_venv"
    "$python_venv/bin/pip" install -q --disable-pip-version-check "$root/client/python[test]"
    echo "$sources" >"$python_venv/.photonfarm-sources"
  fi
fi

# bpy 5.0.1 is built for Python 3.11 only: Debian bookworm's /usr/bin/python3, named so that
# another python3 earlier on PATH (pyenv, conda) does not make the venv.
blender_requirements="$(dirname "$0")/../client/blender/requirements.txt"
if [ -n "$blender_venv" ] && ! "$blender_venv/bin/python" -c 'import bpy, pytest' 2>/dev/null; then
  echo "install-deps: Python virtual environment $blender_venv for make test-blender (bpy: a 374 MB download)"
  /usr/bin/python3 -m venv "$blender_venv"
  "$blender_venv/bin/pip" install -q -r "$blender_requirements"
fi
