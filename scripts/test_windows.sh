#!/usr/bin/env bash
# The Windows host under wine, against the Linux build (issue 32), and the
# core's Android check:
#   bash scripts/test_windows.sh [pytest args...]
# 1. cross-builds shapewright-xr.exe (scripts/build_windows.sh) and the
#    Linux binary, both in release, or both in dev with SHAPEWRIGHT_TEST_PROFILE=dev;
# 2. builds the wine-only ProcessPrng shim (tests/windows/processprng_shim.c:
#    wine 8 lacks bcryptprimitives.dll, which Rust's std imports; never
#    shipped) and puts it beside copies of the exes in target/wine-test/;
# 3. makes a wine prefix once (target/wine-test/prefix; no Mono/Gecko);
# 4. runs tests/windows under xvfb-run (wine's Vulkan reaches the host's
#    lavapipe only through its X11 driver);
# 5. `cargo check --target aarch64-linux-android -p shapewright`: the core
#    stays portable to standalone headsets (docs/standalone.md);
#    SHAPEWRIGHT_ANDROID_CHECK=0 skips it (CI does).
# Needs wine64, the mingw-w64 compilers and xvfb (scripts/setup.sh).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
wine="${SHAPEWRIGHT_WINE:-/usr/lib/wine/wine64}"
for tool in "$wine" wineboot wineserver xvfb-run x86_64-w64-mingw32-gcc; do
  command -v "$tool" >/dev/null || {
    echo "test_windows: $tool is missing; install wine64 xvfb gcc-mingw-w64-x86-64 (apt-get)" >&2
    exit 1
  }
done

start=$SECONDS
exe="$(bash scripts/build_windows.sh | tail -n 1)"
echo "test_windows: Windows build $((SECONDS - start)) s" >&2
# The Linux build to compare with: SHAPEWRIGHT_TEST_PROFILE=dev (test.sh)
# takes the one `cargo test` built; otherwise release.
if [ "${SHAPEWRIGHT_TEST_PROFILE:-release}" = dev ]; then
  linux_exe="${CARGO_TARGET_DIR:-$root/target}/debug/shapewright-xr"
  [ -x "$linux_exe" ] || cargo build -q -p shapewright-xr
else
  cargo build --release -q -p shapewright-xr
  linux_exe="${CARGO_TARGET_DIR:-$root/target}/release/shapewright-xr"
fi

work="$root/target/wine-test"
mkdir -p "$work/bin"
cp "$exe" "$work/bin/shapewright-xr.exe"
cp "$(dirname "$exe")/examples/crash_writer.exe" "$work/bin/crash_writer.exe"
x86_64-w64-mingw32-gcc -O2 -shared -o "$work/bin/bcryptprimitives.dll" \
  tests/windows/processprng_shim.c -ladvapi32

export WINEPREFIX="$work/prefix" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree=;mshtml="
if [ ! -f "$WINEPREFIX/system.reg" ]; then
  wineboot -i >/dev/null 2>&1
fi
# wineboot leaves the prefix's wineserver and desktop (explorer.exe) running
# for a while, and that desktop chose its display driver with no DISPLAY:
# the null one. Wine processes take the running desktop's driver, so tests
# started before it exits find no Vulkan (vkCreateInstance fails with
# VK_ERROR_INITIALIZATION_FAILED; CI of 2026-11-29). They start with no
# wine process left, and their desktop starts under xvfb-run's display.
wineserver -k >/dev/null 2>&1 || true
wineserver -w
# A running wineserver of this prefix is shared by the runs; stop it at exit.
trap 'wineserver -k >/dev/null 2>&1 || true' EXIT

export SHAPEWRIGHT_WIN_EXE="$work/bin/shapewright-xr.exe"
export SHAPEWRIGHT_WIN_CRASH_WRITER="$work/bin/crash_writer.exe"
export SHAPEWRIGHT_LINUX_EXE="$linux_exe"
export SHAPEWRIGHT_WINE="$wine"
t=$SECONDS
xvfb-run -a .venv/bin/python -m pytest -q -p no:cacheprovider tests/windows "$@"
echo "test_windows: wine tests $((SECONDS - t)) s" >&2

# The core for Android (standalone headsets): the target's std is enough
# for a check; linking would need the NDK, which no registry here serves.
if [ "${SHAPEWRIGHT_ANDROID_CHECK:-1}" != 0 ]; then
  rustup target list --installed | grep -qx aarch64-linux-android || rustup target add aarch64-linux-android >&2
  cargo check -q --target aarch64-linux-android -p shapewright
fi
echo "test_windows: done in $((SECONDS - start)) s" >&2
