#include "stereo/c2f_kernels.hpp"

#include <algorithm>
#include <climits>

#include "hazmap/map/internal/simd.hpp"

namespace hazmap {
namespace c2f {

int step_scalar(const std::int16_t* lq, int min_lq, int delta, const std::uint8_t* cost,
                const StepParams& p, std::int16_t* lp, std::uint16_t* sum) {
  int lowest = INT_MAX;
  for (int k = 0; k < p.n; ++k) {
    int v = cost[k];
    if (lq) {
      const int kq = k + delta;
      int best = min_lq + p.p2;
      if (kq >= 0 && kq < p.n) best = std::min(best, static_cast<int>(lq[kq]));
      if (kq - 1 >= 0 && kq - 1 < p.n) best = std::min(best, lq[kq - 1] + p.p1);
      if (kq + 1 >= 0 && kq + 1 < p.n) best = std::min(best, lq[kq + 1] + p.p1);
      v += best - min_lq;
    }
    lp[k] = static_cast<std::int16_t>(v);
    sum[k] = static_cast<std::uint16_t>(sum[k] + v);
    lowest = std::min(lowest, v);
  }
  return lowest;
}

#ifdef HAZMAP_HAVE_AVX2

namespace {

/// kLanes matching costs widened to 16 bits.
HAZMAP_AVX2_KERNEL inline __m256i load_cost(const std::uint8_t* cost) {
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(cost)));
}

/// Writes lanes j.. of the path cost v (the last block raised to the padding mask, so
/// padded lanes never win) into lp, adds them to sum; returns the lane-wise running minimum.
HAZMAP_AVX2_KERNEL inline __m256i store_lanes(__m256i v, int j, bool last, const StepParams& p,
                                              std::int16_t* lp, std::uint16_t* sum,
                                              __m256i lowest) {
  if (last)
    v = _mm256_max_epi16(v, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p.pad_mask)));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(lp + j), v);
  __m256i* s = reinterpret_cast<__m256i*>(sum + j);
  _mm256_storeu_si256(s, _mm256_add_epi16(_mm256_loadu_si256(s), v));
  return _mm256_min_epi16(lowest, v);
}

}  // namespace

HAZMAP_AVX2_KERNEL int step_avx2(const std::int16_t* lq, int min_lq, int delta,
                                 const std::uint8_t* cost, const StepParams& p, std::int16_t* lp,
                                 std::uint16_t* sum) {
  __m256i lowest = _mm256_set1_epi16(kInf);
  const int last = p.npad - kLanes;
  if (!lq) {
    for (int j = 0; j < p.npad; j += kLanes) {
      lowest = store_lanes(load_cost(cost + j), j, j == last, p, lp, sum, lowest);
    }
  } else {
    // Beyond +-(n + 1) lanes no term of the window overlaps: clamping keeps loads inside
    // the padding without changing a lane.
    delta = std::clamp(delta, -(p.n + 1), p.n + 1);
    const __m256i p1 = _mm256_set1_epi16(static_cast<short>(p.p1));
    const __m256i jump = _mm256_set1_epi16(static_cast<short>(min_lq + p.p2));
    const __m256i base = _mm256_set1_epi16(static_cast<short>(min_lq));
    for (int j = 0; j < p.npad; j += kLanes) {
      const std::int16_t* q = lq + j + delta;
      const __m256i same = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q));
      const __m256i below = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q - 1));
      const __m256i above = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q + 1));
      __m256i best = _mm256_min_epi16(same, jump);
      best = _mm256_min_epi16(best, _mm256_add_epi16(_mm256_min_epi16(below, above), p1));
      __m256i v = load_cost(cost + j);
      v = _mm256_add_epi16(v, _mm256_sub_epi16(best, base));
      lowest = store_lanes(v, j, j == last, p, lp, sum, lowest);
    }
  }
  __m128i m = _mm_min_epi16(_mm256_castsi256_si128(lowest), _mm256_extracti128_si256(lowest, 1));
  // Values are >= 0: minpos of unsigned lanes is the signed minimum.
  m = _mm_minpos_epu16(m);
  return _mm_extract_epi16(m, 0);
}

bool avx2_available() { return simd::has_avx2(); }

#else

int step_avx2(const std::int16_t* lq, int min_lq, int delta, const std::uint8_t* cost,
              const StepParams& p, std::int16_t* lp, std::uint16_t* sum) {
  return step_scalar(lq, min_lq, delta, cost, p, lp, sum);
}

bool avx2_available() { return false; }

#endif

}  // namespace c2f
}  // namespace hazmap
