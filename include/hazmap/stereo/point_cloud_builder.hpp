#pragma once
// Disparity image -> world-frame points with covariance (SPEC 3.3, 4).
// p_W = T_W_B * T_B_C * R1^T * p_C', Sigma_W = R_W_C' Sigma_C' R_W_C'^T.

#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/map/measurement.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap {

class PointCloudBuilder {
 public:
  /// `valid_roi`: the part of the rectified image with valid source pixels; pixels
  /// outside produce no points.
  PointCloudBuilder(const StereoConfig& stereo, const SensorConfig& sensor,
                    const StereoGeometry& geometry, const Eigen::Matrix3d& R1,
                    const Pose3d& T_B_C, const cv::Rect& valid_roi);

  /// Fills `cloud` (cleared first; its capacity is reused) from a fixed-point disparity
  /// image (CV_16S, x16). Keeps z_min <= Z <= z_max, every stride-th pixel.
  void build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
             PointCloud& cloud) const;

  /// Pose of the rectified left camera in the world: T_W_B * T_B_C * R1^T.
  Pose3d rectified_camera_pose(const Pose3d& T_W_B) const;

 private:
  StereoConfig stereo_;
  SensorConfig sensor_;
  SensorModel model_;
  StereoGeometry geometry_;
  Pose3d T_B_Cr_;  ///< body <- rectified left camera
  cv::Rect roi_;
};

}  // namespace hazmap
