#pragma once
// Stereo calibration (SPEC 2): intrinsics and distortion of both cameras, the pose of
// the right camera relative to the left (x_right = R x_left + T) and the pose of the
// left camera in the body frame.

#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "hazmap/core/types.hpp"

namespace hazmap {

struct CameraIntrinsics {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  std::vector<double> D;  ///< OpenCV distortion coefficients (k1 k2 p1 p2 [k3 ...]); empty = none
};

struct StereoCalibration {
  int image_width = 0;
  int image_height = 0;
  CameraIntrinsics left;
  CameraIntrinsics right;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< x_right = R x_left + T
  Eigen::Vector3d T = Eigen::Vector3d::Zero();      ///< metres
  Pose3d T_B_C = Pose3d::Identity();                ///< left camera in body: p_B = T_B_C p_C
  bool rectified = false;  ///< images are already rectified: no remapping
};

/// Reads our calibration.yaml (SPEC 2). Throws Error naming the file, line and key.
StereoCalibration load_stereo_calibration(const std::filesystem::path& path);

/// Checks internal consistency (positive focal lengths, non-zero baseline, a rotation
/// for R, rectified files with zero distortion); throws Error prefixed by `source`.
void validate(const StereoCalibration& calibration, const std::string& source);

}  // namespace hazmap
