#pragma once
// Stereo calibration (SPEC 2): intrinsics and distortion of both cameras, the pose of
// the right camera relative to the left (x_right = R x_left + T) and the pose of the
// left camera in the body frame. Reading and writing calibration files:
// hazmap/io/calibration_file.hpp.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "hazmap/camera/cahvore.hpp"
#include "hazmap/core/types.hpp"

namespace hazmap {

/// Plausibility limits of validate(): values beyond them are corrupt files, not cameras.
/// Focal length in pixels, per pixel of the image's larger side (1000: a field of view
/// under 0.06 deg, a telescope rather than a mapping camera).
constexpr double kMaxFocalPerImageSide = 1000.0;
/// |skew| / fx: tan of how far the pixel axes are from square (0.1: about 6 deg; real
/// sensors are within a small fraction of a degree).
constexpr double kMaxSkewPerFocal = 0.1;
/// Baseline and camera offset on the body, metres: 100 m is wider than any stereo rig
/// or rover.
constexpr double kMaxBaselineM = 100.0;

struct CameraIntrinsics {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  std::vector<double> D;  ///< OpenCV distortion coefficients (k1 k2 p1 p2 [k3 ...]); empty = none
};

/// How T_body_left came to be, for the geometry guards' messages
/// (pipeline/rig_geometry.hpp): set in code or derived (simulator, JPL models, EuRoC's
/// T_BS), written as rpy_deg or as a quaternion, or left out (then the identity).
enum class BodyPoseSource { code, rpy_deg, quaternion, absent };

struct StereoCalibration {
  int image_width = 0;
  int image_height = 0;
  CameraIntrinsics left;
  CameraIntrinsics right;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< x_right = R x_left + T
  Eigen::Vector3d T = Eigen::Vector3d::Zero();      ///< metres
  Pose3d T_B_C = Pose3d::Identity();                ///< left camera in body: p_B = T_B_C p_C
  BodyPoseSource body_pose_source = BodyPoseSource::code;  ///< how T_B_C was given
  bool rectified = false;  ///< images are already rectified: no remapping
  /// JPL camera models {left, right} when calibration.yaml says `camera_model: cahv |
  /// cahvor | cahvore`; empty for OpenCV's pinhole + distortion. With models, K above is
  /// each model's linear (CAHV) part, D is empty, R, T and T_B_C are derived from the
  /// models' C, A, H, V and T_B_M, and the rectifier maps pixels through the full models.
  std::vector<CahvoreModel> models;
  Pose3d T_B_M = Pose3d::Identity();  ///< the models' frame M in the body: p_B = T_B_M p_M
  std::string source;      ///< the file it was read from, for messages ("" if none)
};

/// Fills K, D, R, T and T_B_C of `calibration` from its two models and T_B_M (see
/// StereoCalibration::models). Throws Error prefixed by `source` on an unusable model.
void derive_from_models(StereoCalibration& calibration, const std::string& source);

/// Checks internal consistency (positive focal lengths, non-zero baseline, a rotation
/// for R, rectified files with zero distortion); throws Error prefixed by `source`.
void validate(const StereoCalibration& calibration, const std::string& source);

}  // namespace hazmap
