#!/usr/bin/env bash
# Builds the farm's container images: photonfarm/redis, photonfarm/objectstore,
# photonfarm/coordinator, photonfarm/dashboard and photonfarm/worker, all on
# debian:bookworm-slim.
#
# The binaries are built on the host and copied in (Debian's Go is too old for this module,
# and the host is bookworm too, so the worker's shared libraries match the runtime image's):
#   deploy/.build/farm         static Go binary (CGO_ENABLED=0): coordinator, dashboard, CLI
#   deploy/.build/farm-worker  the C++ worker from build/bin (make cpp)
#   deploy/.build/weed         SeaweedFS's weed, built by scripts/install-deps.sh
# If debian:bookworm-slim is neither present nor pullable, it is made locally with
# debootstrap from the Debian mirror in /etc/apt/sources.list.d/debian.sources.
#
# Usage: deploy/build-images.sh            (tag: $FARM_IMAGE_TAG, default "local")
# Needs a running Docker engine (deploy/test-compose.sh starts one if none answers).
set -euo pipefail
deploy="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$deploy/.." && pwd)"
tag="${FARM_IMAGE_TAG:-local}"
build_dir="${BUILD_DIR:-$root/build}"
export PATH="$PATH:/usr/local/go/bin"

now() { echo "$EPOCHREALTIME"; }
since() { awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1fs", b - a }'; }
# The classic builder: Debian's engine has no BuildKit plugin, and these images need none.
export DOCKER_BUILDKIT=0

# 1. Host binaries.
t=$(now)
mkdir -p "$deploy/.build"
(cd "$root" && CGO_ENABLED=0 go build -trimpath -o "$deploy/.build/farm" ./cmd/farm)
if ! file "$deploy/.build/farm" | grep -q 'statically linked'; then
  echo "build-images: $deploy/.build/farm is not statically linked" >&2
  exit 1
fi
cmake --build "$build_dir" --target farm-worker -j "$(nproc)" >/dev/null
install -m 0755 "$build_dir/bin/farm-worker" "$deploy/.build/farm-worker"
# SeaweedFS's weed, which scripts/install-deps.sh builds at the version it pins ($FARM_WEED
# overrides, as in coordinator/blobstore/s3test).
weed="${FARM_WEED:-${FARM_TOOLS_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/photonfarm/tools}/seaweedfs-$(cat "$root/scripts/seaweedfs.version")/weed}"
[ -x "$weed" ] || { echo "build-images: no SeaweedFS weed at $weed: run scripts/install-deps.sh" >&2; exit 1; }
install -m 0755 "$weed" "$deploy/.build/weed"
echo "build-images: host binaries in $(since "$t")"

# 2. The base image.
if ! docker image inspect debian:bookworm-slim >/dev/null 2>&1 &&
   ! timeout 30 docker pull -q debian:bookworm-slim >/dev/null 2>&1; then
  t=$(now)
  command -v debootstrap >/dev/null || {
    echo "build-images: debian:bookworm-slim cannot be pulled and debootstrap is missing" \
         "(apt-get install debootstrap)" >&2
    exit 1
  }
  mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
  mirror="${mirror:-http://deb.debian.org/debian}"
  rootfs=$(mktemp -d /tmp/bookworm-rootfs.XXXXXX)
  trap 'rm -rf "$rootfs"' EXIT
  echo "build-images: making debian:bookworm-slim with debootstrap from $mirror"
  debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >/dev/null
  # What the official slim image drops: apt lists, caches, docs and man pages.
  rm -rf "$rootfs"/var/lib/apt/lists/* "$rootfs"/var/cache/apt/*.bin \
         "$rootfs"/usr/share/doc/* "$rootfs"/usr/share/man/*
  tar -C "$rootfs" -c . | docker import - debian:bookworm-slim >/dev/null
  rm -rf "$rootfs"
  trap - EXIT
  echo "build-images: debian:bookworm-slim made in $(since "$t")"
fi

# 3. The images. One small context: the Dockerfiles, the entrypoints and the binaries.
for image in redis objectstore coordinator dashboard worker; do
  t=$(now)
  log=$(mktemp)
  if ! docker build -t "photonfarm/$image:$tag" -f "$deploy/docker/$image.Dockerfile" "$deploy" >"$log" 2>&1; then
    cat "$log" >&2; rm -f "$log"
    echo "build-images: photonfarm/$image:$tag failed" >&2
    exit 1
  fi
  rm -f "$log"
  size=$(docker image inspect -f '{{.Size}}' "photonfarm/$image:$tag")
  echo "build-images: photonfarm/$image:$tag ($((size / 1000000)) MB) in $(since "$t")"
done
