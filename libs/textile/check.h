#pragma once
// Programmer-error checks for the textile core: a violated invariant is a bug, so abort in every
// build (bad configuration throws instead; numerical trouble at run time is a status + counter).

#include <cstdio>
#include <cstdlib>

#define HAPTEX_TEXTILE_DEMAND(condition)                                                 \
  do {                                                                                   \
    if (!(condition)) {                                                                  \
      std::fprintf(stderr, "%s:%d: haptex textile invariant failed: %s\n", __FILE__,     \
                   __LINE__, #condition);                                                \
      std::abort();                                                                      \
    }                                                                                    \
  } while (false)
