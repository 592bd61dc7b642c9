#pragma once
// ASL / EuRoC MAV sequences (Burri et al. 2016), read directly or imported into our
// sequence layout (SPEC 2):
//   SRC/mav0/cam0/data/<t_ns>.png   left (raw: distorted, unrectified)
//   SRC/mav0/cam1/data/<t_ns>.png   right
//   SRC/mav0/cam{0,1}/sensor.yaml   Kalibr-style: resolution, intrinsics [fu fv cu cv],
//                                   radial-tangential distortion [k1 k2 p1 p2],
//                                   T_BS (4x4 pose of the camera in the body/IMU frame)
//   SRC/mav0/state_groundtruth_estimate0/data.csv   body poses (optional)
// Calibration: T_C1_C0 = T_BS1^-1 T_BS0 gives R, T (x_right = R x_left + T) and
// T_body_left = T_BS0, so our body frame is EuRoC's IMU frame (which is not x forward,
// z up). Pose CSVs are "t_ns, x, y, z, qw, qx, qy, qz[, ...]" (Hamilton, scalar first,
// extra columns ignored), of the body or of the left camera.

#include <cstdint>
#include <filesystem>
#include <functional>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/io/sequence.hpp"

namespace hazmap {

/// One camera's sensor.yaml.
struct EurocCamera {
  int width_px = 0;
  int height_px = 0;
  CameraIntrinsics intrinsics;
  Pose3d T_B_S = Pose3d::Identity();  ///< camera in the body frame: p_B = T_B_S p_S
};

/// Reads a Kalibr-style sensor.yaml (pinhole, radial-tangential or no distortion).
/// Throws Error naming the file, line and key.
EurocCamera read_euroc_camera(const std::filesystem::path& sensor_yaml);

/// The stereo calibration of cam0 (left) and cam1 (right) under `mav0`.
StereoCalibration euroc_stereo_calibration(const std::filesystem::path& mav0);

enum class EurocPoseFrame { body, left_camera };

struct EurocOptions {
  /// Pose CSV; empty: mav0/state_groundtruth_estimate0/data.csv when it exists.
  std::filesystem::path poses_csv;
  EurocPoseFrame poses_frame = EurocPoseFrame::body;
  /// Images between two pose samples at most this far apart get an interpolated pose
  /// (linear position, slerp rotation); images with no exact or bracketing sample are
  /// left out.
  std::int64_t max_pose_gap_ns = 100'000'000;
  /// Without any pose source: true puts every frame at the identity, false throws.
  bool identity_poses = false;
};

/// `dir` itself or `dir/mav0` when that holds cam0 and cam1; empty path otherwise.
std::filesystem::path find_euroc_mav0(const std::filesystem::path& dir);

/// The sequence as our loader would give it, frames referring to the original PNGs
/// (pairs present in both cam0 and cam1 and with a pose), sorted by name (= time).
/// Throws Error naming the file at fault, or when no frame is left.
Sequence load_euroc_sequence(const std::filesystem::path& dir, const EurocOptions& options = {});

/// Writes `dst` in our layout (left/, right/, calibration.yaml, poses.txt) from the
/// frames load_euroc_sequence() keeps; images are copied byte for byte. Every file is
/// written atomically, poses.txt first (its first line, "... imported from EuRoC ...",
/// marks the folder as an import: output_folder.hpp). `before_writing`, when given, is
/// called once SRC has been read and checked, before the first file is written (hazmap
/// import-euroc --overwrite clears DST there). Returns the number of frames.
size_t import_euroc(const std::filesystem::path& src, const std::filesystem::path& dst,
                    const EurocOptions& options = {},
                    const std::function<void()>& before_writing = {});

}  // namespace hazmap
