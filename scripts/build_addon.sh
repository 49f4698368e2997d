#!/usr/bin/env bash
# Builds the Blender extension: one abi3-py311 wheel of the native module
# per platform (maturin; cross-built here: mingw for Windows, zig for macOS
# and Linux), then one extension zip per platform with Blender's own tool
# (`blender_ext.py build --split-platforms`), each checked by its
# `validate`.
#   bash scripts/build_addon.sh                  linux-x64 only (what tests/blender installs)
#   bash scripts/build_addon.sh all              every platform in blender_manifest.toml
#   bash scripts/build_addon.sh windows-x64 macos-arm64 ...
# Output: out/wheels/*.whl, out/extension/shapewright-<version>-<platform>.zip,
# and the linux-x64 zip also as out/shapewright-<version>-linux_x64.zip
# (the one zip there: the test fixtures and blender_newest.sh take it).
# The add-on is staged in out/addon-stage (the source tree is not written):
# its manifest lists the platforms built, plus THIRD_PARTY_NOTICES.txt for
# the crates in those wheels.
# Switches for testing, never for shipping (release.sh clears them):
# SHAPEWRIGHT_ADDON_HOST=1 builds the linux-x64 wheel with this machine's
#   own toolchain (no zig, no --target) in SHAPEWRIGHT_TEST_PROFILE
#   (release when unset; test.sh sets dev), so it shares the compiled
#   dependencies with the host and the tests (about 90 s instead of a
#   cold release build of the core, 9 min on 2 cores), and in dev, with
#   the `testkit` feature, the compiled core too. Its tag is what
#   maturin's audit finds for this machine's glibc (manylinux_2_34 on Debian 12), not the manylinux_2_28 the shipped
#   wheel carries; the staged manifest names it. scripts/test.sh sets it.
# SHAPEWRIGHT_TEST_PROFILE also builds the windows-x64 wheel, in that
#   profile, sharing the core build_windows.sh cross-built for the wine tests.
# SHAPEWRIGHT_ADDON_LINK_CHECK="macos-arm64 ..." builds those platforms'
#   wheels in the `link-check` profile (unoptimized, same link): CI checks
#   their tags, exports and load commands but cannot run them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="$root/.venv/bin:$PATH"
addon=blender_addon/shapewright_blender
manifest="$addon/blender_manifest.toml"
# Blender 4.2 (the oldest line the manifest admits) needs macOS 11.
export MACOSX_DEPLOYMENT_TARGET="${MACOSX_DEPLOYMENT_TARGET:-11.0}"

all_platforms=$(python -c 'import sys, tomllib; print(" ".join(tomllib.load(open(sys.argv[1], "rb"))["platforms"]))' "$manifest")
if [ "$#" -eq 0 ]; then
  platforms=(linux-x64)
elif [ "$1" = all ]; then
  read -r -a platforms <<<"$all_platforms"
else
  platforms=("$@")
fi

# platform -> Rust target and maturin's flags for it.
rust_target() {
  case "$1" in
    linux-x64) echo x86_64-unknown-linux-gnu ;;
    windows-x64) echo x86_64-pc-windows-gnu ;;
    windows-arm64) echo aarch64-pc-windows-gnullvm ;;
    macos-arm64) echo aarch64-apple-darwin ;;
    macos-x64) echo x86_64-apple-darwin ;;
    *) echo "build_addon: unknown platform '$1' (known: $all_platforms)" >&2; return 1 ;;
  esac
}
maturin_flags() {
  case "$1" in
    linux-x64) echo --zig --compatibility manylinux_2_28 ;;
    # mingw-w64's gcc (rustc's default linker for the target); pyo3 links
    # python3.dll by raw-dylib, so no Windows Python is needed to build.
    windows-x64) echo ;;
    windows-arm64 | macos-*) echo --zig ;;
  esac
}

# SHAPEWRIGHT_ADDON_WHEELS_ONLY=DIR builds just the wheels, into DIR, and
# leaves out/ alone (scripts/test.sh warms the macOS build this way in the
# background while the tests run).
wheels_only="${SHAPEWRIGHT_ADDON_WHEELS_ONLY:-}"
wheels_dir="${wheels_only:-out/wheels}"
if [ -z "$wheels_only" ]; then
  rm -rf out/wheels out/extension out/addon-stage
  mkdir -p out/extension
