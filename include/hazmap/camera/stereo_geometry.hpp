#pragma once
// A rectified stereo pair's geometry, as the rectifier makes it and the stereo stage
// reads it: focal length, baseline and principal point, and where the rectified left
// camera C' (x right, y down, z forward) sits on the body.

#include <Eigen/Core>

#include "hazmap/core/types.hpp"

namespace hazmap {

struct StereoGeometry {
  double focal_px = 0.0;    ///< f of the rectified pair
  double baseline_m = 0.0;  ///< B > 0
  double cx_px = 0.0;
  double cy_px = 0.0;
};

/// Pose of the rectified left camera C' in the body: T_B_C * R1^T (p_C' = R1 p_C).
inline Pose3d rectified_camera_in_body(const Pose3d& T_B_C, const Eigen::Matrix3d& R1) {
  Pose3d T_C_Cr = Pose3d::Identity();
  T_C_Cr.linear() = R1.transpose();
  return T_B_C * T_C_Cr;
}

}  // namespace hazmap
