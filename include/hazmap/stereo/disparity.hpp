#pragma once
// Block-matching disparity (SPEC 3.2): cv::StereoBM or cv::StereoSGBM (modes sgbm, hh,
// sgbm_3way, hh4) with every knob from the `stereo` config: range, block size,
// uniqueness, texture threshold and pre-filter (BM), penalties P1/P2 (SGBM), speckle
// filter (speckle_range in pixels: x16 for StereoBM, which compares fixed-point values,
// while SGBM scales it itself), left-right consistency check (disp12_max_diff, -1 off).
// Output is OpenCV's fixed point with 4 fractional bits (sub-pixel): CV_16S, disparity
// x 16; values <= 16 * min_disparity are invalid (SPEC 3.2).
// Matching runs on OpenCV's thread pool (cv::setNumThreads): StereoBM splits the image
// in stripes, SGBM in its sgbm_3way and hh4 modes; sgbm and hh are single-threaded.

#include <opencv2/calib3d.hpp>

#include "hazmap/io/config.hpp"

namespace hazmap {

class DisparityMatcher {
 public:
  /// Throws Error naming the key for an unknown matcher, mode or pre-filter type.
  explicit DisparityMatcher(const StereoConfig& config);

  /// Rectified 8-bit grey images in, fixed-point disparity out (buffer reused).
  /// Throws Error for other image types or sizes that differ.
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16);

  /// Smallest valid fixed-point value (exclusive): d16 > invalid_below() is valid.
  int invalid_below() const { return 16 * min_disparity_; }
  int min_disparity() const { return min_disparity_; }
  int num_disparities() const { return num_disparities_; }

 private:
  cv::Ptr<cv::StereoMatcher> matcher_;
  int min_disparity_ = 0;
  int num_disparities_ = 0;
};

}  // namespace hazmap
