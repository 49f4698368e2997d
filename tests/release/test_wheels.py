"""The native wheels and the per-platform extension zips, as built by
`scripts/build_addon.sh` (or `scripts/release.sh`, which calls it).

Each wheel: its file name and WHEEL tags are abi3-py311 for the platform
Blender names; its RECORD matches its content; its native module is built
for the platform's machine, exports `PyInit__native` and links only the
Python ABI and the operating system's own libraries (PE import table,
Mach-O load commands, ELF NEEDED; read with LIEF), so it loads in any
Blender of that platform with Python 3.11 or later and no other install.

Each zip: one platform in its generated manifest, carrying exactly that
platform's wheel (byte-identical to the one built), the licences and the
third-party notices; Blender's own `validate` accepts it. The repository
index (`index.json`, Blender's `server-generate`) lists every zip with its
platform, size and SHA-256.

SHAPEWRIGHT_ADDON_OUT=DIR reads DIR/wheels and DIR/extension (default:
out/). SHAPEWRIGHT_EXPECT_PLATFORMS=all (set by release.sh) also requires
every platform in blender_manifest.toml to be there. With
SHAPEWRIGHT_ADDON_HOST=1 (scripts/test.sh: the linux wheel linked by this
machine's toolchain, see build_addon.sh) the linux wheel may carry a newer
manylinux tag than the shipped manylinux_2_28; its glibc symbol versions
are then checked against the tag it carries.
"""

from __future__ import annotations

import base64
import hashlib
import json
import os
import re
import struct
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from pathlib import Path

import lief
import pytest

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(os.environ.get("SHAPEWRIGHT_ADDON_OUT", ROOT / "out"))
MANIFEST = tomllib.loads((ROOT / "blender_addon/shapewright_blender/blender_manifest.toml").read_text())
EXT_TOOL = Path(sysconfig.get_paths()["purelib"]) / "bpy/5.0/scripts/addons_core/bl_pkg/cli/blender_ext.py"

# Blender platform -> (wheel platform tag, native module name, machine).
PLATFORMS = {
    "linux-x64": ("manylinux_2_28_x86_64", "_native.abi3.so", "x86_64"),
    "windows-x64": ("win_amd64", "_native.pyd", "x86_64"),
    "windows-arm64": ("win_arm64", "_native.pyd", "arm64"),
    "macos-arm64": ("macosx_11_0_arm64", "_native.abi3.so", "arm64"),
    "macos-x64": ("macosx_11_0_x86_64", "_native.abi3.so", "x86_64"),
}

# DLLs every Windows 10/11 installation has. Not allowed: mingw's runtime
# (libgcc_s_seh-1.dll, libwinpthread-1.dll, libstdc++-6.dll), MSVC's
# (vcruntime140.dll), or a versioned python3XY.dll (that would not be abi3).
WINDOWS_SYSTEM_DLLS = {
    "kernel32.dll", "ntdll.dll", "advapi32.dll", "bcrypt.dll", "bcryptprimitives.dll", "ws2_32.dll",
    "userenv.dll", "psapi.dll", "shell32.dll", "user32.dll", "msvcrt.dll", "secur32.dll", "crypt32.dll",
    "ncrypt.dll", "ole32.dll", "oleaut32.dll", "iphlpapi.dll", "ucrtbase.dll", "synchronization.dll",
}  # fmt: skip
WINDOWS_API_SET = re.compile(r"^api-ms-win-[a-z0-9-]+\.dll$")
# What macOS has at these paths on every machine (the dyld shared cache).
MACOS_SYSTEM = re.compile(
    r"^(/usr/lib/lib(System\.B|c\+\+\.1|iconv\.2|charset\.1|resolv\.9|objc\.A)\.dylib"
    r"|/System/Library/Frameworks/[A-Za-z]+\.framework/Versions/[A-Z]/[A-Za-z]+)$"
)
# glibc's own libraries and libgcc: on every manylinux_2_28 system.
LINUX_SYSTEM = {"libc.so.6", "libm.so.6", "libgcc_s.so.1", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                "ld-linux-x86-64.so.2"}  # fmt: skip


def _wheels() -> list[Path]:
    return sorted((OUT / "wheels").glob("shapewright-*.whl"))


