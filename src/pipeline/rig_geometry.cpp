#include "hazmap/pipeline/rig_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c, d);
  return text;
}

/// A unit quaternion's four numbers as written in calibration.yaml and poses.txt
/// (qx, qy, qz, qw) read the other way, scalar first: w = qx, x = qy, y = qz, z = qw.
Eigen::Matrix3d read_scalar_first(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return Eigen::Quaterniond(q.x(), q.y(), q.z(), q.w()).normalized().toRotationMatrix();
}

std::string describe(const CameraView& v) {
  if (!v.sees_ground)
    return fmt("its optical axis points %.0f deg ", std::abs(v.axis_elevation_deg)) +
           (v.axis_elevation_deg >= 0 ? "above" : "below") + " the horizon and " +
           (v.ground_share > 0 ? fmt("only %.0f %% of the image looks below it", 100 * v.ground_share)
                               : std::string("no pixel looks below it"));
  return fmt("its image is rolled %.0f deg (the image's down points up; optical axis %.0f deg ",
             std::abs(v.roll_deg), std::abs(v.axis_elevation_deg)) +
         (v.axis_elevation_deg >= 0 ? "above" : "below") + " the horizon)";
}

const char* const kMountRule =
    "rpy_deg rotates the camera's axes (x right, y down, z forward) into the body's "
    "(x forward, y left, z up): a forward camera pitched down theta is "
    "rpy_deg: [-(90 + theta), 0, -90], quaternion [qx, qy, qz, qw] scalar last "
    "(docs/conventions.md)";

void check_baseline(const StereoCalibration& c, const RigLimits& limits,
                    std::vector<RigFinding>& out) {
  const double b = c.T.norm();
  if (b >= limits.min_baseline_m && b <= limits.max_baseline_m) return;
  const std::string key = c.models.empty() ? "T" : "left.C, right.C";
  std::string hint;
  if (b > limits.max_baseline_m && b / 1000 >= limits.min_baseline_m && b / 1000 <= limits.max_baseline_m)
    hint = fmt("; T is in metres: %g looks like millimetres (%g m)", b, b / 1000);
  else if (b > limits.max_baseline_m && b / 100 >= limits.min_baseline_m)
    hint = fmt("; T is in metres: %g looks like centimetres (%g m)", b, b / 100);
  else
    hint = "; T is in metres";
  out.push_back({true, c.source + ": key '" + key + "': baseline |T| = " + fmt("%g", b) +
                           " m is outside " + fmt("%g-%g m", limits.min_baseline_m, limits.max_baseline_m) +
                           ", the range of a rover's stereo pair" + hint});
}

void check_focal(const StereoCalibration& c, const RigLimits& limits, std::vector<RigFinding>& out) {
  if (!c.models.empty()) return;  // K follows from the models' H and V
  for (const auto* cam : {&c.left, &c.right}) {
    const std::string key = std::string(cam == &c.left ? "left" : "right") + ".K";
    for (int axis = 0; axis < 2; ++axis) {
      const double f = cam->K(axis, axis);
      const double side = axis == 0 ? c.image_width : c.image_height;
      const double fov = 2 * std::atan(0.5 * side / f) * kRadToDeg;
      // The two messages differ only in the field of view's precision and the hint.
      const auto implausible = [&](const char* fov_format, const char* hint) {
        out.push_back({true, c.source + ": key '" + key + "': " + (axis ? "fy" : "fx") +
                                 fmt(" = %g px gives a ", f) + fmt(fov_format, fov) +
                                 fmt(" deg field of view across the %.0f px image (plausible: %g-%g "
                                     "deg): ",
                                     side, limits.min_fov_deg, limits.max_fov_deg) +
                                 hint});
      };
      if (fov > limits.max_fov_deg) {
        implausible("%.0f", "K is in pixels; a focal length in millimetres must be divided by the "
                            "pixel pitch (f_px = f_mm / pitch_mm)");
        return;
      }
      if (fov < limits.min_fov_deg) {
        implausible("%.2f", "K must be in pixels of these images (written for a larger image, or in "
                            "other units?)");
        return;
      }
    }
    const double cx = cam->K(0, 2), cy = cam->K(1, 2);
    const double w = c.image_width, h = c.image_height;
    if (std::abs(cx - 0.5 * (w - 1)) > limits.max_principal_offset * w ||
        std::abs(cy - 0.5 * (h - 1)) > limits.max_principal_offset * h)
      out.push_back({false, c.source + ": key '" + key +
                                fmt("': principal point (%g, %g) px is far from the centre of the "
                                    "%.0f x ",
                                    cx, cy, w) +
                                fmt("%.0f px image: K written for another image size, or cx and "
                                    "cy swapped?",
                                    h)});
  }
}

