#pragma once
// A cheap, unfenced time-stamp read for timing small pieces of work from inside a loop
// (per layer and chunk of the map insertion). A clock call there fences the pipeline and
// costs more than a small layer's chunk; ticks are converted to time afterwards with a
// clock read around the whole loop.

#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <x86intrin.h>
#else
#include <chrono>
#endif

namespace hazmap {

/// Monotonic ticks at a constant rate (the x86 time-stamp counter; elsewhere the steady
/// clock's count). Only differences mean anything.
inline std::uint64_t read_ticks() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __rdtsc();
#else
  return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

}  // namespace hazmap
