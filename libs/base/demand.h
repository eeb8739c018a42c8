#pragma once
// Programmer-error checks for every part of haptex: a violated invariant is a bug, so abort in
// every build, naming file:line and the condition (bad configuration throws instead; faults at
// run time inside a loop are dropped and counted, see docs/architecture.md "Errors").

#include <cstdio>
#include <cstdlib>

#define HAPTEX_DEMAND(condition)                                                                    \
  do {                                                                                              \
    if (!(condition)) {                                                                             \
      std::fprintf(stderr, "%s:%d: haptex invariant failed: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                                 \
    }                                                                                               \
  } while (false)
