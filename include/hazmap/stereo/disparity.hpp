#pragma once
// Block-matching disparity (SPEC 3.2): cv::StereoBM or cv::StereoSGBM with every knob
// from the `stereo` config. Output is OpenCV's fixed point: CV_16S, disparity x 16;
// values <= 16 * min_disparity are invalid.

#include <opencv2/calib3d.hpp>

#include "hazmap/io/config.hpp"

namespace hazmap {

class DisparityMatcher {
 public:
  explicit DisparityMatcher(const StereoConfig& config);

  /// Rectified 8-bit grey images in, fixed-point disparity out (buffer reused).
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity_x16);

  /// Smallest valid fixed-point value (exclusive): d16 > invalid_below() is valid.
  int invalid_below() const { return 16 * min_disparity_; }

 private:
  cv::Ptr<cv::StereoMatcher> matcher_;
  int min_disparity_ = 0;
};

}  // namespace hazmap
