#pragma once
// Body poses of the simulated rover: the true pose T_W_B standing on the terrain (height,
// roll and pitch from the ground under its four wheels), and a drifted copy whose
// position error grows as a fraction of the distance travelled, as odometry drifts.
//
// Frames (SPEC 1): W world, z up; B body, x forward, y left, z up, origin on the ground
// between the wheels. R_W_B = Rz(yaw) Ry(pitch) Rx(roll) (SPEC 2): positive pitch is
// nose down, positive roll lifts the left side.

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "hazmap/core/types.hpp"
#include "hazmap/sim/path.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {

/// Wheel contact points at body (+-wheelbase/2, +-track/2) (front/rear, left/right).
struct WheelGeometry {
  double wheelbase_m = 0.30;
  double track_m = 0.25;
};

/// Roll, pitch and body height of a plane fitted to the ground under the wheels.
struct WheelPlane {
  double height_m = 0.0;  ///< plane height at the body origin
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
};

/// Least-squares plane z = a + b x' + c y' through the ground heights at the four wheel
/// contacts, in the yaw-aligned frame (x' forward, y' left) centred on p_W. For the
/// rectangle of contacts this is a = mean height, b = (front - rear) / wheelbase,
/// c = (left - right) / track (pairs averaged). The body then stands on the plane:
/// z_B is its normal and x_B points along the heading, i.e. pitch = -atan(b),
/// roll = atan(c cos(pitch)), height = a.
/// Rocks are ignored: the rover drives through them as if they were not there (a path
/// may keep clear of them, TerrainOptions::keep_clear_m). Throws Error on a
/// non-positive wheelbase or track.
WheelPlane wheel_plane(const Terrain& terrain, const Eigen::Vector2d& p_W, double yaw_rad,
                       const WheelGeometry& wheels);

/// T_W_B of a rover at path point `point` standing on the wheel plane.
Pose3d pose_on_ground(const Terrain& terrain, const PathPoint& point, const WheelGeometry& wheels);

/// Odometry-like drift: the reported position is off by fraction * distance travelled,
/// horizontally along a fixed direction (seeded unless given). Attitude is not drifted.
struct DriftOptions {
  double fraction = 0.0;  ///< 0: no drift; 0.1 = 10 cm per metre travelled
  /// Direction of the error in W from +x towards +y, degrees; NaN: drawn from the seed.
  double direction_deg = std::numeric_limits<double>::quiet_NaN();
};

/// Throws Error naming the option if fraction is negative or not finite, or the
/// direction is infinite.
void validate(const DriftOptions& options);

/// The direction of the error, radians: options.direction_deg, or uniform in [0, 2 pi)
/// from the seed.
double drift_direction_rad(const DriftOptions& options, std::uint64_t seed);

/// Drifted copy of T_W_B: translation + fraction * distance_m * (cos a, sin a, 0), same
/// rotation.
Pose3d drifted_pose(const Pose3d& T_W_B, double distance_m, double fraction, double direction_rad);

}  // namespace hazmap::sim