def _zips() -> list[Path]:
    return sorted((OUT / "extension").glob("shapewright-*.zip"))


HOST_LINUX = os.environ.get("SHAPEWRIGHT_ADDON_HOST") == "1"
MANYLINUX = re.compile(r"^manylinux_2_(\d+)_x86_64$")


def _shipped_tag(tag: str) -> str:
    """The tag the shipped wheel has: a host-built linux wheel's own
    manylinux tag stands for the shipped manylinux_2_28 one."""
    if HOST_LINUX and MANYLINUX.match(tag):
        return PLATFORMS["linux-x64"][0]
    return tag


def _shipped_name(wheel: str) -> str:
    stem, ext = wheel.rsplit(".", 1)
    head, tag = stem.rsplit("-", 1)
    return f"{head}-{_shipped_tag(tag)}.{ext}"


def _platform_of(wheel: Path) -> str:
    tag = _shipped_tag(wheel.stem.split("-")[-1])
    found = [p for p, (t, _, _) in PLATFORMS.items() if t == tag]
    assert found, f"{wheel.name}: platform tag {tag!r} is none Blender ships on ({sorted(PLATFORMS)})"
    return found[0]


def test_artifacts_are_there() -> None:
    wheels, zips = _wheels(), _zips()
    assert wheels, f"no wheels in {OUT / 'wheels'}: run scripts/build_addon.sh first"
    built = {_platform_of(w) for w in wheels}
    assert {z.stem.rsplit("-", 1)[1].replace("_", "-") for z in zips} == built, (zips, built)
    assert built <= set(MANIFEST["platforms"]), f"built {built}, manifest lists {MANIFEST['platforms']}"
    if os.environ.get("SHAPEWRIGHT_EXPECT_PLATFORMS") == "all":
        assert built == set(MANIFEST["platforms"]), f"release misses {set(MANIFEST['platforms']) - built}"
    listed = {Path(w).name for w in MANIFEST["wheels"]}
    shipped = {_shipped_name(w.name) for w in wheels}
    assert shipped <= listed, "blender_manifest.toml does not list every wheel built"


def _native(wheel: Path) -> tuple[str, bytes]:
    platform = _platform_of(wheel)
    module = PLATFORMS[platform][1]
    with zipfile.ZipFile(wheel) as zf:
        names = [n for n in zf.namelist() if n.endswith("/" + module)]
        assert names == [f"shapewright/{module}"], f"{wheel.name}: native module {names}"
        return platform, zf.read(names[0])


@pytest.mark.parametrize("wheel", _wheels(), ids=lambda w: w.name)
def test_wheel_tags_and_record(wheel: Path) -> None:
    name, version, py, abi, plat = wheel.stem.split("-")
    assert (name, py, abi) == ("shapewright", "cp311", "abi3"), wheel.name
    with zipfile.ZipFile(wheel) as zf:
        info = f"shapewright-{version}.dist-info"
        meta = zf.read(f"{info}/WHEEL").decode()
        assert f"Tag: cp311-abi3-{plat}" in meta.splitlines(), meta
        assert "Root-Is-Purelib: false" in meta
        # RECORD: every file with its sha256 and size (pip refuses a wheel that lies).
        record = zf.read(f"{info}/RECORD").decode().splitlines()
        rows = {r.rsplit(",", 2)[0]: r.rsplit(",", 2)[1:] for r in record if r}
        assert set(rows) == set(zf.namelist()), set(rows) ^ set(zf.namelist())
        for path, (digest, size) in rows.items():
            if path.endswith("RECORD"):
                continue
            data = zf.read(path)
            want = "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
            assert (digest, int(size)) == (want, len(data)), path


@pytest.mark.parametrize("wheel", _wheels(), ids=lambda w: w.name)
def test_native_module_links_only_python_and_the_system(wheel: Path) -> None:
    platform, data = _native(wheel)
    # Mach-O through MachO.parse: it keeps the fat header (lief.parse
    # returns the first slice as a plain Binary and hides a second one).
    macos = platform.startswith("macos")
    binary = lief.MachO.parse(list(data)) if macos else lief.parse(list(data))
    assert binary is not None, f"{wheel.name}: LIEF cannot read the native module"
    machine = PLATFORMS[platform][2]
    if platform.startswith("windows"):
        _check_pe(binary, machine)
    elif macos:
        _check_macho(binary, machine, data)
    else:
        glibc = int(MANYLINUX.match(wheel.stem.split("-")[-1]).group(1))
        _check_elf(binary, machine, glibc)


