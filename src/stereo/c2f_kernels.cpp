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


void census_row_scalar(const std::uint8_t* const* rows, int cw, int ch, int width,
                       std::uint64_t* code) {
  const int rw = cw / 2, rh = ch / 2;
  for (int x = 0; x < width; ++x) {
    const std::uint8_t centre = rows[rh][x + rw];
    std::uint64_t c = 0;
    int j = 0;
    for (int i = 0; i < ch; ++i)
      for (int k = 0; k < cw; ++k) {
        if (i == rh && k == rw) continue;
        c |= static_cast<std::uint64_t>(rows[i][x + k] < centre) << j;
        ++j;
      }
    code[x] = c;
  }
}

namespace {

/// Costs of x's window: lane k = differing bits of left and right[x - d0 - k], `bits` where
/// that lies left of the image; a byte per lane, lanes >= n zero.
inline std::uint64_t window_costs(const NarrowRow& r, int x, int d0) {
  const std::uint64_t left = r.census_l[x];
  std::uint64_t c = 0;
  for (int k = 0; k < r.n; ++k) {
    const int xr = x - d0 - k;
    const std::uint64_t v =
        xr >= 0 ? static_cast<std::uint64_t>(__builtin_popcountll(left ^ r.census_r[xr]))
                : static_cast<std::uint64_t>(r.bits);
    c |= v << (8 * k);
  }
  return c;
}

}  // namespace

void rows_narrow_scalar(const NarrowRow& r) {
  StepParams sp;
  sp.n = r.n;
  sp.npad = kNarrow;
  sp.p1 = r.p1;
  sp.p2 = r.p2;
  std::int16_t buf[2][kNarrow];
  std::uint16_t zero[kNarrow];
  for (int dir = 0; dir < 2; ++dir) {
    const int x0 = dir == 0 ? 0 : r.width - 1, dx = dir == 0 ? 1 : -1;
    std::int16_t* prev = buf[0];
    std::int16_t* cur = buf[1];
    bool has_prev = false;
    int prev_min = 0, prev_dmin = 0;
    for (int i = 0, x = x0; i < r.width; ++i, x += dx) {
      const int d0 = r.dmin[x];
      if (d0 == kNoSeed) {
        has_prev = false;
        continue;
      }
      std::uint8_t* cost = r.cost + static_cast<std::size_t>(x) * kNarrow;
      std::uint16_t* sum = r.sum + static_cast<std::size_t>(x) * kNarrow;
      if (dir == 0) {
        const std::uint64_t c = window_costs(r, x, d0);
        for (int k = 0; k < kNarrow; ++k) cost[k] = static_cast<std::uint8_t>(c >> (8 * k));
        std::fill(zero, zero + kNarrow, 0);
      }
      if (has_prev && r.p2_of_diff) sp.p2 = edge_p2(r.p2_of_diff, r.image[x], r.image[x - dx]);
      prev_min = step_scalar(has_prev ? prev : nullptr, prev_min, d0 - prev_dmin, cost, sp, cur,
                             dir == 0 ? zero : sum);
      if (dir == 0) std::copy(zero, zero + kNarrow, sum);
      prev_dmin = d0;
      has_prev = true;
      std::swap(prev, cur);
    }
  }
}

