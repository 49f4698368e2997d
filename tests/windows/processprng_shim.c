/* A test fixture for wine 8 only, never shipped: Rust's standard library
 * imports bcryptprimitives.dll!ProcessPrng (Windows 10+), which wine 8
 * lacks. scripts/test_windows.sh builds this with mingw as
 * bcryptprimitives.dll beside the executables under test; Windows has the
 * real DLL. */
#include <windows.h>
#include <ntsecapi.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len)
{
    while (len > 0) {
        ULONG n = len > 0x40000000 ? 0x40000000 : (ULONG)len;
        if (!RtlGenRandom(data, n))
            return FALSE;
        data += n;
        len -= n;
    }
    return TRUE;
}
