#pragma once
// Small value types shared by every module. Eigen only.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hazmap {

using Pose3d = Eigen::Isometry3d;  ///< rigid transform; T_A_B maps points of B into A

/// Standard deviations of the pose noise added since the previous frame (SPEC 2, 7).
struct PoseNoise {
  double sx_m = 0.0;
  double sy_m = 0.0;
  double sz_m = 0.0;
  double syaw_rad = 0.0;
};

/// Rotation R = Rz(yaw) Ry(pitch) Rx(roll), angles in radians (SPEC 2).
inline Eigen::Matrix3d rotation_from_rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace hazmap
