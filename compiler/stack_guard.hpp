// How deep the running thread's stack may still grow. The evaluator's limits are
// counted separately (10 000 calls deep, 1000 levels of syntax in one expression)
// and their product is not: 10 000 calls each of an expression 500 levels deep
// overflowed even the compiler's 1 GB stack (a crash of check, render, watch and
// the language server). A call checks the stack it is on instead.
#pragma once

#include <pthread.h>

#include <algorithm>
#include <cstddef>

namespace snell::compile {

// The address below which this thread's stack has less than `margin` bytes left,
// or null when the thread's stack cannot be found (nothing is checked then).
inline const char* stack_floor(std::size_t margin) {
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) != 0) return nullptr;
  void* low = nullptr;
  std::size_t size = 0;
  const bool ok = pthread_attr_getstack(&attr, &low, &size) == 0 && low && size > 0;
  pthread_attr_destroy(&attr);
  if (!ok) return nullptr;
  // A small stack (a thread of 8 MB or less) keeps half of it in reserve.
  return static_cast<const char*>(low) + std::min(margin, size / 2);
}

// True when the caller's frame lies below `floor` (stacks grow down on every
// target Snell builds for).
[[gnu::always_inline]] inline bool stack_low(const char* floor) {
  return floor && static_cast<const char*>(__builtin_frame_address(0)) < floor;
}

}  // namespace snell::compile
