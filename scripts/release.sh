#!/usr/bin/env bash
# Builds every release artifact into dist/, from a fresh clone, in one
# command (scripts/setup.sh installs what is missing first):
#   bash scripts/release.sh
# dist/
#   blender/shapewright-<v>-<platform>.zip   the Blender extension, one per platform
#   blender/index.json, index.html           a self-hosted extension repository over them
#   wheels/shapewright-<v>-cp311-abi3-*.whl  the native wheels inside those zips
#   shapewright-xr-<v>-linux-x64.tar.gz      the headset host for Linux
#   shapewright-xr-<v>-windows-x64.zip       the headset host for Windows (scripts/build_windows.sh)
#   THIRD_PARTY_NOTICES-*.txt                the notices each artifact also carries inside
#   SHA256SUMS                               every file above (sha256sum -c SHA256SUMS)
# Then runs tests/release over the extension (every platform required),
# and the Blender suite (tests/blender) on the linux-x64 zip as shipped.
# Takes about an hour cold on 2 cores (five release builds of the core);
# SHAPEWRIGHT_RELEASE_PLATFORMS="linux-x64 windows-x64" limits the extension.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source scripts/setup.sh
cd "$root"
export PATH="$root/.venv/bin:$PATH"
version="$(python -c 'import tomllib; print(tomllib.load(open("Cargo.toml", "rb"))["workspace"]["package"]["version"])')"
start=$SECONDS
say() { echo "== release: $* [at $((SECONDS - start)) s]"; }

# The test switches of build_addon.sh make wheels that are not for shipping.
unset SHAPEWRIGHT_ADDON_HOST SHAPEWRIGHT_ADDON_LINK_CHECK SHAPEWRIGHT_TEST_PROFILE
rm -rf dist
mkdir -p dist/blender dist/wheels

say "Blender extension (${SHAPEWRIGHT_RELEASE_PLATFORMS:-all platforms})"
# shellcheck disable=SC2086
bash scripts/build_addon.sh ${SHAPEWRIGHT_RELEASE_PLATFORMS:-all}
expect=all
[ -n "${SHAPEWRIGHT_RELEASE_PLATFORMS:-}" ] && expect=
SHAPEWRIGHT_EXPECT_PLATFORMS="$expect" python -m pytest -q -p no:cacheprovider tests/release
cp out/extension/*.zip out/extension/index.json out/extension/index.html dist/blender/
# The shipped linux-x64 zip (zig-linked, manylinux_2_28) through the whole
# Blender suite: the tests' own zip is linked by this machine's toolchain.
linux_zip="$(ls -1 dist/blender/shapewright-*-linux_x64.zip 2>/dev/null || true)"
if [ -n "$linux_zip" ]; then
  say "the Blender suite on $(basename "$linux_zip")"
  SHAPEWRIGHT_ADDON_ZIP="$root/$linux_zip" python -m pytest -q -p no:cacheprovider tests/blender
fi
cp out/wheels/*.whl dist/wheels/
cp out/addon-stage/shapewright_blender/THIRD_PARTY_NOTICES.txt dist/THIRD_PARTY_NOTICES-blender-extension.txt

# A host archive: the binary, the licences, its notices (the crates in it,
# the DejaVu font it draws labels with).
host_notices() {  # target out
  python scripts/notices.py --package shapewright-xr --target "$1" --title "shapewright-xr ($1)" \
    --extra "xr_host/assets/fonts/DejaVu-LICENSE.txt:DejaVu Sans Condensed (the font bundled in the binary)" \
    --out "$2"
}
stage_host() {  # dir binary notices
  mkdir -p "$1"
  cp "$2" "$1/"
  cp LICENSE-MIT LICENSE-APACHE "$1/"
  cp "$3" "$1/THIRD_PARTY_NOTICES.txt"
}

say "Linux host"
cargo build --release -q -p shapewright-xr
name="shapewright-xr-$version-linux-x64"
host_notices x86_64-unknown-linux-gnu "dist/THIRD_PARTY_NOTICES-$name.txt"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
stage_host "$tmp/$name" "${CARGO_TARGET_DIR:-target}/release/shapewright-xr" "dist/THIRD_PARTY_NOTICES-$name.txt"
tar --sort=name --owner=0 --group=0 --numeric-owner --mtime='2026-01-01 00:00Z' \
  -C "$tmp" -czf "dist/$name.tar.gz" "$name"

say "Windows host"
name="shapewright-xr-$version-windows-x64"
if [ -f scripts/build_windows.sh ]; then
  exe="$(bash scripts/build_windows.sh | tail -1)"
  host_notices x86_64-pc-windows-gnu "dist/THIRD_PARTY_NOTICES-$name.txt"
  stage_host "$tmp/$name" "$exe" "dist/THIRD_PARTY_NOTICES-$name.txt"
  (cd "$tmp" && TZ=UTC find "$name" -exec touch -d '2026-01-01 00:00' {} + && \
    find "$name" -type f | sort | python -c '
import sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as z:
    for line in sys.stdin:
        z.write(line.strip())
' "$root/dist/$name.zip")
else
  echo "release: scripts/build_windows.sh is not here: no Windows host in dist/ (it comes with the winhost work)" >&2
fi

say "checksums"
(cd dist && find . -type f ! -name SHA256SUMS | sed 's|^\./||' | LC_ALL=C sort | xargs sha256sum > SHA256SUMS)
cat dist/SHA256SUMS
say "done"
