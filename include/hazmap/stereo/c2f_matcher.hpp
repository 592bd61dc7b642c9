#pragma once
// `stereo.matcher: c2f`: a coarse-to-fine census matcher with semi-global aggregation.
//
// An image pyramid (the 5-tap Gaussian of cv::pyrDown, without its allocations). At the coarsest level every pixel searches the whole
// range; at each finer level a pixel searches only +- radius around twice the coarser
// level's disparity at its place. Every level: census transform (a bit per window pixel
// darker than the centre: invariant to gain and offset), cost = differing bits
// (popcount), semi-global aggregation along 4 or 8 paths with penalties P1 / P2 over each
// pixel's own window (a neighbour's disparities outside it cost as if unreachable;
// with p2_edge the jump penalty falls where the left image has an edge),
// winner-takes-all, a left-right check; the coarsest level also a uniqueness test (its
// best against its second-best cost more than 1 px away: the per-pixel confidence), the
// finest sub-pixel disparities: a parabola through the pixel's aggregated sums or, with
// `subpixel_radius` > 0, two lines through the raw census costs summed over a box of
// neighbours at its three disparities. Output: OpenCV's fixed point (CV_16S, x16;
// (min_disparity - 1) x 16 where invalid), with `outline_jump_px` the far side of each
// horizontal outline dropped, then the speckle filter.
//
// Two kernel sets, the same integers: a scalar one (the reference) and AVX2, chosen at
// run time (simd::has_avx2). Rows and columns run in strips on OpenCV's thread pool.
// Every buffer is sized at construction; compute() allocates nothing.

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/stereo/speckle_filter.hpp"
#include "hazmap/stereo/stereo_config.hpp"

namespace hazmap {

namespace c2f {
struct StepParams;  // stereo/c2f_kernels.hpp (internal)
}

/// Which kernels compute() uses: the fastest the CPU runs, or the scalar reference.
enum class C2fKernels { best, scalar };

class C2fMatcher {
 public:
  /// Searches [min_disparity, end_disparity) in `image`-sized pairs; `speckle_window` /
  /// `speckle_range` (px, 0 window: off) as in StereoConfig. Throws Error naming the key
  /// when the range is empty or the pyramid too deep for the image.
  C2fMatcher(const C2fConfig& config, int min_disparity, int end_disparity, cv::Size image,
             int speckle_window, int speckle_range, C2fKernels kernels = C2fKernels::best);
  ~C2fMatcher();
  C2fMatcher(C2fMatcher&&) noexcept;
  C2fMatcher& operator=(C2fMatcher&&) noexcept;

  /// 8-bit grey rectified pair in, fixed-point disparity out (buffer reused).
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16);

  /// Per pixel of the last pair (CV_8U): the coarsest level's (second-best - best) /
  /// second-best cost x 255 at that pixel's place, 0 where that level found nothing.
  const cv::Mat& confidence() const { return confidence_; }
  /// Valid pixels at each level of the last pair, finest first (before the speckle filter).
  const std::vector<std::size_t>& valid_by_level() const { return valid_by_level_; }
  bool uses_avx2() const { return avx2_; }

  struct Level;

 private:
  void match_level(int l);
  void seed_level(int l);
  // match_level's stages, in its order (c2f_matcher.cpp).
  c2f::StepParams step_params(const Level& L) const;
  void compute_costs(Level& L) const;
  void aggregate_rows(Level& L);
  void aggregate_columns(Level& L) const;
  void column_pass(Level& L, int dx, int dy, cv::Range cols) const;
  void column_pass_narrow(Level& L, int dx, int dy, cv::Range cols) const;
  void select_winners(Level& L) const;
  void drop_poor_matches(Level& L) const;
  void refine_subpixel(Level& L) const;
  void drop_outline_rows(cv::Mat& disparity_x16, int invalid);

  C2fConfig config_;
  int min_disparity_ = 0;
  int end_disparity_ = 0;
  int speckle_window_ = 0;
  int speckle_range_ = 0;
  bool avx2_ = false;
  std::vector<Level> levels_;
  std::vector<std::vector<std::int16_t>> scratch_;  // per strip
  int strips_ = 1;
  cv::Mat confidence_;
  SpeckleFilter speckle_;
  std::vector<int> pyramid_row_;  // per strip one source row, filtered vertically
  std::vector<std::size_t> valid_by_level_;
  // stereo.c2f.outline_jump_px: per column the last valid row and its disparity, the drops.
  std::vector<int> outline_row_;
  std::vector<std::int16_t> outline_value_;
  cv::Mat outline_drop_;
  std::vector<std::int16_t> p2_of_diff_;  // 256 entries with stereo.c2f.p2_edge, else empty
  const std::int16_t* p2_lut() const { return p2_of_diff_.empty() ? nullptr : p2_of_diff_.data(); }
};

}  // namespace hazmap
