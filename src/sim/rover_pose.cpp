#include "hazmap/sim/rover_pose.hpp"

#include <cmath>
#include <random>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

WheelPlane wheel_plane(const Terrain& terrain, const Eigen::Vector2d& p_W, double yaw_rad,
                       const WheelGeometry& wheels) {
  check(wheels.wheelbase_m > 0.0 && wheels.track_m > 0.0,
        "rover pose: wheelbase_m and track_m must be positive");
  const Eigen::Vector2d forward(std::cos(yaw_rad), std::sin(yaw_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  auto ground = [&](double along_m, double across_m) {
    const Eigen::Vector2d q = p_W + along_m * forward + across_m * left;
    return terrain.ground_height_m(q.x(), q.y());
  };
  const double half_base_m = 0.5 * wheels.wheelbase_m;
  const double half_track_m = 0.5 * wheels.track_m;
  const double front_left = ground(half_base_m, half_track_m);
  const double front_right = ground(half_base_m, -half_track_m);
  const double rear_left = ground(-half_base_m, half_track_m);
  const double rear_right = ground(-half_base_m, -half_track_m);
  const double b = 0.5 * (front_left + front_right - rear_left - rear_right) / wheels.wheelbase_m;
  const double c = 0.5 * (front_left + rear_left - front_right - rear_right) / wheels.track_m;
  WheelPlane plane;
  plane.height_m = 0.25 * (front_left + front_right + rear_left + rear_right);
  plane.pitch_rad = -std::atan(b);
  plane.roll_rad = std::atan(c * std::cos(plane.pitch_rad));
  return plane;
}

Pose3d pose_on_ground(const Terrain& terrain, const PathPoint& point, const WheelGeometry& wheels) {
  const WheelPlane plane = wheel_plane(terrain, point.p_W, point.yaw_rad, wheels);
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = rotation_from_rpy(plane.roll_rad, plane.pitch_rad, point.yaw_rad);
  T_W_B.translation() = Eigen::Vector3d(point.p_W.x(), point.p_W.y(), plane.height_m);
  return T_W_B;
}

void validate(const DriftOptions& options) {
  check(std::isfinite(options.fraction) && options.fraction >= 0.0 && options.fraction <= 1.0,
        "drift: fraction must be in [0, 1]");
  check(!std::isinf(options.direction_deg), "drift: direction_deg must be finite (or NaN: random)");
}

double drift_direction_rad(const DriftOptions& options, std::uint64_t seed) {
  if (!std::isnan(options.direction_deg)) return options.direction_deg * kPi / 180.0;
  std::mt19937_64 rng(seed);
  return 2.0 * kPi * unit_double(rng());
}

Pose3d drifted_pose(const Pose3d& T_W_B, double distance_m, double fraction,
                    double direction_rad) {
  Pose3d drifted = T_W_B;
  drifted.translation() += fraction * distance_m *
                           Eigen::Vector3d(std::cos(direction_rad), std::sin(direction_rad), 0.0);
  return drifted;
}

}  // namespace hazmap::sim
