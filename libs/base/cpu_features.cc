#include "libs/base/cpu_features.h"

namespace haptex::base {

#ifdef HAPTEX_X86_KERNELS
bool CpuHasAvx() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx") != 0;
  }();
  return has;
}

bool CpuHasAvx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}

// GCC's check reads the OS's XCR0 too: false where the OS does not save the AVX-512 state.
bool CpuHasAvx512Vl() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512vl") != 0;
  }();
  return has;
}
#else
bool CpuHasAvx() { return false; }
bool CpuHasAvx2() { return false; }
bool CpuHasAvx512Vl() { return false; }
#endif

}  // namespace haptex::base
