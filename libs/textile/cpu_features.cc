#include "libs/textile/cpu_features.h"

namespace haptex::textile::internal {

#ifdef HAPTEX_TEXTILE_X86_KERNELS
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
#else
bool CpuHasAvx() { return false; }
bool CpuHasAvx2() { return false; }
#endif

}  // namespace haptex::textile::internal
