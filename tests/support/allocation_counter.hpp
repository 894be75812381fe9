#pragma once
// Counts heap allocations made by the calling thread while armed: every
// operator new and (outside AddressSanitizer) every malloc, calloc and
// realloc. Include it in exactly one file of a test executable: it replaces
// the global allocation functions.
//
// Only the thread that armed the counter counts, so simulated devices on
// threads of their own do not blur the proof.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <cstdlib>
#include <new>

namespace alloc_counter {
inline thread_local bool t_armed = false;
inline thread_local long t_allocations = 0;
inline void note() {
  if (t_armed) ++t_allocations;
}
// Arms the counter for this thread and zeroes it.
inline void arm() {
  t_allocations = 0;
  t_armed = true;
}
// Disarms it and returns the allocations counted since arm().
inline long disarm() {
  t_armed = false;
  return t_allocations;
}
}  // namespace alloc_counter

void* operator new(std::size_t n) {
  alloc_counter::note();
  if (void* p = std::malloc(n ? n : 1)) return p;
  std::abort();
}
void* operator new[](std::size_t n) {
  alloc_counter::note();
  if (void* p = std::malloc(n ? n : 1)) return p;
  std::abort();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

#if !defined(__SANITIZE_ADDRESS__)
// glibc's own allocator under the hooks.
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* malloc(std::size_t n) {
  alloc_counter::note();
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t a, std::size_t b) {
  alloc_counter::note();
  return __libc_calloc(a, b);
}
extern "C" void* realloc(void* p, std::size_t n) {
  alloc_counter::note();
  return __libc_realloc(p, n);
}
#endif