/// The orientation checks: the left camera in W at the first frame's pose. Blames the
/// pose when the camera would be fine on a level body, else T_body_left.
void check_orientation(const Sequence& seq, const SequenceFrame& frame, const RigLimits& limits,
                       std::vector<RigFinding>& out) {
  const StereoCalibration& c = seq.calibration;
  const Eigen::Matrix3d R_B_C = c.T_B_C.linear();
  const Eigen::Matrix3d R_W_B = frame.pose.T_W_B.linear();
  const CameraView in_w = camera_view(R_W_B * R_B_C, c, limits);
  if (in_w.plausible()) return;
  const CameraView in_b = camera_view(R_B_C, c, limits);
  const std::string poses = seq.poses_source.empty() ? std::string("poses") : seq.poses_source;
  if (in_b.plausible()) {
    // The mount is fine on a level body: the pose turns it away.
    const double tilt = std::acos(std::clamp(R_W_B(2, 2), -1.0, 1.0)) * kRadToDeg;
    std::string hint = "poses are T_W_B (the body in W), quaternion qx qy qz qw, scalar last";
    if (camera_view(read_scalar_first(R_W_B) * R_B_C, c, limits).plausible())
      hint = "the quaternion looks written scalar first (qw qx qy qz): poses.txt wants "
             "qx qy qz qw";
    else if (camera_view(R_W_B.transpose() * R_B_C, c, limits).plausible())
      hint = "its inverse would be plausible: poses are T_W_B (the body in W), not the "
             "world seen from the body";
    out.push_back({true, poses + ": frame '" + frame.name +
                             fmt("': the body is tilted %.0f deg from level, so the left camera "
                                 "is wrong way round in W: ",
                                 tilt) +
                             describe(in_w) + "; " + hint});
    return;
  }
  std::string hint = kMountRule;
  if (c.body_pose_source == BodyPoseSource::quaternion &&
      camera_view(R_W_B * read_scalar_first(R_B_C), c, limits).plausible())
    hint = "the quaternion looks written scalar first ([qw, qx, qy, qz]): hazmap reads "
           "[qx, qy, qz, qw]; move the first number to the end";
  else if (c.body_pose_source == BodyPoseSource::rpy_deg)
    hint = std::string("rpy_deg is not the camera's own pitch: ") + kMountRule;
  out.push_back({true, c.source + ": key 'T_body_left': the left camera is mounted so that " +
                           describe(in_b) + "; " + hint});
}

}  // namespace

