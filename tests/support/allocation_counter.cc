#include "tests/support/allocation_counter.h"

#include <cstdlib>
#include <new>

namespace {
// Thread-local so that other threads (loggers, receivers) do not disturb a measurement.
thread_local std::int64_t t_allocations = 0;
}  // namespace

namespace haptex::testing {

bool AllocationCountingSupported() {
#if defined(HAPTEX_SANITIZED) || defined(__SANITIZE_ADDRESS__)
  return false;
#else
  return true;
#endif
}

AllocationCounter::AllocationCounter() : start_(t_allocations) {}
AllocationCounter::~AllocationCounter() = default;
std::int64_t AllocationCounter::count() const { return t_allocations - start_; }

}  // namespace haptex::testing

#if !defined(HAPTEX_SANITIZED) && !defined(__SANITIZE_ADDRESS__)
namespace {
void CountOne() { ++t_allocations; }
}  // namespace

// glibc's own entry points, so that the interposed malloc family can forward to them.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* ptr, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* ptr);

void* malloc(std::size_t size) {
  CountOne();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  CountOne();
  return __libc_calloc(n, size);
}
void* realloc(void* ptr, std::size_t size) {
  CountOne();
  return __libc_realloc(ptr, size);
}
void free(void* ptr) { __libc_free(ptr); }
}

namespace {
void* CountedNew(std::size_t size) {
  CountOne();
  if (size == 0) size = 1;
  if (void* p = __libc_malloc(size)) return p;
  throw std::bad_alloc();
}
void* CountedAlignedNew(std::size_t size, std::align_val_t alignment) {
  CountOne();
  if (size == 0) size = 1;
  if (void* p = __libc_memalign(static_cast<std::size_t>(alignment), size)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return CountedNew(size); }
void* operator new[](std::size_t size) { return CountedNew(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  CountOne();
  return __libc_malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  CountOne();
  return __libc_malloc(size == 0 ? 1 : size);
}
void* operator new(std::size_t size, std::align_val_t a) { return CountedAlignedNew(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return CountedAlignedNew(size, a); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
#endif
