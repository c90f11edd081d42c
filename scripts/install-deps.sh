#!/usr/bin/env bash
# Installs everything the build and the tests need on Debian bookworm, and nothing that is
# already there. Safe to run again; the Makefile runs it before building.
set -euo pipefail

debian_packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libembree-dev libopenexr-dev libopenimageio-dev openimageio-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libtbb-dev libtinyobjloader-dev libgtest-dev libgmock-dev libbenchmark-dev libnanoflann-dev
  redis-server golang-go
)

missing=()
for pkg in "${debian_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
# A Go toolchain already on PATH (newer than Debian's) is used as is.
if command -v go >/dev/null 2>&1; then
  filtered=()
  for pkg in "${missing[@]}"; do [ "$pkg" = golang-go ] || filtered+=("$pkg"); done
  missing=("${filtered[@]+"${filtered[@]}"}")
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