void column_row_narrow_scalar(const NarrowColumnRow& r) {
  StepParams sp;
  sp.n = r.n;
  sp.npad = kNarrow;
  sp.p1 = r.p1;
  sp.p2 = r.p2;
  for (int x = r.x0; x < r.x1; ++x) {
    const int d0 = r.dmin[x];
    if (d0 == kNoSeed) continue;
    const int xq = x - r.dx;
    const bool has_prev =
        r.prev_dmin != nullptr && xq >= 0 && xq < r.width && r.prev_dmin[xq] != kNoSeed;
    const std::size_t p = static_cast<std::size_t>(x) * kNarrow;
    const std::size_t q = state_at(has_prev ? xq : 0);
    if (has_prev && r.p2_of_diff) sp.p2 = edge_p2(r.p2_of_diff, r.image[x], r.prev_image[xq]);
    r.cur_min[x] = step_scalar(has_prev ? r.prev + q : nullptr, has_prev ? r.prev_min[xq] : 0,
                               d0 - (has_prev ? r.prev_dmin[xq] : 0), r.cost + p, sp,
                               r.cur + state_at(x), r.sum + p);
  }
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


HAZMAP_AVX2_KERNEL void census_row_avx2(const std::uint8_t* const* rows, int cw, int ch,
                                        int width, std::uint64_t* code) {
  const int rw = cw / 2, rh = ch / 2;
  // The window's pixels in bit order: row and column offset.
  const std::uint8_t* src[64];
  int bits = 0;
  for (int i = 0; i < ch; ++i)
    for (int k = 0; k < cw; ++k)
      if (i != rh || k != rw) src[bits++] = rows[i] + k;
  const __m256i sign = _mm256_set1_epi8(static_cast<char>(0x80));
  int x = 0;
  for (; x + 32 <= width; x += 32) {
    const __m256i centre = _mm256_xor_si256(
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rows[rh] + x + rw)), sign);
    // Byte plane b of 32 pixels: bits 8 b .. 8 b + 7 of their codes.
    __m256i plane[8];
    for (int b = 0; b < 8; ++b) {
      __m256i acc = _mm256_setzero_si256();
      for (int i = 0; i < 8 && 8 * b + i < bits; ++i) {
        const __m256i other = _mm256_xor_si256(
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src[8 * b + i] + x)), sign);
        // other < centre (unsigned, both sign-flipped): that bit.
        acc = _mm256_or_si256(
            acc, _mm256_and_si256(_mm256_cmpgt_epi8(centre, other),
                                  _mm256_set1_epi8(static_cast<char>(1 << i))));
      }
      plane[b] = acc;
    }
    // Transpose: pixel x's 8 plane bytes become its little-endian uint64.
    const __m256i a0 = _mm256_unpacklo_epi8(plane[0], plane[1]);
    const __m256i a1 = _mm256_unpackhi_epi8(plane[0], plane[1]);
    const __m256i b0 = _mm256_unpacklo_epi8(plane[2], plane[3]);
    const __m256i b1 = _mm256_unpackhi_epi8(plane[2], plane[3]);
    const __m256i c0 = _mm256_unpacklo_epi8(plane[4], plane[5]);
    const __m256i c1 = _mm256_unpackhi_epi8(plane[4], plane[5]);
    const __m256i d0 = _mm256_unpacklo_epi8(plane[6], plane[7]);
    const __m256i d1 = _mm256_unpackhi_epi8(plane[6], plane[7]);
    // 32-bit groups (planes 0-3, 4-7) of pixels 0-3, 4-7, 8-11, 12-15 (+16 in the high lane).
    const __m256i ab00 = _mm256_unpacklo_epi16(a0, b0), ab01 = _mm256_unpackhi_epi16(a0, b0);
    const __m256i ab10 = _mm256_unpacklo_epi16(a1, b1), ab11 = _mm256_unpackhi_epi16(a1, b1);
    const __m256i cd00 = _mm256_unpacklo_epi16(c0, d0), cd01 = _mm256_unpackhi_epi16(c0, d0);
    const __m256i cd10 = _mm256_unpacklo_epi16(c1, d1), cd11 = _mm256_unpackhi_epi16(c1, d1);
    // Codes of pixels {0,1 | 16,17}, {2,3 | 18,19}, ... {14,15 | 30,31}.
    const __m256i r0 = _mm256_unpacklo_epi32(ab00, cd00), r1 = _mm256_unpackhi_epi32(ab00, cd00);
    const __m256i r2 = _mm256_unpacklo_epi32(ab01, cd01), r3 = _mm256_unpackhi_epi32(ab01, cd01);
    const __m256i r4 = _mm256_unpacklo_epi32(ab10, cd10), r5 = _mm256_unpackhi_epi32(ab10, cd10);
    const __m256i r6 = _mm256_unpacklo_epi32(ab11, cd11), r7 = _mm256_unpackhi_epi32(ab11, cd11);
    __m256i* out = reinterpret_cast<__m256i*>(code + x);
    _mm256_storeu_si256(out + 0, _mm256_permute2x128_si256(r0, r1, 0x20));
    _mm256_storeu_si256(out + 1, _mm256_permute2x128_si256(r2, r3, 0x20));
    _mm256_storeu_si256(out + 2, _mm256_permute2x128_si256(r4, r5, 0x20));
    _mm256_storeu_si256(out + 3, _mm256_permute2x128_si256(r6, r7, 0x20));
    _mm256_storeu_si256(out + 4, _mm256_permute2x128_si256(r0, r1, 0x31));
    _mm256_storeu_si256(out + 5, _mm256_permute2x128_si256(r2, r3, 0x31));
    _mm256_storeu_si256(out + 6, _mm256_permute2x128_si256(r4, r5, 0x31));
    _mm256_storeu_si256(out + 7, _mm256_permute2x128_si256(r6, r7, 0x31));
  }
  if (x < width) {
    const std::uint8_t* tail[16];
    for (int i = 0; i < ch; ++i) tail[i] = rows[i] + x;
    census_row_scalar(tail, cw, ch, width - x, code + x);
  }
}

