#!/usr/bin/env bash
# Install every Debian 12 package raystream builds, tests and runs with. Idempotent: does
# nothing when all are present. Needs root (CI and the README commands run as root).
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libcglm-dev libassimp-dev libcmocka-dev libpng-dev libcjson-dev
  libhidapi-dev libusb-1.0-0-dev
  # OpenCV components for backends/opencv (the libopencv-dev meta-package adds ~40 more,
  # VTK and MPI among them)
  libopencv-core-dev libopencv-imgproc-dev libopencv-calib3d-dev libopencv-imgcodecs-dev
  libopencv-videoio-dev
  clang-14 libclang-rt-14-dev clang-format-14
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libgbm-dev libosmesa6-dev
  libturbojpeg0-dev libx11-dev xvfb x11-apps
  gnuplot-nox
  jq  # tools/paper-tables.sh reads raystream-bench --json
)

# Intel Embree 3: the peer tracer of raystream-bench --table 2, a benchmark-only dependency
# (CMake builds the peer only when it finds Embree).
packages+=(libembree-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "deps: installing ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "deps: need root to install packages (run as root or with sudo)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: done"
