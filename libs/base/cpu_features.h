#pragma once
// What the CPU running us can do, checked once at run time: the vector kernels (libs/textile,
// libs/contact) pick a vectorised variant where they can (the project builds without -march).
// Each variant does the same operations in the same order as the portable one, so results do
// not depend on the CPU.

// The AVX/AVX2 kernels exist only where GCC-style target attributes and x86-64 intrinsics do.
#if defined(__GNUC__) && defined(__x86_64__)
#define HAPTEX_X86_KERNELS 1
#endif

namespace haptex::base {

bool CpuHasAvx();   ///< false where HAPTEX_X86_KERNELS is not defined
bool CpuHasAvx2();  ///< likewise
/// AVX-512 F and VL (the AVX2 instructions on 32 vector registers), enabled by the OS; likewise.
bool CpuHasAvx512Vl();

}  // namespace haptex::base
