#!/usr/bin/env bash
# Cross-builds the standalone host for Windows x86_64 (issue 32):
#   bash scripts/build_windows.sh
# writes target/windows/x86_64-pc-windows-gnu/release/shapewright-xr.exe (and the
# crash-test fixture crash_writer.exe beside it in examples/) and prints
# the exe's path last. The OpenXR loader is linked statically (openxr-sys
# `static`, built by cmake with the mingw toolchain file
# .cargo/mingw-w64-x86_64.cmake), as are libgcc, libstdc++ and winpthread
# (.cargo/config.toml): the exe imports only DLLs Windows ships, which
# this script checks in its import table.
#
# Needs Debian's gcc-mingw-w64-x86-64, g++-mingw-w64-x86-64 (the -posix
# compilers) and cmake (scripts/setup.sh installs them); adds the Rust
# target when it is missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
target=x86_64-pc-windows-gnu

for tool in x86_64-w64-mingw32-gcc-posix x86_64-w64-mingw32-g++-posix x86_64-w64-mingw32-objdump cmake; do
  if ! command -v "$tool" >/dev/null; then
    echo "build_windows: $tool is missing; install gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64 cmake (apt-get)" >&2
    exit 1
  fi
done
if ! rustup target list --installed | grep -qx "$target"; then
  rustup target add "$target" >&2
fi

# SHAPEWRIGHT_TEST_PROFILE=dev (scripts/test.sh) builds in cargo's dev
# profile, like the Linux host the wine tests compare it with: dependencies
# optimized, the workspace at opt-level 1; cold, 337 s against release's
# 375 s on two cores (2026-11-29), and the two hosts the wine tests compare
# are built alike. Shipping (release.sh) unsets it.
profile="${SHAPEWRIGHT_TEST_PROFILE:-release}"
# Its own target dir (the Windows wheel of build_addon.sh uses it too, so
# the two share the cross-built core). In the common one, this build held
# the lock on target/debug (a cross build keeps its build scripts and proc
# macros there) for all of its minutes, and scripts/test.sh's foreground
# `cargo test` waited behind it (a cold run of 2026-12-01, seen in
# /proc/locks): the background build did not fill the foreground's idle
# time, it came first. The price: the host-side build scripts and proc
# macros are compiled a second time.
tdir="${CARGO_TARGET_DIR:-$root/target}/windows"
start=$SECONDS
cargo build --profile "$profile" --target "$target" --target-dir "$tdir" -p shapewright-xr --bin shapewright-xr >&2
cargo build --profile "$profile" --target "$target" --target-dir "$tdir" -p shapewright-atomic --example crash_writer >&2
echo "build_windows: built ($profile) in $((SECONDS - start)) s" >&2

[ "$profile" = dev ] && dir=debug || dir="$profile"
out="$tdir/$target/$dir"
exe="$out/shapewright-xr.exe"

# The import table: every DLL must be one Windows ships. A mingw runtime
# DLL (libgcc_s_seh-1, libstdc++-6, libwinpthread-1) or the OpenXR loader
# (openxr_loader.dll) here would make the exe fail to start on a clean
# Windows. vulkan-1.dll is not imported: ash loads it at run time (GPU
# drivers install it), and the headset host says so when it is missing.
allowed=" kernel32.dll ntdll.dll advapi32.dll msvcrt.dll ws2_32.dll userenv.dll \
bcrypt.dll bcryptprimitives.dll user32.dll shell32.dll ole32.dll oleaut32.dll \
secur32.dll crypt32.dll ncrypt.dll iphlpapi.dll dbghelp.dll \
api-ms-win-core-synch-l1-2-0.dll "
check_imports() {
  local file=$1 bad=0 dll
  while read -r dll; do
    if [[ "$allowed" != *" ${dll,,} "* ]]; then
      echo "build_windows: $(basename "$file") imports $dll, which Windows does not ship" >&2
      bad=1
    fi
  done < <(x86_64-w64-mingw32-objdump -p "$file" | sed -n 's/^\s*DLL Name: //p')
  return $bad
}
check_imports "$exe"
check_imports "$out/examples/crash_writer.exe"
echo "build_windows: imports $(x86_64-w64-mingw32-objdump -p "$exe" | sed -n 's/^\s*DLL Name: //p' | tr '\n' ' ')" >&2
echo "$exe"
