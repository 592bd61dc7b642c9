#include "hazmap/rules/kalman.hpp"

#include "hazmap/map/internal/lazy_ageing.hpp"

#include "hazmap/map/internal/simd.hpp"

namespace hazmap {

namespace {
/// Runs [first, last) merged one after another with KalmanRule::merge_run.
std::size_t merge_one_by_one(const KalmanRule::Config& cfg, KalmanRule::Cell* cells,
                             std::uint32_t frame, const ChunkRuns& runs, int first, int last) {
  const double max_precision = KalmanRule::max_precision(cfg);
  std::size_t used = 0;
  for (int k = first; k < last; ++k) {
    const int s = runs.slot(k);
    if (s < 0) continue;
    used += static_cast<std::size_t>(runs.end(k) - runs.begin(k));
    KalmanRule::merge_run(cfg, cells[s], KalmanRule::run_sums(runs, k), runs.first_z(k),
                          owed_frames(frame, cells[s].stamp), max_precision);
    cells[s].stamp = frame;
  }
  return used;
}
}  // namespace

std::size_t KalmanRule::merge_chunk_runs_scalar(const Config& cfg, Cell* cells, std::uint32_t frame,
                                                const ChunkRuns& runs) {
  return merge_one_by_one(cfg, cells, frame, runs, 0, runs.size());
}

#ifdef HAZMAP_HAVE_AVX2
namespace {

static_assert(sizeof(KalmanRule::Cell) == 16, "cell = ref, off, precision, stamp");

/// KalmanRule::merge_run on four lanes of doubles (same steps, same order).
[[gnu::always_inline]] inline HAZMAP_AVX2_KERNEL void merge4(
    __m256d ref, __m256d off, __m256d p, __m256d z_ref, __m256d w, __m256d wz, __m256d owed,
    __m256d q, __m256d cap, __m128& new_ref, __m128& new_off, __m128& new_p) {
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d offset = _mm256_sub_pd(_mm256_add_pd(ref, off), z_ref);
  const __m256d d = _mm256_add_pd(one, _mm256_mul_pd(_mm256_mul_pd(owed, q), p));
  const __m256d a = _mm256_add_pd(p, _mm256_mul_pd(d, w));
  const __m256d r = _mm256_div_pd(one, _mm256_mul_pd(d, a));
  const __m256d mean = _mm256_add_pd(
      z_ref,
      _mm256_mul_pd(_mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(p, offset), _mm256_mul_pd(d, wz)), d),
                    r));
  // SplitHeight::set: the float nearest the mean, then the float nearest the rest.
  new_ref = _mm256_cvtpd_ps(mean);
  new_off = _mm256_cvtpd_ps(_mm256_sub_pd(mean, _mm256_cvtps_pd(new_ref)));
  new_p = _mm256_cvtpd_ps(_mm256_min_pd(_mm256_mul_pd(_mm256_mul_pd(a, a), r), cap));
}

[[gnu::always_inline]] inline HAZMAP_AVX2_KERNEL __m256d lo(__m256 v) {
  return _mm256_cvtps_pd(_mm256_castps256_ps128(v));
}
[[gnu::always_inline]] inline HAZMAP_AVX2_KERNEL __m256d hi(__m256 v) {
  return _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1));
}

/// merge4 on eight float lanes: both halves in double.
[[gnu::always_inline]] inline HAZMAP_AVX2_KERNEL void merge_lanes(
    __m256 ref, __m256 off, __m256 p, __m256 z_ref, __m256 w, __m256 wz, __m256 owed, __m256d q,
    __m256d cap, __m256& new_ref, __m256& new_off, __m256& new_p) {
  __m128 r0, o0, p0, r1, o1, p1;
  merge4(lo(ref), lo(off), lo(p), lo(z_ref), lo(w), lo(wz), lo(owed), q, cap, r0, o0, p0);
  merge4(hi(ref), hi(off), hi(p), hi(z_ref), hi(w), hi(wz), hi(owed), q, cap, r1, o1, p1);
  new_ref = _mm256_set_m128(r1, r0);
  new_off = _mm256_set_m128(o1, o0);
  new_p = _mm256_set_m128(p1, p0);
}

