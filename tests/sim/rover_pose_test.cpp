// Rover poses on the terrain: roll and pitch on a ramp equal the ramp angle (in the
// SPEC 2 sign convention), the body z axis is the ground normal, and drift is the
// requested fraction of the distance travelled.

#include "hazmap/sim/rover_pose.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kExact = 1e-12;

Terrain ramp(double degrees) {
  TerrainOptions options;
  options.scenario = "ramp";
  options.ramp_deg = degrees;
  return make_terrain(options);
}

PathPoint at(double x_m, double y_m, double yaw_deg) {
  PathPoint point;
  point.p_W = Eigen::Vector2d(x_m, y_m);
  point.yaw_rad = yaw_deg * kPi / 180.0;
  return point;
}

TEST(RoverPose, ClimbingARampPitchesByTheRampAngle) {
  const double angle = 15.0 * kPi / 180.0;
  const Terrain terrain = ramp(15.0);
  const WheelPlane plane = wheel_plane(terrain, Eigen::Vector2d(1.0, 0.2), 0.0, WheelGeometry());
  EXPECT_NEAR(plane.pitch_rad, -angle, kExact);  // nose up is negative pitch
  EXPECT_NEAR(plane.roll_rad, 0.0, kExact);
  EXPECT_NEAR(plane.height_m, std::tan(angle), kExact);

  const Pose3d T_W_B = pose_on_ground(terrain, at(1.0, 0.2, 0.0), WheelGeometry());
  EXPECT_TRUE(T_W_B.linear().col(2).isApprox(terrain.ground_normal_W(1.0, 0.2), kExact));
  EXPECT_TRUE(T_W_B.translation().isApprox(Eigen::Vector3d(1.0, 0.2, std::tan(angle)), kExact));
}

TEST(RoverPose, DrivingAcrossARampRollsByTheRampAngle) {
  const double angle = 12.0 * kPi / 180.0;
  const Terrain terrain = ramp(12.0);
  // Heading +y on a ramp rising along +x: the left side (-x) is low, so roll is negative.
  const WheelPlane plane = wheel_plane(terrain, Eigen::Vector2d(0.5, 0.0), kPi / 2, WheelGeometry());
  EXPECT_NEAR(plane.roll_rad, -angle, kExact);
  EXPECT_NEAR(plane.pitch_rad, 0.0, kExact);
  // Heading -y: the left side is high.
  EXPECT_NEAR(wheel_plane(terrain, Eigen::Vector2d(0.5, 0.0), -kPi / 2, WheelGeometry()).roll_rad,
              angle, kExact);
}

TEST(RoverPose, AnyHeadingStandsOnTheGroundPlane) {
  const Terrain terrain = ramp(18.0);
  for (double yaw_deg : {0.0, 30.0, 100.0, -135.0}) {
    const Pose3d T_W_B = pose_on_ground(terrain, at(2.0, -1.0, yaw_deg), WheelGeometry{0.4, 0.3});
    // z_B is the ground normal; x_B is level with the heading in the horizontal plane.
    EXPECT_TRUE(T_W_B.linear().col(2).isApprox(terrain.ground_normal_W(2.0, -1.0), kExact));
    const Eigen::Vector3d x_B = T_W_B.linear().col(0);
    EXPECT_NEAR(std::atan2(x_B.y(), x_B.x()), yaw_deg * kPi / 180.0, kExact);
    // Every wheel contact lies on the ground (a plane fits a ramp exactly).
    for (double sx : {-0.2, 0.2}) {
      for (double sy : {-0.15, 0.15}) {
        const Eigen::Vector3d wheel_W = T_W_B * Eigen::Vector3d(sx, sy, 0.0);
        EXPECT_NEAR(wheel_W.z(), terrain.ground_height_m(wheel_W.x(), wheel_W.y()), kExact);
      }
    }
  }
}

TEST(RoverPose, FlatGroundIsLevel) {
  TerrainOptions options;
  options.scenario = "flat";
  const Terrain terrain = make_terrain(options);
  const Pose3d T_W_B = pose_on_ground(terrain, at(1.0, 2.0, 45.0), WheelGeometry());
  EXPECT_TRUE(T_W_B.linear().isApprox(rotation_from_rpy(0, 0, kPi / 4), kExact));
  EXPECT_EQ(T_W_B.translation().z(), 0.0);
}

TEST(RoverPose, WheelPlaneAveragesASineUnderTheWheels) {
  TerrainOptions options;
  options.scenario = "sine";
  const Terrain terrain = make_terrain(options);
  // Wheels at x = +-0.15 on z = A sin(2 pi x): front and rear at the same height -> no
  // pitch at x = 0.25 (crest between them), height = A sin(2 pi 0.4) = A cos(2 pi 0.15).
  const WheelPlane plane = wheel_plane(terrain, Eigen::Vector2d(0.25, 0.0), 0.0, WheelGeometry());
  EXPECT_NEAR(plane.pitch_rad, 0.0, kExact);
  EXPECT_NEAR(plane.height_m, 0.05 * std::cos(2 * kPi * 0.15), kExact);
  // At x = 0 the slope between the wheels is (A sin(0.3 pi) - A sin(-0.3 pi)) / 0.3.
  const WheelPlane rising = wheel_plane(terrain, Eigen::Vector2d(0.0, 0.0), 0.0, WheelGeometry());
  EXPECT_NEAR(rising.pitch_rad, -std::atan(2 * 0.05 * std::sin(0.3 * kPi) / 0.3), kExact);
}

TEST(RoverPose, DriftIsTheFractionOfDistanceAlongItsDirection) {
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = rotation_from_rpy(0.1, -0.05, 1.0);
  T_W_B.translation() = Eigen::Vector3d(3.0, -1.0, 0.2);
  const double direction = 40.0 * kPi / 180.0;
  const Pose3d drifted = drifted_pose(T_W_B, 2.5, 0.1, direction);
  const Eigen::Vector3d error = drifted.translation() - T_W_B.translation();
  EXPECT_NEAR(error.norm(), 0.25, kExact);
  EXPECT_NEAR(std::atan2(error.y(), error.x()), direction, kExact);
  EXPECT_EQ(error.z(), 0.0);
  EXPECT_TRUE(drifted.linear().isApprox(T_W_B.linear(), 0.0));

  DriftOptions options;
  options.direction_deg = 40.0;
  EXPECT_NEAR(drift_direction_rad(options, 1), direction, kExact);
  options.direction_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(drift_direction_rad(options, 5), drift_direction_rad(options, 5));
  EXPECT_NE(drift_direction_rad(options, 5), drift_direction_rad(options, 6));
  options.fraction = -0.1;
  EXPECT_THROW(validate(options), Error);
}

}  // namespace
}  // namespace hazmap::sim
