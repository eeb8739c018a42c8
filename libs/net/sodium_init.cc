#include "libs/net/sodium_init.h"

#include <sodium.h>

#include <cstdio>
#include <cstdlib>

namespace haptex::net {

void EnsureSodiumInitialised() {
  static const bool initialised = [] {
    if (sodium_init() < 0) {
      std::fputs("haptex: libsodium failed to initialise\n", stderr);
      std::abort();
    }
    return true;
  }();
  (void)initialised;
}

}  // namespace haptex::net
