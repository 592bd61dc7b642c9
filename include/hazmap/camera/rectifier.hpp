#pragma once
// Stereo rectification (SPEC 3.1). The undistort/rectify maps are computed once at
// construction; per frame only cv::remap runs. Points triangulated from rectified
// images live in the rectified left frame C'; p_C = R1^T p_C'.

#include <opencv2/core.hpp>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap {

class Rectifier {
 public:
  /// `alpha` as in cv::stereoRectify (0: only valid pixels, 1: all source pixels,
  /// -1: OpenCV's default). Rectified calibrations skip remapping.
  Rectifier(const StereoCalibration& calibration, double alpha);

  /// Remaps both 8-bit grey images into the rectified frame, reusing `out_*` buffers.
  /// For rectified sequences this is a shallow copy. Throws Error if a size differs
  /// from the calibration's.
  void rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& out_left,
               cv::Mat& out_right) const;

  /// Focal length, baseline and principal point of the rectified pair.
  const StereoGeometry& geometry() const { return geometry_; }
  /// Rotation from the original left camera frame to the rectified one (p_C' = R1 p_C).
  const Eigen::Matrix3d& R1() const { return R1_; }
  /// The part of the rectified left image where every pixel has valid source data.
  const cv::Rect& valid_roi() const { return valid_roi_; }
  cv::Size image_size() const { return size_; }

 private:
  cv::Size size_;
  bool identity_ = false;
  cv::Mat map_left_x_, map_left_y_, map_right_x_, map_right_y_;
  StereoGeometry geometry_;
  Eigen::Matrix3d R1_ = Eigen::Matrix3d::Identity();
  cv::Rect valid_roi_;
};

}  // namespace hazmap
