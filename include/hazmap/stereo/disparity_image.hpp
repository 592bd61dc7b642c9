#pragma once
// Disparity images for people and tools (`hazmap stereo`, SPEC 13).

#include <opencv2/core.hpp>

namespace hazmap {

/// Fixed-point disparity (CV_16S, x16) -> CV_16U PNG-ready image holding disparity x 16,
/// 0 where invalid (d16 <= invalid_below_x16; SPEC 3.2). Every valid value is > 0, so
/// 0 is unambiguous. `out` is reused.
void disparity_to_u16(const cv::Mat& disparity_x16, int invalid_below_x16, cv::Mat& out_u16);

/// False colour (8-bit BGR, cv::COLORMAP_TURBO: blue far, red near) over the matcher's
/// range [min_disparity, min_disparity + num_disparities] px; invalid pixels black.
void colorize_disparity(const cv::Mat& disparity_x16, int invalid_below_x16, int min_disparity,
                        int num_disparities, cv::Mat& out_bgr);

}  // namespace hazmap
