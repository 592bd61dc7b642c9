#pragma once
// Why a run produced no point: the pixels of frames without points, counted by the gate
// that dropped them, and the one setting most likely wrong. Counted only for frames that
// gave no point (a pass over the disparity image, allocating nothing), so a run that
// works pays nothing; `hazmap run` ends non-zero with this line when no frame gave one.

#include <cstddef>
#include <string>

#include <opencv2/core.hpp>


namespace hazmap {

struct EmptyRunCounts {
  std::size_t frames = 0;             ///< frames counted
  std::size_t pixels = 0;             ///< pixels of the region that may give points
  std::size_t no_disparity = 0;       ///< no match (or the matcher's invalid value)
  std::size_t beyond_z_max = 0;       ///< disparity below f B / stereo.z_max
  std::size_t nearer_than_z_min = 0;  ///< disparity above f B / stereo.z_min
  std::size_t unsupported = 0;        ///< removed as floating mismatches (support_rows)
  std::size_t below_ground = 0;       ///< below the wheel plane (SPEC 3.3)
  std::size_t occluded = 0;           ///< seen through terrain already mapped
};

/// Adds one frame's disparity image (x16, the matcher's) over `region` to `drops`:
/// pixels, no disparity, and the depth gate's two sides (d_min = f B / z_max, d_max =
/// f B / z_min). The frame's unsupported, below-ground and occluded counts are added by
/// the caller from its FrameReport.
void count_disparity_drops(const cv::Mat& disparity_x16, const cv::Rect& region,
                           int invalid_below_x16, double d_min_px, double d_max_px,
                           EmptyRunCounts& drops);

/// The one line `hazmap run` ends with when no frame gave a point: the counts and the
/// setting most likely wrong.
std::string no_points_message(const EmptyRunCounts& drops);

}  // namespace hazmap