def _check_pe(pe: lief.PE.Binary, machine: str) -> None:
    want = {"x86_64": lief.PE.Header.MACHINE_TYPES.AMD64, "arm64": lief.PE.Header.MACHINE_TYPES.ARM64}
    assert pe.header.machine == want[machine], pe.header.machine
    assert "PyInit__native" in {e.name for e in pe.get_export().entries}
    dlls = {i.name.lower() for i in pe.imports} | {d.name.lower() for d in pe.delay_imports}
    assert "python3.dll" in dlls, f"no python3.dll import (not abi3?): {sorted(dlls)}"
    foreign = {
        d for d in dlls - {"python3.dll"} if d not in WINDOWS_SYSTEM_DLLS and not WINDOWS_API_SET.match(d)
    }
    assert not foreign, f"imports DLLs Windows does not ship: {sorted(foreign)}"
    py = next(i for i in pe.imports if i.name.lower() == "python3.dll")
    assert any(e.name == "PyModule_Create2" or e.name.startswith("PyModule_") for e in py.entries)


def _check_macho(fat: lief.MachO.FatBinary, machine: str, raw: bytes) -> None:
    assert fat.size == 1, "one architecture per wheel"
    macho = fat.at(0)
    want = {"x86_64": lief.MachO.Header.CPU_TYPE.X86_64, "arm64": lief.MachO.Header.CPU_TYPE.ARM64}
    assert macho.header.cpu_type == want[machine], macho.header.cpu_type
    assert "_PyInit__native" in {s.name for s in macho.exported_symbols}
    # The libraries it loads (LC_ID_DYLIB, the module's own name, is no load).
    libs = [lib.name for lib in macho.libraries if lib.command != lief.MachO.LoadCommand.TYPE.ID_DYLIB]
    assert libs, "no load commands for libraries"
    foreign = [lib for lib in libs if not MACOS_SYSTEM.match(lib)]
    assert not foreign, f"links libraries macOS does not have: {foreign}"
    # Python's symbols come from the process that loads the module
    # (-undefined dynamic_lookup): imported, but from no library.
    py = [s for s in macho.imported_symbols if s.name.startswith("_Py")]
    assert py, "imports no Python symbols"
    bound = [s.name for s in py if s.library is not None]
    assert not bound, f"Python symbols bound to a library: {bound[:5]}"
    # Apple silicon runs no unsigned code: the linker's ad-hoc signature
    # must be there and still match the bytes (a strip after signing breaks it).
    if machine == "arm64":
        _check_adhoc_signature(macho, raw)
    # Nothing newer than the deployment target the tag promises (11.0).
    assert macho.build_version is not None or macho.version_min is not None
    minos = macho.build_version.minos if macho.build_version is not None else macho.version_min.version
    assert list(minos)[:2] <= [11, 0], minos


