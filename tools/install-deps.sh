#!/usr/bin/env bash
# @brief Installs the Debian packages fovea needs, and nothing else. The one list of packages lives here.
# Fast when everything is present: it only asks dpkg. Run as root (or with sudo available) on Debian 12.
set -euo pipefail

PACKAGES=(
  # build
  cmake make gcc clang pkg-config libclang-rt-14-dev
  # Vulkan: loader, headers, Mesa lavapipe (CPU driver), validation layer, shader compiler and validator
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools spirv-tools vulkan-tools
  # models, scene files, images, window
  libassimp-dev libcjson-dev libstb-dev libglfw3-dev
  # eye-tracker I/O
  libhidapi-dev libusb-1.0-0-dev zlib1g-dev
  # live trackers: Pupil Capture's network API (ZeroMQ + msgpack)
  libzmq3-dev libmsgpack-dev
  # CPU reference renderer (ray casting) and the plots of `fovea bench`
  libembree-dev gnuplot-nox
  # tests (image metrics are checked against scikit-image)
  libcmocka-dev python3-skimage python3-numpy
  # window tests: a virtual X server, input and screenshots
  xvfb xauth xdotool x11-apps imagemagick
  # OpenXR runtime (xr/): headers and loader, hello_xr, the core-validation layer; EGL and GLES (the OpenGL test app)
  libopenxr-dev libopenxr-loader1 libopenxr-utils openxr-layer-corevalidation libegl-dev libgles-dev
)
# Wanted but not needed: the tests that use them pass (and say so) without them, so a failed install is a warning.
OPTIONAL=(
  # real-world model files the import tests read where installed (tests/scene/test_scene_import.c)
  assimp-testmodels
)

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

missing=()
for p in "${PACKAGES[@]}"; do
  installed "$p" || missing+=("$p")
done
optional=()
for p in "${OPTIONAL[@]}"; do
  installed "$p" || optional+=("$p")
done
((${#missing[@]} == 0 && ${#optional[@]} == 0)) && exit 0

SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  if ((${#missing[@]} == 0)); then
    command -v sudo >/dev/null || { echo "install-deps: optional packages (${optional[*]}) left out: not root" >&2; exit 0; }
  fi
  command -v sudo >/dev/null || { echo "install-deps: missing packages (${missing[*]}) and not root; run as root" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q >&2 || true
if ((${#missing[@]} > 0)); then
  echo "install-deps: installing ${missing[*]}" >&2
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi
if ((${#optional[@]} > 0)); then
  $SUDO apt-get install -y -q --no-install-recommends "${optional[@]}" >&2 ||
    echo "install-deps: optional packages (${optional[*]}) could not be installed; the tests that read them skip" >&2
fi
