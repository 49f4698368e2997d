# CMake toolchain for x86_64-pc-windows-gnu cross builds (Debian's mingw-w64),
# used by the openxr-sys `static` feature's loader build through
# CMAKE_TOOLCHAIN_FILE_x86_64_pc_windows_gnu (.cargo/config.toml).
# The -posix compilers: the -win32 thread model lacks std::shared_timed_mutex,
# which the OpenXR loader uses.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER x86_64-w64-mingw32-gcc-posix)
set(CMAKE_CXX_COMPILER x86_64-w64-mingw32-g++-posix)
set(CMAKE_RC_COMPILER x86_64-w64-mingw32-windres)
set(CMAKE_FIND_ROOT_PATH /usr/x86_64-w64-mingw32)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