fi
mkdir -p "$wheels_dir"
targets=()
for p in "${platforms[@]}"; do
  t="$(rust_target "$p")"
  targets+=("--target" "$t")
  echo "build_addon: wheel for $p ($t)" >&2
  if [[ "$p" == linux-x64 && "${SHAPEWRIGHT_ADDON_HOST:-}" == 1 ]]; then
    # In the dev profile of scripts/test.sh, with the features `cargo test
    # --workspace` built the core with (native/Cargo.toml's `testkit`), so
    # the core is linked from that build, not compiled again.
    features=()
    [ "${SHAPEWRIGHT_TEST_PROFILE:-}" = dev ] && features=(--features testkit)
    maturin build --profile "${SHAPEWRIGHT_TEST_PROFILE:-release}" "${features[@]}" -q \
      -m blender_addon/native/Cargo.toml -o "$wheels_dir"
  else
    profile=(--release)
    if [[ "$p" == windows-x64 ]]; then
      # The Windows host's target dir (build_windows.sh says why it has its
      # own) and, in tests, the profile it was built in: the two share the
      # cross-built core.
      [ -n "${SHAPEWRIGHT_TEST_PROFILE:-}" ] && profile=(--profile "$SHAPEWRIGHT_TEST_PROFILE")
      profile+=(--target-dir "${CARGO_TARGET_DIR:-$root/target}/windows")
    elif [[ " ${SHAPEWRIGHT_ADDON_LINK_CHECK:-} " == *" $p "* ]]; then
      # Its own target dir: test.sh builds it in the background while
      # pytest builds the linux wheel, and two maturins in one target dir
      # race on its staging folder (target/maturin).
      profile=(--profile link-check --target-dir "${CARGO_TARGET_DIR:-$root/target}/link-check")
      echo "build_addon: $p in the link-check profile (unoptimized: for checking, not for shipping)" >&2
    fi
    rustc_args=()
    if [[ "$p" == macos-* ]]; then
      # No macOS SDK here: link stubs for the two frameworks the TLS
      # roots crate links (scripts/macos_stubs.py says why that is sound).
      [ -d out/macos-sdk-stubs ] || python scripts/macos_stubs.py out/macos-sdk-stubs
      rustc_args=(-- -C "link-arg=-F$root/out/macos-sdk-stubs")
    fi
    # shellcheck disable=SC2046
    maturin build "${profile[@]}" -q -m blender_addon/native/Cargo.toml --target "$t" $(maturin_flags "$p") \
      -o "$wheels_dir" "${rustc_args[@]}"
  fi
done

[ -z "$wheels_only" ] || exit 0

# The add-on as it ships: source files, the wheels built, a manifest
# listing just those platforms and wheels, the crates' notices.
stage=out/addon-stage/shapewright_blender
mkdir -p "$stage"
cp -r "$addon"/. "$stage"/
rm -rf "$stage/wheels" "$stage/__pycache__"
mkdir -p "$stage/wheels"
cp out/wheels/*.whl "$stage/wheels/"
python - "$stage/blender_manifest.toml" "${platforms[@]}" <<'EOF'
"""Keep in the staged manifest only the platforms built and their wheels
(Blender's build refuses a manifest naming a wheel that is not there)."""
import os
import re
import sys
from pathlib import Path

path, built = Path(sys.argv[1]), sys.argv[2:]
text = path.read_text()
wheels_dir = path.parent / "wheels"
wheels = sorted(f"./wheels/{w.name}" for w in wheels_dir.glob("*.whl"))
listed = re.findall(r'"(\./wheels/[^"]+)"', text)
text = re.sub(r"(?ms)^platforms = \[.*?\]", "platforms = [" + ", ".join(f'"{p}"' for p in built) + "]", text)
text = re.sub(r"(?ms)^wheels = \[.*?\]\n", "wheels = [\n" + "".join(f'  "{w}",\n' for w in wheels) + "]\n", text)
host = os.environ.get("SHAPEWRIGHT_ADDON_HOST") == "1"
for w in wheels:
    # A host-built linux wheel carries this machine's manylinux tag in
    # place of the shipped one's.
    shipped = re.sub(r"manylinux_2_\d+_", "manylinux_2_28_", w) if host else w
    if shipped not in listed:
        sys.exit(f"build_addon: built {w}, which blender_manifest.toml does not list (update its wheels)")
path.write_text(text)
EOF
python scripts/notices.py --package shapewright-py "${targets[@]}" --title "the Shapewright Blender extension" \
  --out "$stage/THIRD_PARTY_NOTICES.txt" >&2
cp LICENSE-MIT LICENSE-APACHE "$stage/"

ext_tool="$(python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/bpy/5.0/scripts/addons_core/bl_pkg/cli/blender_ext.py"
python "$ext_tool" build --split-platforms --source-dir "$stage" --output-dir out/extension >&2
for z in out/extension/*.zip; do
  python "$ext_tool" validate "$z" >&2
done
# A self-hosted extension repository over these zips (index.json, and an
# index.html to browse): serve the folder, add its index.json's URL in
# Blender (Get Extensions > Repositories > + > Add Remote Repository).
python "$ext_tool" server-generate --repo-dir out/extension --html >&2
if [[ " ${platforms[*]} " == *" linux-x64 "* ]]; then
  rm -f out/shapewright-*.zip
  cp out/extension/shapewright-*-linux_x64.zip out/
fi
ls -1 out/extension/*.zip
