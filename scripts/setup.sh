#!/usr/bin/env bash
# Installs the Debian packages hlodr needs to build, test and run, skipping those already there.
# Runs as root (or through sudo when available). Safe to run again.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libgtest-dev libgmock-dev libbenchmark-dev
  libglm-dev libopenmesh-dev libmeshoptimizer-dev libopenimageio-dev
  libtinygltf-dev libstb-dev nlohmann-json3-dev libcpp-httplib-dev libdeflate-dev libturbojpeg0-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6 libosmesa6-dev
  ffmpeg
  prometheus wrk curl
  chromium
)
# The browser test (tests/web) needs node and npm. Debian's npm conflicts with a Node that was
# installed another way, so both come from Debian only when there is no npm at all.
command -v npm >/dev/null || packages+=(nodejs npm)

# --runtime-packages BINARY: the Debian packages that hold the libraries BINARY links (from ldd),
# plus what hlodr opens at run time (Mesa's EGL and OSMesa drivers) or runs (ffmpeg): the list
# of a runtime image.
if [ "${1:-}" = "--runtime-packages" ]; then
  bin=${2:?usage: setup.sh --runtime-packages BINARY}
  { ldd "$bin" | awk '/=> \//{print $3}' | xargs -r -n1 readlink -f | xargs -r dpkg -S 2>/dev/null \
      | cut -d: -f1
    printf '%s\n' libegl1 libegl-mesa0 libgl1-mesa-dri libosmesa6 ffmpeg; } | sort -u | tr '\n' ' '
  echo
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
