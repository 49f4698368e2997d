#!/usr/bin/env bash
# Installs what Shapewright needs on a fresh machine (Debian 12, Rust and
# Python 3.11 present): system packages, a Python venv in .venv with the
# packages in requirements.txt, and the release build of the host.
# Idempotent: a second run only checks. Sourced by demo.sh and test.sh.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

need_cmd() { command -v "$1" >/dev/null 2>&1 || { echo "setup: '$1' is missing; $2" >&2; exit 1; }; }
need_cmd cargo "install Rust (rustup) first"
need_cmd python3 "install Python 3.11 first"

# System packages (only those not present yet).
apt_pkgs=()
# cmake and g++ build the OpenXR loader bundled by the openxr crate;
# libvulkan1 and mesa-vulkan-drivers give Vulkan on the CPU (lavapipe);
# nats-server (JetStream) carries shared sessions (scripts/nats.sh, and the
# shapewright-net tests start their own on 127.0.0.1).
# prusa-slicer (Debian's 2.5, slices from the command line without a display)
# checks that exported STL and 3MF files print at true size (tests/python/test_slicer.py).
# The Windows host and wheels are cross-built with mingw-w64 (the -posix
# compilers come with these) and the host is tested under wine64, whose
# Vulkan reaches lavapipe through its X11 driver on xvfb (scripts/test_windows.sh).
for p in ${SHAPEWRIGHT_APT_PACKAGES:-cmake g++ libvulkan1 mesa-vulkan-drivers nats-server prusa-slicer \
    gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64 wine wine64 xvfb}; do
  dpkg -s "$p" >/dev/null 2>&1 || apt_pkgs+=("$p")
done
if [ "${#apt_pkgs[@]}" -gt 0 ]; then
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${apt_pkgs[@]}"
fi

# xr: the OpenXR core validation layer; the Monado integration tests run
# one session under it (Monado itself is built by scripts/monado.sh).
if ! dpkg -s openxr-layer-corevalidation >/dev/null 2>&1; then
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq openxr-layer-corevalidation
fi

# Python venv.
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
stamp=".venv/.requirements.sha"
want="$(sha256sum requirements.txt | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  .venv/bin/pip install -q --upgrade pip
  .venv/bin/pip install -q -r requirements.txt
  echo "$want" > "$stamp"
fi

# release (issue 32): the extension's wheels are cross-built for Windows
# (mingw-w64, installed above) and macOS (zig, from .venv); rustup adds
# each target's standard library once.
installed_targets="$(rustup target list --installed)"
for t in x86_64-pc-windows-gnu aarch64-apple-darwin x86_64-apple-darwin; do
  grep -qx "$t" <<<"$installed_targets" || rustup target add "$t"
done
