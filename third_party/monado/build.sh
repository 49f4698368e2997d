#!/usr/bin/env bash
# Builds Monado, the open-source OpenXR runtime, from the source tarball in
# this folder, as an in-process runtime (no monado-service) with the null
# compositor (renders into nothing, Vulkan on lavapipe) and two drivers:
#   simulated  an HMD only: no controllers, and no hand tracking
#   remote     an HMD plus two Valve Index controllers with hand tracking,
#              driven over TCP port 4242 (src/xrt/drivers/remote/)
# Prints the path of the runtime manifest (for XR_RUNTIME_JSON) on its last line.
#
#   bash build.sh [BUILD_DIR]        default: $XDG_CACHE_HOME/monado (~/.cache/monado)
#
# A second run with the same BUILD_DIR only checks (about a second).
# Build time on 2 cores: 56 s measured (2026-11-29), once the packages are in. Needs root for apt-get (or sudo).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
tarball="$(ls "$here"/monado-src-*.tar.xz | tail -n 1)"
out="${1:-${XDG_CACHE_HOME:-$HOME/.cache}/monado}"
manifest="$out/build/openxr_monado-dev.json"
stamp="$out/.built-from"
if [ -f "$manifest" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$(basename "$tarball")" ]; then
  echo "$manifest"; exit 0
fi

pkgs="cmake ninja-build g++ pkg-config libeigen3-dev libvulkan-dev glslang-tools glslang-dev
  libgl-dev libx11-dev libxrandr-dev libxcb-randr0-dev libx11-xcb-dev libxcb1-dev libwayland-dev
  libbsd-dev libusb-1.0-0-dev libhidapi-dev libudev-dev libcjson-dev mesa-vulkan-drivers libvulkan1"
missing=()
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ "${#missing[@]}" -gt 0 ]; then
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi

rm -rf "$out"; mkdir -p "$out"
tar -xJf "$tarball" -C "$out"
src="$(ls -d "$out"/monado*-src | head -n 1)"
off=""
for d in UVC ARDUINO BLUBUR_S1 CONTACTGLOVE DAYDREAM DEPTHAI EUROC HANDTRACKING TWRAP HDK HYDRA \
         ILLIXR NS OHMD OPENGLOVES UDCAP PSMV PSSENSE PSVR PSVR2 QWERTY REALSENSE RIFT RIFT_SENSOR \
         RIFT_S ROKID STEAMVR_LIGHTHOUSE SURVIVE ULV2 ULV5 VF VIVE WMR XREAL_AIR SIMULAVR SOLARXR; do
  off="$off -DXRT_BUILD_DRIVER_$d=OFF"
done
for h in OPENCV SDL2 GST WAYLAND OPENGL OPENGLES EGL SYSTEMD DBUS V4L2 LIBUVC FFMPEG JPEG; do
  off="$off -DXRT_HAVE_$h=OFF"
done
# shellcheck disable=SC2086
cmake -G Ninja -S "$src" -B "$out/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo $off \
  -DXRT_BUILD_DRIVER_SIMULATED=ON -DXRT_BUILD_DRIVER_REMOTE=ON \
  -DXRT_FEATURE_SERVICE=OFF -DXRT_MODULE_COMPOSITOR_NULL=ON \
  -DXRT_FEATURE_STEAMVR_PLUGIN=OFF -DXRT_FEATURE_WINDOW_PEEK=OFF -DXRT_FEATURE_TRACING=OFF \
  -DXRT_FEATURE_GESTURE_DETECTOR=OFF -DXRT_MODULE_MONADO_CLI=OFF \
  -DBUILD_TESTING=OFF -DXRT_BUILD_SAMPLES=OFF -DBUILD_DOC=OFF >"$out/configure.log" 2>&1 \
  || { tail -n 30 "$out/configure.log" >&2; exit 1; }
cmake --build "$out/build" -j "$(nproc)" >"$out/build.log" 2>&1 || { tail -n 30 "$out/build.log" >&2; exit 1; }
[ -f "$manifest" ] || { echo "monado: no manifest at $manifest" >&2; exit 1; }
basename "$tarball" >"$stamp"
echo "$manifest"
