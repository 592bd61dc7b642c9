#pragma once
// Geometry guards: checks of a sequence's stereo rig and mounting that run before the
// first frame (hazmap run, stereo, check). Each catches a well-formed but wrong number
// that would otherwise run to an empty or meaningless map: a baseline in millimetres, a
// focal length in millimetres, a T_body_left or a pose that turns the camera away from
// the ground or upside down (a quaternion written scalar first, rpy_deg taken for the
// camera's own pitch), T_body_left left out. Each finding is one line naming the file,
// the key and the likely mistake (units, order, frame).

#include <string>
#include <vector>

#include "hazmap/io/sequence.hpp"

namespace hazmap {

/// What a rover's stereo pair plausibly is; beyond these a number is a mistake.
struct RigLimits {
  double min_baseline_m = 0.01;  ///< 1 cm: below it depth resolves nothing past arm's length
  double max_baseline_m = 2.0;   ///< 2 m: wider than any rover's mast
  /// Field of view across the image's width (fx) or height (fy): a focal length in
  /// millimetres gives nearly 180 deg, one for a larger image a few degrees.
  double min_fov_deg = 2.0;
  double max_fov_deg = 160.0;
  /// A principal point farther than this share of the image from its centre: K written
  /// for another image size, or cx and cy swapped (a warning).
  double max_principal_offset = 0.3;
  /// Roll beyond this (the image's down pointing up) is a camera upside down.
  double max_roll_deg = 90.0;
  /// A mapping camera sees ground in at least this share of its image (rays below the
  /// horizon): a camera turned to the sky may still catch a corner of ground.
  double min_ground_share = 0.1;
};

struct RigFinding {
  bool error = false;   ///< false: a warning (the run goes on)
  std::string message;  ///< one line, naming the file and key
};

/// How a camera orientation meets the ground, in a frame whose z is up.
struct CameraView {
  double axis_elevation_deg = 0.0;    ///< optical axis above (+) or below (-) the horizon
  double ground_share = 0.0;          ///< share of the image's rays below the horizon
  double roll_deg = 0.0;              ///< image down against the world's down, about the axis
  bool sees_ground = false;           ///< ground_share >= RigLimits::min_ground_share
  bool upright = true;                ///< |roll| <= RigLimits::max_roll_deg
  bool plausible() const { return sees_ground && upright; }
};

/// The view of a camera with rotation `R_up_C` (columns: the camera's x right, y down,
/// z forward in a frame with z up) and intrinsics of the calibration's left camera.
CameraView camera_view(const Eigen::Matrix3d& R_up_C, const StereoCalibration& calibration,
                       const RigLimits& limits = {});

/// Every finding for `sequence`, its orientation checks on the first of `frames` (its
/// pose); empty when all is plausible.
std::vector<RigFinding> check_rig_geometry(const Sequence& sequence,
                                           const std::vector<SequenceFrame>& frames,
                                           const RigLimits& limits = {});

/// After a frame: when the ground its points lie on (unit normal `ground_normal_W`) is
/// tilted beyond `max_slope_deg` in W, but reading T_body_left's quaternion (or the
/// pose's) scalar first would level it, the hint that says so ("" otherwise). Both
/// readings can be plausible mounts before a frame is seen (a forward camera pitched down
/// theta, misread, is a level camera turned theta to the side); the ground tells them apart.
std::string scalar_first_hint(const StereoCalibration& calibration, const Pose3d& T_W_B,
                              const Eigen::Vector3d& ground_normal_W, double max_slope_deg);

/// Throws Error with the first error's line; returns the warnings' lines.
std::vector<std::string> enforce_rig_geometry(const std::vector<RigFinding>& findings);

/// The rpy_deg (roll, pitch, yaw) of T_body_left for a camera looking along x_B,
/// pitched down by `pitch_down_deg` and turned left by `yaw_left_deg` (docs/conventions.md):
/// [-(90 + pitch_down), 0, yaw_left - 90].
Eigen::Vector3d forward_camera_rpy_deg(double pitch_down_deg, double yaw_left_deg = 0.0);

}  // namespace hazmap
