#include "hazmap/map/internal/chunk_runs.hpp"

#include <array>
#include <cstdint>
#include <cstring>

#include "hazmap/map/internal/simd.hpp"

namespace hazmap {
namespace {

using simd::Vec8;
using Mask8 = simd::Int8;
using Index8 = simd::Int8;  ///< lane numbers for __builtin_shuffle
static_assert(sizeof(Vec8) / sizeof(float) == kRunLanes, "one Vec8 per run, eight runs per batch");

[[gnu::always_inline]] inline void load8(const float* p, Vec8& v) { std::memcpy(&v, p, sizeof v); }
[[gnu::always_inline]] inline void keep8(Vec8& v, const Mask8& live) {
  v = reinterpret_cast<Vec8>(reinterpret_cast<Mask8>(v) & live);
}

/// Pairwise sums of neighbouring lanes of a and b, per 128-bit half (x86 hadd order).
[[gnu::always_inline]] inline void pair_sums(const Vec8& a, const Vec8& b, Vec8& out) {
  out = __builtin_shuffle(a, b, Index8{0, 2, 8, 10, 4, 6, 12, 14}) +
        __builtin_shuffle(a, b, Index8{1, 3, 9, 11, 5, 7, 13, 15});
}

/// out[j] = sum of the lanes of v[j], for eight vectors at once.
[[gnu::always_inline]] inline void reduce8(const Vec8 (&v)[8], Vec8& out) {
  Vec8 h01, h23, h45, h67, h0123, h4567;
  pair_sums(v[0], v[1], h01);
  pair_sums(v[2], v[3], h23);
  pair_sums(v[4], v[5], h45);
  pair_sums(v[6], v[7], h67);
  pair_sums(h01, h23, h0123);  // lanes: v0..v3 low halves, then v0..v3 high halves
  pair_sums(h45, h67, h4567);
  out = __builtin_shuffle(h0123, h4567, Index8{0, 1, 2, 3, 8, 9, 10, 11}) +
        __builtin_shuffle(h0123, h4567, Index8{4, 5, 6, 7, 12, 13, 14, 15});
}

#ifdef HAZMAP_HAVE_AVX2
/// For each 8-bit mask, the positions of its set bits, one per byte, lowest first.
constexpr std::array<std::uint64_t, 256> make_set_bit_table() {
  std::array<std::uint64_t, 256> table{};
  for (unsigned m = 0; m < 256; ++m) {
    std::uint64_t packed = 0;
    int n = 0;
    for (unsigned bit = 0; bit < 8; ++bit)
      if (m & (1u << bit)) packed |= std::uint64_t(bit) << (8 * n++);
    table[m] = packed;
  }
  return table;
}
constexpr std::array<std::uint64_t, 256> kSetBits = make_set_bit_table();

static_assert(sizeof(__m256i) / sizeof(int) == kRunLanes, "find_runs compares one __m256i of slots");

HAZMAP_AVX2_KERNEL int find_runs_avx2(const int* slot, int count, int* starts,
                                                          int* run_slot) {
  starts[0] = 0;
  run_slot[0] = slot[0];
  int runs = 1, i = 1;
  for (; i + kRunLanes <= count; i += kRunLanes) {
    const __m256i cur = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(slot + i));
    const __m256i prev = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(slot + i - 1));
    const unsigned same = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(cur, prev))));
    const unsigned start = ~same & 0xFFu;
    // All eight candidate starts are stored; only the first popcount(start) are kept.
    const __m256i at =
        _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(kSetBits[start])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(starts + runs),
                        _mm256_add_epi32(at, _mm256_set1_epi32(i)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(run_slot + runs),
                        _mm256_permutevar8x32_epi32(cur, at));
    runs += _mm_popcnt_u32(start);
  }
  for (; i < count; ++i) {
    starts[runs] = i;
    run_slot[runs] = slot[i];
    runs += slot[i] != slot[i - 1];
  }
  starts[runs] = count;
  return runs;
}
#endif

}  // namespace

int find_runs_portable(const int* slot, int count, int* starts, int* run_slot) {
  starts[0] = 0;
  if (count <= 0) return 0;
  // Branch-free: every index is written, the count advances only at a run start.
  run_slot[0] = slot[0];
  int runs = 1;
  for (int i = 1; i < count; ++i) {
    starts[runs] = i;
    run_slot[runs] = slot[i];
    runs += slot[i] != slot[i - 1];
  }
  starts[runs] = count;
  return runs;
}

int find_runs(const int* slot, int count, int* starts, int* run_slot) {
#ifdef HAZMAP_HAVE_AVX2
  if (simd::has_avx2() && count > 0) return find_runs_avx2(slot, count, starts, run_slot);
#endif
  return find_runs_portable(slot, count, starts, run_slot);
}

HAZMAP_KERNEL void run_height_sums(const int* starts, int runs, const float* w, const float* z,
                                   float* sum_w, float* sum_wz, float* first_z) {
  const Mask8 lane = {0, 1, 2, 3, 4, 5, 6, 7};
  // Eight runs at a time: each run's lanes are summed in one vector per quantity, then
  // the eight vectors are reduced together by a tree of pairwise adds (one result lane per
  // run), which costs a few shuffles per run instead of a horizontal sum each.
  for (int r0 = 0; r0 < runs; r0 += kRunLanes) {
    Vec8 acc_w[kRunLanes], acc_wz[kRunLanes];
#pragma GCC unroll 8
    for (int j = 0; j < kRunLanes; ++j) {
      const int r = r0 + j;
      const bool valid = r < runs;
      const int b = valid ? starts[r] : 0, n = valid ? starts[r + 1] - b : 0;
      const float zb = z[b];
      first_z[r] = zb;
      // Two vectors in straight-line code (runs on a 1 cm layer are mostly 1 to 16 points
      // long), then a loop only for longer runs: no branch on a run's length below 17.
      const Mask8 len = {n, n, n, n, n, n, n, n};
      Vec8 pw0, pz0, pw1, pz1;
      load8(w + b, pw0);
      load8(z + b, pz0);
      load8(w + b + 8, pw1);
      load8(z + b + 8, pz1);
      pz0 -= zb;
      pz1 -= zb;
      keep8(pw0, lane < len);
      keep8(pz0, lane < len);
      keep8(pw1, lane + 8 < len);
      keep8(pz1, lane + 8 < len);
      Vec8 aw = pw0 + pw1, awz = pw0 * pz0 + pw1 * pz1;
      for (int k = kRunSumVectors * kRunLanes; k < n; k += kRunLanes) {
        const Mask8 live = (lane + k) < len;
        Vec8 pw, pz;
        load8(w + b + k, pw);
        load8(z + b + k, pz);
        pz -= zb;
        keep8(pw, live);
        keep8(pz, live);
        aw += pw;
        awz += pw * pz;
      }
      acc_w[j] = aw;
      acc_wz[j] = awz;
    }
    Vec8 tw, twz;
    reduce8(acc_w, tw);
    reduce8(acc_wz, twz);
    std::memcpy(sum_w + r0, &tw, sizeof tw);
    std::memcpy(sum_wz + r0, &twz, sizeof twz);
  }
}

void ChunkRuns::find(const int* slot, int count) {
  runs_ = find_runs(slot, count, starts_.data(), slots_.data());
}

void ChunkRuns::sum_heights(const float* w, const float* z) {
  run_height_sums(starts_.data(), runs_, w, z, sum_w_.data(), sum_wz_.data(), first_z_.data());
}

}  // namespace hazmap