namespace {

/// Lane shifts of an 8-lane window: out[k] = in[k + s] where 0 <= k + s < 8, else kInf;
/// s in [-9, 9]. A byte shuffle (0x80: zero) and the kInf fill for the lanes it empties.
struct ShiftTables {
  alignas(16) std::int8_t index[19][16];
  alignas(16) std::int16_t fill[19][kNarrow];
};
constexpr ShiftTables make_shift_tables() {
  ShiftTables t{};
  for (int s = -9; s <= 9; ++s)
    for (int k = 0; k < kNarrow; ++k) {
      const int from = k + s;
      const bool inside = from >= 0 && from < kNarrow;
      t.index[s + 9][2 * k] = static_cast<std::int8_t>(inside ? 2 * from : -128);
      t.index[s + 9][2 * k + 1] = static_cast<std::int8_t>(inside ? 2 * from + 1 : -128);
      t.fill[s + 9][k] = inside ? 0 : kInf;
    }
  return t;
}
constexpr ShiftTables kShift = make_shift_tables();

HAZMAP_AVX2_KERNEL inline __m128i shifted(__m128i v, int s) {
  return _mm_max_epi16(
      _mm_shuffle_epi8(v, _mm_load_si128(reinterpret_cast<const __m128i*>(kShift.index[s + 9]))),
      _mm_load_si128(reinterpret_cast<const __m128i*>(kShift.fill[s + 9])));
}

/// step_scalar on one 8-lane register: lanes >= n of lq are kInf, and so are those of
/// the result; base = min_lq in every lane.
HAZMAP_AVX2_KERNEL inline __m128i narrow_step(__m128i lq, __m128i base, int delta, bool has_prev,
                                              __m128i cost, __m128i p1, __m128i p2,
                                              __m128i mask) {
  __m128i v = cost;
  if (has_prev) {
    // |delta| >= 8: no lane of q's window is within 1 of p's (n <= 7): all kInf.
    delta = std::clamp(delta, -8, 8);
    const __m128i same = shifted(lq, delta);
    const __m128i below = shifted(lq, delta - 1);
    const __m128i above = shifted(lq, delta + 1);
    __m128i best = _mm_min_epi16(same, _mm_add_epi16(base, p2));
    best = _mm_min_epi16(best, _mm_add_epi16(_mm_min_epi16(below, above), p1));
    v = _mm_add_epi16(v, _mm_sub_epi16(best, base));
  }
  return _mm_max_epi16(v, mask);
}

/// The lanes >= n mask: 0 below n, kInf from n.
HAZMAP_AVX2_KERNEL inline __m128i narrow_mask(int n) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(kShift.fill[std::min(9, kNarrow - n) + 9]));
}

