#pragma once
// Counts heap allocations made by the current thread inside a scope, in the spirit of Drake's
// LimitMalloc. Linking haptex::test_alloc into a test binary replaces the global operator new
// family and malloc/calloc/realloc with counting versions.
//
//   haptex::testing::AllocationCounter counter;
//   step();                       // warmed-up hot path
//   EXPECT_EQ(counter.count(), 0);

#include <cstdint>

namespace haptex::testing {

/// True when counting works in this build (not under AddressSanitizer, which owns malloc).
bool AllocationCountingSupported();

/// Counts allocations by this thread between construction and count(). Scopes may nest.
class AllocationCounter final {
 public:
  AllocationCounter();
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;

  /// Allocations (new, new[], malloc, calloc, realloc) by this thread since construction.
  std::int64_t count() const;

 private:
  std::int64_t start_;
};

}  // namespace haptex::testing
