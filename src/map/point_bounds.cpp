#include "hazmap/map/internal/point_bounds.hpp"

#include <algorithm>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "hazmap/map/internal/simd.hpp"

namespace hazmap {

namespace {

#ifdef HAZMAP_HAVE_AVX2
/// Eight lanes per bound; vminps / vmaxps with the point first are exactly
/// `x < b ? x : b` and `x > b ? x : b` (a NaN point keeps the bound). Returns the points
/// done (a multiple of eight); `b` = lo_x, hi_x, lo_y, hi_y, updated.
HAZMAP_AVX2_KERNEL int extend_avx2(const float* x, const float* y, int n, float* b) {
  __m256 lx = _mm256_set1_ps(b[0]), hx = _mm256_set1_ps(b[1]);
  __m256 ly = _mm256_set1_ps(b[2]), hy = _mm256_set1_ps(b[3]);
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 vx = _mm256_loadu_ps(x + i), vy = _mm256_loadu_ps(y + i);
    lx = _mm256_min_ps(vx, lx);
    hx = _mm256_max_ps(vx, hx);
    ly = _mm256_min_ps(vy, ly);
    hy = _mm256_max_ps(vy, hy);
  }
  alignas(32) float lanes[4][8];
  _mm256_store_ps(lanes[0], lx);
  _mm256_store_ps(lanes[1], hx);
  _mm256_store_ps(lanes[2], ly);
  _mm256_store_ps(lanes[3], hy);
  for (int lane = 0; lane < 8; ++lane) {
    b[0] = std::min(b[0], lanes[0][lane]);
    b[1] = std::max(b[1], lanes[1][lane]);
    b[2] = std::min(b[2], lanes[2][lane]);
    b[3] = std::max(b[3], lanes[3][lane]);
  }
  return i;
}
#endif

}  // namespace

// The scalar loop (std::min and std::max point after point) is four chains of dependent
// compares, one point per compare latency (~1.5 ns per point, most of what single-layer
// insertion lost by 37383c0). Here in vector lanes: eight per bound with AVX2 (where the
// CPU has it), else two vectors of four, with min / max instructions, which are exactly
// `a < b ? a : b` and `a > b ? a : b` (the tail and the lanes' reduction: std::min, max).
void PointBounds::extend(const float* x, const float* y, int n) {
  int i = 0;
#ifdef HAZMAP_HAVE_AVX2
  if (simd::has_avx2() && n >= 8) {
    float b[4] = {lo_x, hi_x, lo_y, hi_y};
    i = extend_avx2(x, y, n, b);
    lo_x = b[0], hi_x = b[1], lo_y = b[2], hi_y = b[3];
  }
#endif
#if defined(__SSE__)
  if (i == 0 && n >= 8) {
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