HAZMAP_AVX2_KERNEL inline __m128i window_costs_avx2(const NarrowRow& r, int x, int d0) {
  const std::uint64_t left = r.census_l[x];
  std::uint64_t c = 0;
  const int xr0 = x - d0;
  if (xr0 - (r.n - 1) >= 0) {
    const std::uint64_t* right = r.census_r + xr0;
    for (int k = 0; k < r.n; ++k)
      c |= static_cast<std::uint64_t>(__builtin_popcountll(left ^ right[-k])) << (8 * k);
  } else {
    c = window_costs(r, x, d0);
  }
  return _mm_cvtsi64_si128(static_cast<long long>(c));
}

}  // namespace

HAZMAP_AVX2_KERNEL void rows_narrow_avx2(const NarrowRow& row) {
  // A local copy: the byte stores of the costs could alias the caller's struct, and every
  // pixel would reload its fields.
  const NarrowRow r = row;
  const __m128i p1 = _mm_set1_epi16(static_cast<short>(r.p1));
  const __m128i p2 = _mm_set1_epi16(static_cast<short>(r.p2));
  const __m128i mask = narrow_mask(r.n);
  for (int dir = 0; dir < 2; ++dir) {
    const int x0 = dir == 0 ? 0 : r.width - 1, dx = dir == 0 ? 1 : -1;
    __m128i lq = _mm_setzero_si128(), base = _mm_setzero_si128();
    bool has_prev = false;
    int prev_dmin = 0;
    for (int i = 0, x = x0; i < r.width; ++i, x += dx) {
      const int d0 = r.dmin[x];
      if (d0 == kNoSeed) {
        has_prev = false;
        continue;
      }
      std::uint8_t* cost = r.cost + static_cast<std::size_t>(x) * kNarrow;
      __m128i* sum = reinterpret_cast<__m128i*>(r.sum + static_cast<std::size_t>(x) * kNarrow);
      __m128i c;
      if (dir == 0) {
        c = window_costs_avx2(r, x, d0);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(cost), c);
      } else {
        c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(cost));
      }
      const __m128i step_p2 = r.p2_of_diff && has_prev
                                  ? _mm_set1_epi16(static_cast<short>(
                                        edge_p2(r.p2_of_diff, r.image[x], r.image[x - dx])))
                                  : p2;
      const __m128i v =
          narrow_step(lq, base, d0 - prev_dmin, has_prev, _mm_cvtepu8_epi16(c), p1, step_p2, mask);
      _mm_storeu_si128(sum, dir == 0 ? v : _mm_add_epi16(_mm_loadu_si128(sum), v));
      base = _mm_broadcastw_epi16(_mm_minpos_epu16(v));
      lq = v;
      prev_dmin = d0;
      has_prev = true;
    }
  }
}

