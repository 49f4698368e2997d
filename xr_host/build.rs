//! Links the C++ runtime the static OpenXR loader needs on windows-gnu.
//!
//! openxr-sys's `static` feature builds the Khronos loader (C++) with
//! cmake and links a C++ runtime on Linux, macOS and Android, but not on
//! Windows, where it assumes MSVC's linker finds one by itself. With
//! mingw-w64 (the x86_64-pc-windows-gnu target) nothing does, so this
//! links mingw's libstdc++ statically, after every native library (the
//! loader's archive comes after this crate's own native libraries, so a
//! `rustc-link-lib` here would come too early), followed by what it
//! calls: winpthread (the -posix thread model's std::shared_timed_mutex)
//! and the C runtime (mingwex, msvcrt, kernel32), which std has already
//! named once before. The exe then needs no libstdc++-6.dll or
//! libwinpthread-1.dll (scripts/build_windows.sh checks its imports).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let env = std::env::var("CARGO_CFG_TARGET_ENV").unwrap_or_default();
    if os == "windows" && env == "gnu" {
        for lib in [
            "-l:libstdc++.a",
            "-l:libwinpthread.a",
            "-lmingwex",
            "-lmsvcrt",
            "-lkernel32",
        ] {
            println!("cargo:rustc-link-arg={lib}");
        }
    }
}
