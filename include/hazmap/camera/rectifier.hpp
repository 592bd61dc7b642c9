#pragma once
// Stereo rectification (SPEC 3.1). The undistort/rectify maps are computed once at
// construction (cv::stereoRectify with CALIB_ZERO_DISPARITY, then
// cv::initUndistortRectifyMap; for JPL CAHV/CAHVOR/CAHVORE models stereoRectify on their
// linear parts, maps through the full models); per frame only cv::remap runs. Points
// triangulated from rectified images live in the rectified left frame C';
// p_C = R1^T p_C'.
// Thread safety: const methods may run concurrently.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/camera/stereo_geometry.hpp"

namespace hazmap {

enum class StereoSide { left, right };

class Rectifier {
 public:
  /// `alpha` as in cv::stereoRectify (0: only valid pixels, 1: all source pixels,
  /// -1: OpenCV's default). Rectified calibrations skip remapping. Throws Error if the
  /// right camera is not to the right of the left one after rectification.
  /// `row_offset_px`: set_row_offset()'s shift, 0 for none.
  Rectifier(const StereoCalibration& calibration, double alpha, double row_offset_px = 0.0);

  /// Moves the rectified right image down by `px` rows (its maps rebuilt: the rectified
  /// right camera's principal point cy + px), so that a pair whose rectified rows differ
  /// by y_left - y_right = px (row_offset.hpp) agrees. Rectified calibrations get a
  /// remap of the right image then. Not per frame: it builds a map.
  void set_row_offset(double px);
  double row_offset() const { return row_offset_px_; }

  /// Remaps both images (any depth and channel count, e.g. 8-bit grey) into the
  /// rectified frame, reusing the `out_*` buffers. For rectified sequences this is a
  /// shallow copy. Throws Error if a size differs from the calibration's.
  void rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& out_left,
               cv::Mat& out_right) const;

  /// Maps raw (distorted) pixel positions of one camera to the rectified image, the
  /// exact inverse of what rectify() does to pixels (cv::undistortPoints with R and P).
  void rectify_points(StereoSide side, const std::vector<cv::Point2f>& raw_px,
                      std::vector<cv::Point2f>& rectified_px) const;

  /// Focal length, baseline and principal point of the rectified pair.
  const StereoGeometry& geometry() const { return geometry_; }
  /// Rotation from the original left camera frame to the rectified one (p_C' = R1 p_C).
  const Eigen::Matrix3d& R1() const { return R1_; }
  /// The part of the rectified left image where every pixel has valid source data.
  const cv::Rect& valid_roi() const { return valid_roi_; }
  /// The same for the rectified right image.
  const cv::Rect& valid_roi_right() const { return valid_roi_right_; }
  cv::Size image_size() const { return size_; }
  /// True when the calibration says the images are already rectified (no remapping).
  bool identity() const { return identity_; }

 private:
  cv::Size size_;
  bool identity_ = false;
  bool remap_right_ = false;  ///< identity_ with a row offset: the right image is remapped
  double row_offset_px_ = 0.0;
  cv::Rect roi_right_unshifted_;
  cv::Mat map_left_x_, map_left_y_, map_right_x_, map_right_y_;
  cv::Mat K1_, D1_, K2_, D2_, R1_cv_, R2_cv_, P1_, P2_;
  cv::Mat P2_shifted_;  ///< P2_ with cy + row_offset_px_: what the right map uses
  std::vector<CahvoreModel> models_;  ///< JPL models {left, right}, or empty
  StereoGeometry geometry_;
  Eigen::Matrix3d R1_ = Eigen::Matrix3d::Identity();
  cv::Rect valid_roi_;
  cv::Rect valid_roi_right_;
};

}  // namespace hazmap