HAZMAP_AVX2_KERNEL void column_row_narrow_avx2(const NarrowColumnRow& r) {
  const __m128i p1 = _mm_set1_epi16(static_cast<short>(r.p1));
  const __m128i p2 = _mm_set1_epi16(static_cast<short>(r.p2));
  const __m128i mask = narrow_mask(r.n);
  // r's fields in locals: the stores below (int, int16) could alias them otherwise, and
  // every pixel would reload them.
  const int width = r.width, dx = r.dx, x1 = r.x1;
  const std::int16_t* const dmin = r.dmin;
  const std::int16_t* const prev_dmin = r.prev_dmin;
  const std::int16_t* const prev = r.prev;
  const int* const prev_min = r.prev_min;
  std::int16_t* const cur = r.cur;
  int* const cur_min = r.cur_min;
  const std::uint8_t* const cost = r.cost;
  std::uint16_t* const sum_row = r.sum;
  const std::int16_t* const p2_of_diff = r.p2_of_diff;
  const std::uint8_t* const image = r.image;
  const std::uint8_t* const prev_image = r.prev_image;
  for (int x = r.x0; x < x1; ++x) {
    const int d0 = dmin[x];
    if (d0 == kNoSeed) continue;
    const int xq = x - dx;
    const bool has_prev =
        prev_dmin != nullptr && xq >= 0 && xq < width && prev_dmin[xq] != kNoSeed;
    const std::size_t p = static_cast<std::size_t>(x) * kNarrow;
    __m128i v = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(cost + p)));
    if (has_prev) {
      // narrow_step with the shifted windows read from the padded state row: lane k of a
      // load at offset s is q's lane k + s, or kInf padding outside [0, kNarrow).
      const std::int16_t* q = prev + state_at(xq) + std::clamp(d0 - prev_dmin[xq], -8, 8);
      const __m128i base = _mm_set1_epi16(static_cast<short>(prev_min[xq]));
      const __m128i same = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
      const __m128i below = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q - 1));
      const __m128i above = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q + 1));
      const __m128i step_p2 =
          p2_of_diff
              ? _mm_set1_epi16(static_cast<short>(edge_p2(p2_of_diff, image[x], prev_image[xq])))
              : p2;
      __m128i best = _mm_min_epi16(same, _mm_add_epi16(base, step_p2));
      best = _mm_min_epi16(best, _mm_add_epi16(_mm_min_epi16(below, above), p1));
      v = _mm_add_epi16(v, _mm_sub_epi16(best, base));
    }
    v = _mm_max_epi16(v, mask);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cur + state_at(x)), v);
    cur_min[x] = _mm_extract_epi16(_mm_minpos_epu16(v), 0);
    __m128i* sum = reinterpret_cast<__m128i*>(sum_row + p);
    _mm_storeu_si128(sum, _mm_add_epi16(_mm_loadu_si128(sum), v));
  }
}

namespace {

/// The right pixels whose left-right state (lowest sum, its disparity) winners_narrow_avx2
/// holds in registers: right_s / right_d[base .. base + 7]; base < 0: none.
struct RightWindow {
  int base = -1;
  __m128i sums{}, disparities{};
};

/// Writes the window back (its lanes are newer than memory).
HAZMAP_AVX2_KERNEL inline void flush(RightWindow& w, std::uint16_t* right_s,
                                     std::int16_t* right_d) {
  if (w.base < 0) return;
  _mm_storeu_si128(reinterpret_cast<__m128i*>(right_s + w.base), w.sums);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(right_d + w.base), w.disparities);
  w.base = -1;
}

/// Moves the window to start at `base`. One pixel on (the usual step: the next left pixel
/// at the same dmin), the leaving lane is stored and the entering one loaded alone;
/// otherwise the whole window. Loading 16 bytes that overlap the 16 stored one pixel
/// before stalls store-to-load forwarding: that one load was ~40 % of this kernel.
HAZMAP_AVX2_KERNEL inline void move_to(RightWindow& w, int base, std::uint16_t* right_s,
                                       std::int16_t* right_d) {
  if (base == w.base) return;
  if (w.base >= 0 && base == w.base + 1) {
    right_s[w.base] = static_cast<std::uint16_t>(_mm_extract_epi16(w.sums, 0));
    right_d[w.base] = static_cast<std::int16_t>(_mm_extract_epi16(w.disparities, 0));
    // alignr: lanes 1..7 down one, the entering pixel's state into lane 7.
    w.sums = _mm_alignr_epi8(_mm_cvtsi32_si128(right_s[base + kNarrow - 1]), w.sums, 2);
    w.disparities =
        _mm_alignr_epi8(_mm_cvtsi32_si128(static_cast<std::uint16_t>(right_d[base + kNarrow - 1])),
                        w.disparities, 2);
    w.base = base;
    return;
  }
  flush(w, right_s, right_d);
  w.sums = _mm_loadu_si128(reinterpret_cast<const __m128i*>(right_s + base));
  w.disparities = _mm_loadu_si128(reinterpret_cast<const __m128i*>(right_d + base));
  w.base = base;
}

}  // namespace

