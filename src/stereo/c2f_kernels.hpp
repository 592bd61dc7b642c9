#pragma once
// Internal to the c2f matcher (src/stereo/c2f_matcher.cpp): one semi-global aggregation
// step, scalar (the reference) and AVX2, which must agree exactly.

#include <cstdint>

namespace hazmap {
namespace c2f {

/// Cost lanes are processed in chunks of this many int16 (one AVX2 register).
constexpr int kLanes = 16;
/// INF lanes kept on either side of a padded path-cost vector: shifted loads by up to
/// +-(n + 2) lanes for windows of n <= kLanes - 1 stay inside.
constexpr int kPad = 32;
/// A path cost no reachable disparity has: above every real cost (<= 64 + P2 <= 4064)
/// plus P2, and INF + P1 + P2 still fits int16.
constexpr std::int16_t kInf = 0x3FFF;

struct StepParams {
  int n = 0;     ///< disparities in a pixel's window
  int npad = 0;  ///< n rounded up to kLanes
  int p1 = 0;
  int p2 = 0;
  const std::int16_t* pad_mask = nullptr;  ///< last chunk: 0 for lanes < n, kInf beyond
};

/// One pixel p of a path after its predecessor q: for each k < n (disparity dmin_p + k)
///   Lp[k] = C[k] + min(Lq[k + delta], Lq[k + delta +- 1] + P1, minLq + P2) - minLq,
/// terms outside q's window left out; delta = dmin_p - dmin_q. Without a predecessor
/// (lq == nullptr: the path starts or q has no window) Lp = C. Adds Lp to S (uint16,
/// wrapping; only lanes < n are meaningful) and returns min_k Lp[k].
/// Scalar: lq and lp point at lane 0 of n-lane vectors.
int step_scalar(const std::int16_t* lq, int min_lq, int delta, const std::uint8_t* cost,
                const StepParams& p, std::int16_t* lp, std::uint16_t* sum);
/// AVX2: lq and lp point at lane 0 of padded vectors (kPad kInf lanes before, npad
/// lanes, kPad kInf lanes after); lanes n..npad of lp are set to kInf.
int step_avx2(const std::int16_t* lq, int min_lq, int delta, const std::uint8_t* cost,
              const StepParams& p, std::int16_t* lp, std::uint16_t* sum);
/// Whether step_avx2 exists in this build and the CPU runs it.
bool avx2_available();

}  // namespace c2f
}  // namespace hazmap
