#!/usr/bin/env bash
# Installs the Debian 12 packages pathfarm needs, only if some are missing (TOOLCHAIN.md).
set -euo pipefail

PACKAGES=(
  cmake ninja-build ccache g++ pkg-config git python3 clang-format
  libglm-dev libspdlog-dev libtbb-dev zlib1g-dev libzstd-dev
  libopenimageio-dev libembree-dev embree-tools
  libtinygltf-dev libtinyobjloader-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libasio-dev libprotobuf-dev protobuf-compiler libssl-dev
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  gnuplot-nox libturbojpeg0-dev libsdl2-dev xvfb xauth xdotool
  libwebsocketpp-dev python3-prometheus-client python3-websocket chromium
  libavcodec-dev libavutil-dev libswscale-dev
  clang libclang-rt-14-dev bc python3-yaml openssl
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install_deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q -o DPkg::Lock::Timeout=600
$SUDO apt-get install -y -q --no-install-recommends -o DPkg::Lock::Timeout=600 "${missing[@]}"
