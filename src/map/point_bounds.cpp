#include "hazmap/map/internal/point_bounds.hpp"

#include <algorithm>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace hazmap {

// The scalar loop (std::min and std::max point after point) is four chains of dependent
// compares, one point per compare latency (~1.5 ns per point, most of what single-layer
// insertion lost by 37383c0); here two vectors of four lanes per bound, eight points a
// step, with minps / maxps, which are exactly `a < b ? a : b` and `a > b ? a : b`.
void PointBounds::extend(const float* x, const float* y, int n) {
  int i = 0;
#if defined(__SSE__)
  if (n >= 8) {
    __m128 lx[2], hx[2], ly[2], hy[2];
    for (int k = 0; k < 2; ++k) {
      lx[k] = _mm_set1_ps(lo_x);
      hx[k] = _mm_set1_ps(hi_x);
      ly[k] = _mm_set1_ps(lo_y);
      hy[k] = _mm_set1_ps(hi_y);
    }
    for (; i + 8 <= n; i += 8)
      for (int k = 0; k < 2; ++k) {
        // The point first: a NaN in it keeps the bound (minps returns the second operand).
        const __m128 vx = _mm_loadu_ps(x + i + 4 * k), vy = _mm_loadu_ps(y + i + 4 * k);
        lx[k] = _mm_min_ps(vx, lx[k]);
        hx[k] = _mm_max_ps(vx, hx[k]);
        ly[k] = _mm_min_ps(vy, ly[k]);
        hy[k] = _mm_max_ps(vy, hy[k]);
      }
    alignas(16) float lanes[4][8];
    for (int k = 0; k < 2; ++k) {
      _mm_store_ps(lanes[0] + 4 * k, lx[k]);
      _mm_store_ps(lanes[1] + 4 * k, hx[k]);
      _mm_store_ps(lanes[2] + 4 * k, ly[k]);
      _mm_store_ps(lanes[3] + 4 * k, hy[k]);
    }
    for (int lane = 0; lane < 8; ++lane) {
      lo_x = std::min(lo_x, lanes[0][lane]);
      hi_x = std::max(hi_x, lanes[1][lane]);
      lo_y = std::min(lo_y, lanes[2][lane]);
      hi_y = std::max(hi_y, lanes[3][lane]);
    }
  }
#endif
  for (; i < n; ++i) {
    lo_x = std::min(lo_x, x[i]);
    hi_x = std::max(hi_x, x[i]);
    lo_y = std::min(lo_y, y[i]);
    hi_y = std::max(hi_y, y[i]);
  }
}

}  // namespace hazmap