def _check_adhoc_signature(macho: lief.MachO.Binary, raw: bytes) -> None:
    """The code directory's page hashes match the file (what the kernel
    checks when it maps the pages on Apple silicon)."""
    assert macho.has_code_signature, "arm64 module without a code signature"
    cmd = macho.code_signature
    data = raw[cmd.data_offset : cmd.data_offset + cmd.data_size]
    magic, _length, count = struct.unpack_from(">III", data, 0)
    assert magic == 0xFADE0CC0, f"not an embedded signature superblob: {magic:#x}"
    blobs = [struct.unpack_from(">II", data, 12 + 8 * i)[1] for i in range(count)]
    cds = [off for off in blobs if struct.unpack_from(">I", data, off)[0] == 0xFADE0C02]
    fields = {off: struct.unpack_from(">IIIIIBBBB", data, off + 16) for off in cds}
    sha256 = [off for off, f in fields.items() if f[5:7] == (32, 2)]
    assert sha256, f"no SHA-256 code directory among {len(cds)}"
    off = sha256[0]
    hash_offset, _ident, _special, ncode, code_limit, _size, _type, _platform, page_log = fields[off]
    assert code_limit == cmd.data_offset, "the signature does not cover the whole file before it"
    page = 1 << page_log
    assert ncode == -(-code_limit // page)
    for i in range(ncode):
        want = data[off + hash_offset + 32 * i : off + hash_offset + 32 * (i + 1)]
        got = hashlib.sha256(raw[i * page : min(code_limit, (i + 1) * page)]).digest()
        assert got == want, f"page {i} does not match its signed hash (modified after signing?)"


def _check_elf(elf: lief.ELF.Binary, machine: str, glibc: int) -> None:
    assert elf.header.machine_type == lief.ELF.ARCH.X86_64 and machine == "x86_64"
    assert "PyInit__native" in {s.name for s in elf.exported_symbols}
    needed = set(elf.libraries)
    foreign = needed - LINUX_SYSTEM
    assert not foreign, f"NEEDED beyond glibc and libgcc: {sorted(foreign)}"
    # Undefined dynamic symbols (LIEF's imported_symbols skips unversioned ones).
    py = [s.name for s in elf.dynamic_symbols if s.shndx == 0 and s.name.startswith("Py")]
    assert py, "imports no Python symbols (resolved from Blender's process)"
    # manylinux_2_NN: no glibc symbol version newer than 2.NN (2.28 shipped).
    versions = set()
    for req in elf.symbols_version_requirement:
        for aux in req.get_auxiliary_symbols():
            if aux.name.startswith("GLIBC_2."):
                versions.add(tuple(int(x) for x in aux.name[len("GLIBC_") :].split(".")))
    assert versions and max(versions) <= (2, glibc), sorted(versions)


@pytest.mark.parametrize("zip_path", _zips(), ids=lambda z: z.name)
def test_extension_zip(zip_path: Path) -> None:
    platform = zip_path.stem.rsplit("-", 1)[1].replace("_", "-")
    with zipfile.ZipFile(zip_path) as zf:
        names = set(zf.namelist())
        manifest = tomllib.loads(zf.read("blender_manifest.toml").decode())
        generated = manifest["build"]["generated"]
        assert generated["platforms"] == [platform], generated
        tag = PLATFORMS[platform][0]
        wheels = generated["wheels"]
        assert len(wheels) == 1 and _shipped_name(wheels[0]).endswith(f"-{tag}.whl"), generated
        inner = generated["wheels"][0].removeprefix("./")
        assert [n for n in names if n.endswith(".whl")] == [inner], "one wheel, the platform's"
        built = OUT / "wheels" / Path(inner).name
        assert zf.read(inner) == built.read_bytes(), "the zip's wheel is not the one built"
        for required in (
            "LICENSE",
            "LICENSE-MIT",
            "LICENSE-APACHE",
            "THIRD_PARTY_NOTICES.txt",
            "__init__.py",
        ):
            assert required in names, f"{zip_path.name} lacks {required}"
        notices = zf.read("THIRD_PARTY_NOTICES.txt").decode()
        for crate in ("pyo3 ", "manifold-rust ", "libmimalloc-sys ", "ring "):
            assert f"\n{crate}" in notices, f"notices name no {crate.strip()}"
        assert manifest["license"] == ["SPDX:GPL-3.0-or-later"]
    r = subprocess.run(
        [sys.executable, str(EXT_TOOL), "validate", str(zip_path)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stdout + r.stderr


def test_repository_index() -> None:
    """Blender's `server-generate` index over the zips: one entry per zip,
    with the platform it serves, its size and SHA-256 (Blender checks the
    hash after downloading and refuses a mismatch)."""
    index = json.loads((OUT / "extension" / "index.json").read_text())
    entries = {e["archive_url"].removeprefix("./"): e for e in index["data"]}
    zips = _zips()
    assert set(entries) == {z.name for z in zips}, (sorted(entries), [z.name for z in zips])
    for z in zips:
        e = entries[z.name]
        assert e["id"] == MANIFEST["id"] and e["version"] == MANIFEST["version"]
        assert e["platforms"] == [z.stem.rsplit("-", 1)[1].replace("_", "-")], e["platforms"]
        assert e["archive_size"] == z.stat().st_size
        assert e["archive_hash"] == "sha256:" + hashlib.sha256(z.read_bytes()).hexdigest()
        assert e["blender_version_min"] == MANIFEST["blender_version_min"]
        assert e["license"] == MANIFEST["license"]
