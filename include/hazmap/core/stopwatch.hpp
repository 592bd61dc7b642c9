#pragma once
// Milliseconds on the steady clock: the per-stage timings in summary.json, run.log and
// `hazmap bench`.

#include <chrono>

namespace hazmap {

/// Milliseconds from `start` (a std::chrono::steady_clock::now()) to now.
inline double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace hazmap
