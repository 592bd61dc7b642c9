#pragma once
// Internal to the c2f matcher (src/stereo/c2f_matcher.cpp): its kernels, scalar (the
// reference) and AVX2, which must agree exactly: the census of a row, one semi-global
// aggregation step over a padded 16-lane window (the full-range level and wide windows),
// and the narrow levels' row and column passes (windows of <= kNarrowMax disparities in
// one 8-lane vector, costs computed in the first row pass).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

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

/// dmin of a pixel without a window (no seed from the coarser level).
constexpr std::int16_t kNoSeed = std::numeric_limits<std::int16_t>::min();

/// Census codes of one row: bit j of code[x] set where the j-th pixel of x's window
/// (row-major, centre skipped) is darker than the centre. rows[i] is window row i (of
/// ch) of a padded image, x's window starting at column x; cw x ch - 1 <= 64 bits.
void census_row_scalar(const std::uint8_t* const* rows, int cw, int ch, int width,
                       std::uint64_t* code);
void census_row_avx2(const std::uint8_t* const* rows, int cw, int ch, int width,
                     std::uint64_t* code);

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
/// A narrow level: each pixel's window of n <= kNarrowMax disparities in kNarrow lanes.
constexpr int kNarrow = 8;
constexpr int kNarrowMax = kNarrow - 1;

/// One image row of a narrow level.
struct NarrowRow {
  int width = 0;
  int n = 0;     ///< disparities per window, <= kNarrowMax
  int bits = 0;  ///< census bits: the cost where the right pixel lies outside the image
  int p1 = 0, p2 = 0;
  /// Edge-aware P2: p2_of_diff[|image[x] - image[x -+ 1]|] replaces p2 (nullptr: p2).
  const std::int16_t* p2_of_diff = nullptr;
  const std::uint8_t* image = nullptr;  ///< this row of the left image (with p2_of_diff)
  const std::int16_t* dmin = nullptr;  ///< width; kNoSeed: no window
  const std::uint64_t* census_l = nullptr;
  const std::uint64_t* census_r = nullptr;
  std::uint8_t* cost = nullptr;  ///< width x kNarrow, written (lanes < n)
  std::uint16_t* sum = nullptr;  ///< width x kNarrow, set to the two row paths (lanes < n)
};
/// Both row paths of a row: left to right (computing and storing the costs, setting the
/// sums), then right to left (adding), each pixel a step_scalar of its window.
void rows_narrow_scalar(const NarrowRow& r);
void rows_narrow_avx2(const NarrowRow& r);

/// A narrow level's column-pass state row: pixel x's kNarrow path costs at lanes
/// kStatePad + x kStateStride, with kStatePad kInf lanes before each pixel's and after the
/// last, so that a window shifted by up to +-(kNarrow + 1) lanes is one plain load.
constexpr int kStatePad = 16;
constexpr int kStateStride = kStatePad + kNarrow;
/// Lanes of one state row of `width` pixels.
constexpr std::size_t state_row_lanes(int width) {
  return static_cast<std::size_t>(width) * kStateStride + kStatePad;
}
/// Where pixel x's path costs start in a state row.
constexpr std::size_t state_at(int x) {
  return static_cast<std::size_t>(x) * kStateStride + kStatePad;
}

/// One row of a column (dx 0) or diagonal (dx +-1) path of a narrow level: pixel x after
/// pixel x - dx of the row before, for x in [x0, x1).
struct NarrowColumnRow {
  int width = 0, n = 0, p1 = 0, p2 = 0;
  int x0 = 0, x1 = 0, dx = 0;
  /// Edge-aware P2: p2_of_diff[|image[x] - prev_image[x - dx]|] replaces p2 (nullptr: p2).
  const std::int16_t* p2_of_diff = nullptr;
  const std::uint8_t* image = nullptr;       ///< this row of the left image
  const std::uint8_t* prev_image = nullptr;  ///< the row before
  const std::int16_t* dmin = nullptr;       ///< this row
  const std::int16_t* prev_dmin = nullptr;  ///< the row before; nullptr: the path starts here
  const std::int16_t* prev = nullptr;       ///< its path costs, a state row (state_at)
  const int* prev_min = nullptr;            ///< and their minima, width
  std::int16_t* cur = nullptr;              ///< this row's path costs, a state row; only
                                            ///< the kNarrow lanes of each pixel written
  int* cur_min = nullptr;
  const std::uint8_t* cost = nullptr;  ///< width x kNarrow
  std::uint16_t* sum = nullptr;        ///< width x kNarrow, += this path
};
void column_row_narrow_scalar(const NarrowColumnRow& r);
void column_row_narrow_avx2(const NarrowColumnRow& r);

/// The jump penalty of a path step between grey values a and b: the edge-aware table's
/// entry for |a - b| (callers without a table keep the plain p2).
inline int edge_p2(const std::int16_t* p2_of_diff, int a, int b) {
  return p2_of_diff[a > b ? a - b : b - a];
}

/// Above every sum of path costs (<= 8 paths x (64 + p2 <= 4000) = 32512).
constexpr std::uint16_t kNoSum = 0xFFFF;

/// One row of a level's decisions (C2fMatcher::match_level).
struct WinnerRow {
  const std::uint16_t* sum = nullptr;  ///< width x npad
  int npad = 0, n = 0, width = 0, lo = 0, hi = 0, uniqueness = 0;
  bool full = false;
  const std::int16_t* dmin = nullptr;
  std::uint16_t* right_s = nullptr;  ///< in: kNoSum; out: per right pixel the lowest sum
  std::int16_t* right_d = nullptr;   ///< in: -1; out: its disparity
  float* disp = nullptr;             ///< out, < 0 invalid
  std::int16_t* winner = nullptr;    ///< out, whole-pixel winner
  std::uint8_t* conf = nullptr;      ///< out (full level only)
};
/// Offers left pixel x's sums s[0..n) (disparities d0 + k) to the right pixels x - d0 - k
/// they match: each right pixel keeps its first lowest sum, for the left-right check.
/// Shared by winners_row (scalar) and winners_narrow_avx2.
inline void offer_to_right(const WinnerRow& r, const std::uint16_t* s, int x, int d0, int n) {
  if (x - d0 < 0) return;  // every right pixel left of the image
  const int kmax = std::min(n - 1, x - d0);
  std::uint16_t* rs = r.right_s + (x - d0);
  std::int16_t* rd = r.right_d + (x - d0);
  for (int k = 0; k <= kmax; ++k) {
    const bool lower = s[k] < rs[-k];
    rs[-k] = lower ? s[k] : rs[-k];
    rd[-k] = lower ? static_cast<std::int16_t>(d0 + k) : rd[-k];
  }
}

/// The decisions of a narrow level's row (winners_row in the matcher is the reference;
/// sums of kNarrow lanes): the first lowest sum by one minpos.
void winners_narrow_avx2(const WinnerRow& r);

/// Whether step_avx2 exists in this build and the CPU runs it.
bool avx2_available();

}  // namespace c2f
}  // namespace hazmap