HAZMAP_AVX2_KERNEL void winners_narrow_avx2(const WinnerRow& row) {
  const WinnerRow r = row;  // a local copy, as in rows_narrow_avx2
  const int n = r.n;
  const __m128i lane = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  const __m128i above_n = _mm_cmpgt_epi16(lane, _mm_set1_epi16(static_cast<short>(n - 1)));
  // offer_to_right on one register: right pixels x - d0 - 7 .. x - d0 in lanes 0..7, so
  // lane j takes sum lane 7 - j (reversed) where 7 - j < n; unsigned compares by the sign
  // flip. Each left pixel offers to distinct right pixels: the same as the scalar loop.
  const __m128i reverse = _mm_setr_epi8(14, 15, 12, 13, 10, 11, 8, 9, 6, 7, 4, 5, 2, 3, 0, 1);
  const __m128i in_window = _mm_cmpgt_epi16(lane, _mm_set1_epi16(static_cast<short>(7 - n)));
  const __m128i flip = _mm_set1_epi16(static_cast<short>(0x8000));
  RightWindow window;
  for (int x = 0; x < r.width; ++x) {
    r.disp[x] = -1.f;
    const int d0 = r.dmin[x];
    if (d0 == kNoSeed) continue;
    const std::uint16_t* s = r.sum + static_cast<std::size_t>(x) * kNarrow;
    const __m128i sums = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s));
    // Lanes >= n to kNoSum; minpos: the lowest sum and its first lane.
    const __m128i m = _mm_minpos_epu16(_mm_or_si128(sums, above_n));
    const int best = _mm_extract_epi16(m, 0);
    const int kb = _mm_extract_epi16(m, 1);
    const int xr0 = x - d0;
    if (xr0 < 0) continue;
    if (xr0 >= kNarrow - 1) {
      move_to(window, xr0 - (kNarrow - 1), r.right_s, r.right_d);
      const __m128i offered = _mm_shuffle_epi8(sums, reverse);
      const __m128i take = _mm_and_si128(
          in_window,
          _mm_cmpgt_epi16(_mm_xor_si128(window.sums, flip), _mm_xor_si128(offered, flip)));
      window.sums = _mm_blendv_epi8(window.sums, offered, take);
      const __m128i disparity =
          _mm_sub_epi16(_mm_set1_epi16(static_cast<short>(d0 + kNarrow - 1)), lane);
      window.disparities = _mm_blendv_epi8(window.disparities, disparity, take);
    } else {
      flush(window, r.right_s, r.right_d);
      offer_to_right(r, s, x, d0, n);
    }
    if (x - d0 - kb < 0) continue;
    if ((kb == 0 && d0 > r.lo) || (kb == n - 1 && d0 + n < r.hi)) continue;
    float d = static_cast<float>(d0 + kb);
    if (kb > 0 && kb < n - 1) {
      const int a = s[kb - 1], c = s[kb + 1];
      const int denom = a + c - 2 * best;
      if (denom > 0) d += static_cast<float>(a - c) / static_cast<float>(2 * denom);
    }
    r.disp[x] = d;
    r.winner[x] = static_cast<std::int16_t>(d0 + kb);
  }
  flush(window, r.right_s, r.right_d);
}

bool avx2_available() { return simd::has_avx2(); }

#else

int step_avx2(const std::int16_t* lq, int min_lq, int delta, const std::uint8_t* cost,
              const StepParams& p, std::int16_t* lp, std::uint16_t* sum) {
  return step_scalar(lq, min_lq, delta, cost, p, lp, sum);
}

void census_row_avx2(const std::uint8_t* const* rows, int cw, int ch, int width,
                     std::uint64_t* code) {
  census_row_scalar(rows, cw, ch, width, code);
}
void rows_narrow_avx2(const NarrowRow& r) { rows_narrow_scalar(r); }
void column_row_narrow_avx2(const NarrowColumnRow& r) { column_row_narrow_scalar(r); }
void winners_narrow_avx2(const WinnerRow&) {}  // never called: avx2_available() is false

bool avx2_available() { return false; }

#endif

}  // namespace c2f
}  // namespace hazmap
