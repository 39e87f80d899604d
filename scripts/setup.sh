#!/usr/bin/env bash
# Installs the Debian packages hlodr needs to build, test and run, skipping those already there.
# Runs as root (or through sudo when available). Safe to run again.
#   scripts/setup.sh                      everything (build, run, tests)
#   scripts/setup.sh --build-only         what building and running need
#   scripts/setup.sh --runtime-packages BINARY   prints the packages a runtime image needs
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libgtest-dev libgmock-dev libbenchmark-dev
  libglm-dev libopenmesh-dev libmeshoptimizer-dev libopenimageio-dev
  libtinygltf-dev libstb-dev nlohmann-json3-dev libcpp-httplib-dev libdeflate-dev libturbojpeg0-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6 libosmesa6-dev
  ffmpeg
)
# What only the tests and benchmarks use (skipped by --build-only, as the image's build stage
# does): promtool, the load balancer of the deploy test (haproxy), the load generator, the browser, and clang with its sanitizer and libFuzzer
# runtimes (libclang-rt-14-dev) for the sanitizer build and the fuzz targets. The browser test
# needs node and npm too; Debian's npm conflicts with a Node installed another way, so both come
# from Debian only when there is no npm at all.
if [ "${1:-}" != "--build-only" ]; then
  packages+=(prometheus haproxy wrk curl chromium clang libclang-rt-14-dev)
  command -v npm >/dev/null || packages+=(nodejs npm)
fi

# --runtime-packages BINARY: the Debian packages that hold the libraries BINARY links (from ldd),
# plus what hlodr opens at run time (Mesa's EGL and OSMesa drivers) or runs (ffmpeg): the list
# of a runtime image.
if [ "${1:-}" = "--runtime-packages" ]; then
  bin=${2:?usage: setup.sh --runtime-packages BINARY}
  {
    for lib in $(ldd "$bin" | awk '/=> \//{print $3}'); do
      real=$(readlink -f "$lib")
      pkg=""
      # Debian 12 merges /lib into /usr/lib: dpkg knows a library under one of the two names.
      for p in "$lib" "$real" "${real#/usr}" "/usr$lib"; do
        pkg=$(dpkg -S "$p" 2>/dev/null | head -n1 | cut -d: -f1) || true
        [ -n "$pkg" ] && break
      done
      if [ -n "$pkg" ]; then echo "$pkg"; else echo "setup: no package holds $lib" >&2; fi
    done
    printf '%s\n' libegl1 libegl-mesa0 libgl1-mesa-dri libosmesa6 ffmpeg
  } | sort -u | tr '\n' ' '
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