HAZMAP_AVX2_KERNEL std::size_t merge_avx2(const KalmanRule::Config& cfg,
                                                           KalmanRule::Cell* cells,
                                                           std::uint32_t frame,
                                                           const ChunkRuns& runs) {
  // Prefetch the cells of the batch four ahead. Inside the flight stack the cells come from
  // L3 (the CCM layers evict them between chunks); the next batch (8) was too close and
  // cost ~0.2 ns per point more, measured in BM_FlightStackByLayer.
  constexpr int kAhead = 32;
  const int count = runs.size();
  const int* const slots = runs.slots();
  const int* const starts = runs.starts();
  const float* const sum_w = runs.sums_w();
  const float* const sum_wz = runs.sums_wz();
  const float* const first_z = runs.first_zs();
  float* const fields = reinterpret_cast<float*>(cells);  // cell s: 4 lanes at 4 s
  const __m256d q = _mm256_set1_pd(cfg.time_inflation_m2);
  const __m256d cap = _mm256_set1_pd(KalmanRule::max_precision(cfg));
  const __m256 zero = _mm256_setzero_ps();
  const __m256i now = _mm256_set1_epi32(static_cast<int>(frame));
  // Lane rotations by 1 to 4: comparing a vector with them compares every pair of lanes.
  const __m256i rot1 = _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 0);
  const __m256i rot2 = _mm256_setr_epi32(2, 3, 4, 5, 6, 7, 0, 1);
  const __m256i rot3 = _mm256_setr_epi32(3, 4, 5, 6, 7, 0, 1, 2);
  const __m256i rot4 = _mm256_setr_epi32(4, 5, 6, 7, 0, 1, 2, 3);
  __m256i used = _mm256_setzero_si256();
  std::size_t used_scalar = 0;
  int k = 0;
  for (; k + 8 <= count; k += 8) {
    if (k + kAhead + 8 <= count)
      for (int j = kAhead; j < kAhead + 8; ++j) {
        const int ahead = slots[k + j];
        if (ahead >= 0) __builtin_prefetch(&cells[ahead], 1);
      }
    const __m256i s = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(slots + k));
    const __m256i clash = _mm256_or_si256(
        _mm256_or_si256(_mm256_cmpeq_epi32(s, _mm256_permutevar8x32_epi32(s, rot1)),
                        _mm256_cmpeq_epi32(s, _mm256_permutevar8x32_epi32(s, rot2))),
        _mm256_or_si256(_mm256_cmpeq_epi32(s, _mm256_permutevar8x32_epi32(s, rot3)),
                        _mm256_cmpeq_epi32(s, _mm256_permutevar8x32_epi32(s, rot4))));
    const __m256i bad = _mm256_or_si256(clash, _mm256_cmpgt_epi32(_mm256_setzero_si256(), s));
    if (!_mm256_testz_si256(bad, bad)) {
      used_scalar += merge_one_by_one(cfg, cells, frame, runs, k, k + 8);
      continue;
    }
    // The eight cells (16 bytes: ref, off, precision, stamp) transposed into lanes. No
    // gather instructions: measured, they took half the batch's time on this CPU.
    alignas(32) int slot[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(slot), s);
    const auto row = [&](int j) { return _mm_loadu_ps(fields + 4 * slot[j]); };
    const __m256 c04 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(0)), row(4), 1);
    const __m256 c15 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(1)), row(5), 1);
    const __m256 c26 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(2)), row(6), 1);
    const __m256 c37 = _mm256_insertf128_ps(_mm256_castps128_ps256(row(3)), row(7), 1);
    const __m256 t0 = _mm256_unpacklo_ps(c04, c15), t1 = _mm256_unpackhi_ps(c04, c15);
    const __m256 t2 = _mm256_unpacklo_ps(c26, c37), t3 = _mm256_unpackhi_ps(c26, c37);
    const __m256 ref = _mm256_shuffle_ps(t0, t2, 0x44);  // lanes 0, 1 of each
    const __m256 off = _mm256_shuffle_ps(t0, t2, 0xEE);  // lanes 2, 3 of each
    const __m256 p = _mm256_shuffle_ps(t1, t3, 0x44);
    const __m256i stamp = _mm256_castps_si256(_mm256_shuffle_ps(t1, t3, 0xEE));
    const __m256i begin = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(starts + k));
    const __m256i end = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(starts + k + 1));
    used = _mm256_add_epi32(used, _mm256_sub_epi32(end, begin));
    const __m256 z_ref = _mm256_loadu_ps(first_z + k);
    const __m256 w = _mm256_loadu_ps(sum_w + k), wz = _mm256_loadu_ps(sum_wz + k);
    // Frames owed: now - stamp, or 0 if the stamp is ahead (unsigned).
    const __m256 owed = _mm256_cvtepi32_ps(_mm256_sub_epi32(now, _mm256_min_epu32(stamp, now)));
    // A run without weight on a cleared cell leaves it cleared (the formula is 0 / 0).
    const __m256 empty =
        _mm256_andnot_ps(_mm256_cmp_ps(w, zero, _CMP_GT_OQ), _mm256_cmp_ps(p, zero, _CMP_EQ_OQ));
    __m256 new_ref_v, new_off_v, new_p_v;
    merge_lanes(ref, off, p, z_ref, w, wz, owed, q, cap, new_ref_v, new_off_v, new_p_v);
    new_ref_v = _mm256_blendv_ps(new_ref_v, ref, empty);
    new_off_v = _mm256_blendv_ps(new_off_v, off, empty);
    new_p_v = _mm256_blendv_ps(new_p_v, p, empty);
    // Back to rows (the stamp lane now the frame), one 16-byte store per cell.
    const __m256 frame_v = _mm256_castsi256_ps(now);
    const __m256 u0 = _mm256_unpacklo_ps(new_ref_v, new_off_v);  // r0 o0 r1 o1 | r4 o4 r5 o5
    const __m256 u1 = _mm256_unpackhi_ps(new_ref_v, new_off_v);  // r2 o2 r3 o3 | r6 o6 r7 o7
    const __m256 u2 = _mm256_unpacklo_ps(new_p_v, frame_v);
    const __m256 u3 = _mm256_unpackhi_ps(new_p_v, frame_v);
    const __m256 rows04 = _mm256_shuffle_ps(u0, u2, 0x44), rows15 = _mm256_shuffle_ps(u0, u2, 0xEE);
    const __m256 rows26 = _mm256_shuffle_ps(u1, u3, 0x44), rows37 = _mm256_shuffle_ps(u1, u3, 0xEE);
    _mm_storeu_ps(fields + 4 * slot[0], _mm256_castps256_ps128(rows04));
    _mm_storeu_ps(fields + 4 * slot[1], _mm256_castps256_ps128(rows15));
    _mm_storeu_ps(fields + 4 * slot[2], _mm256_castps256_ps128(rows26));
    _mm_storeu_ps(fields + 4 * slot[3], _mm256_castps256_ps128(rows37));
    _mm_storeu_ps(fields + 4 * slot[4], _mm256_extractf128_ps(rows04, 1));
    _mm_storeu_ps(fields + 4 * slot[5], _mm256_extractf128_ps(rows15, 1));
    _mm_storeu_ps(fields + 4 * slot[6], _mm256_extractf128_ps(rows26, 1));
    _mm_storeu_ps(fields + 4 * slot[7], _mm256_extractf128_ps(rows37, 1));
  }
  alignas(32) int lanes[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), used);
  for (int j = 0; j < 8; ++j) used_scalar += static_cast<std::size_t>(lanes[j]);
  return used_scalar + merge_one_by_one(cfg, cells, frame, runs, k, count);
}

}  // namespace
#endif

std::size_t KalmanRule::merge_chunk_runs(const Config& cfg, Cell* cells, std::uint32_t frame,
                                         const ChunkRuns& runs) {
#ifdef HAZMAP_HAVE_AVX2
  if (simd::has_avx2()) return merge_avx2(cfg, cells, frame, runs);
#endif
  return merge_chunk_runs_scalar(cfg, cells, frame, runs);
}

}  // namespace hazmap