CameraView camera_view(const Eigen::Matrix3d& R_up_C, const StereoCalibration& c,
                       const RigLimits& limits) {
  CameraView v;
  const Eigen::Vector3d axis = R_up_C.col(2);
  v.axis_elevation_deg = std::asin(std::clamp(axis.z(), -1.0, 1.0)) * kRadToDeg;
  // The share of the image below the horizon, from a grid of pixel rays.
  const Eigen::Matrix3d& K = c.left.K;
  const double w = c.image_width - 1, h = c.image_height - 1;
  constexpr int kGrid = 17;
  int below = 0;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u = w * i / (kGrid - 1), y = h * j / (kGrid - 1);
      const Eigen::Vector3d ray =
          R_up_C * Eigen::Vector3d((u - K(0, 2)) / K(0, 0), (y - K(1, 2)) / K(1, 1), 1.0);
      below += ray.z() < 0 ? 1 : 0;
    }
  v.ground_share = static_cast<double>(below) / (kGrid * kGrid);
  v.sees_ground = v.ground_share >= limits.min_ground_share;
  // Roll: the world's down seen in the image plane, against the image's down (+y).
  const Eigen::Vector3d down_c = R_up_C.transpose() * Eigen::Vector3d(0, 0, -1);
  const double in_plane = std::hypot(down_c.x(), down_c.y());
  // Looking (nearly) straight down or up, the image has no down: no roll to measure.
  v.roll_deg = in_plane < std::sin(10.0 / kRadToDeg) ? 0.0
                                                     : std::atan2(-down_c.x(), down_c.y()) * kRadToDeg;
  v.upright = std::abs(v.roll_deg) <= limits.max_roll_deg;
  return v;
}

std::vector<RigFinding> check_rig_geometry(const Sequence& seq,
                                           const std::vector<SequenceFrame>& frames,
                                           const RigLimits& limits) {
  std::vector<RigFinding> out;
  const StereoCalibration& c = seq.calibration;
  check_baseline(c, limits, out);
  check_focal(c, limits, out);
  if (c.body_pose_source == BodyPoseSource::absent) {
    out.push_back({false, c.source + ": T_body_left is absent: the identity is used (the left "
                                     "camera at the body origin, looking up z_B), which sees no "
                                     "ground; give the camera's pose on the rover (docs/conventions.md)"});
  } else if (seq.poses_assumed_identity) {
    // No poses: W is the body frame, whatever that is (EuRoC's IMU): nothing to check.
  } else if (!frames.empty()) {
    check_orientation(seq, frames.front(), limits, out);
  }
  return out;
}

std::string scalar_first_hint(const StereoCalibration& c, const Pose3d& T_W_B,
                              const Eigen::Vector3d& n_W, double max_slope_deg) {
  auto tilt = [](const Eigen::Vector3d& n) {
    return std::acos(std::clamp(std::abs(n.normalized().z()), 0.0, 1.0)) * kRadToDeg;
  };
  if (!(tilt(n_W) > max_slope_deg)) return {};
  const Eigen::Matrix3d R_W_B = T_W_B.linear(), R_B_C = c.T_B_C.linear();
  const Eigen::Vector3d n_C = (R_W_B * R_B_C).transpose() * n_W;  // as the camera saw it
  if (c.body_pose_source == BodyPoseSource::quaternion) {
    const double t = tilt(R_W_B * read_scalar_first(R_B_C) * n_C);
    if (t <= max_slope_deg)
      return fmt("; T_body_left's quaternion looks written scalar first: read so, the ground "
                 "would be tilted %.1f deg; hazmap reads [qx, qy, qz, qw]",
                 t);
  }
  const Eigen::Vector3d n_B = R_W_B.transpose() * n_W;
  const double t = tilt(read_scalar_first(R_W_B) * n_B);
  if (t <= max_slope_deg)
    return fmt("; the pose's quaternion looks written scalar first: read so, the ground would "
               "be tilted %.1f deg; poses.txt wants qx qy qz qw",
               t);
  return {};
}

std::vector<std::string> enforce_rig_geometry(const std::vector<RigFinding>& findings) {
  std::vector<std::string> warnings;
  for (const RigFinding& f : findings) {
    if (f.error) throw Error(f.message);
    warnings.push_back(f.message);
  }
  return warnings;
}

Eigen::Vector3d forward_camera_rpy_deg(double pitch_down_deg, double yaw_left_deg) {
  return {-(90.0 + pitch_down_deg), 0.0, yaw_left_deg - 90.0};
}

}  // namespace hazmap
