// Rover paths: the spline interpolates its waypoints and is C2 with the requested start
// tangent; frames are 4 cm of arc apart (+-1 %); straight paths are exact; seeded.

#include "hazmap/sim/path.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kExactM = 1e-12;
constexpr double kContinuity = 1e-6;  // jump across a knot, evaluated 1e-9 either side

TEST(Path, WaypointsAreARandomWalkWithBoundedTurns) {
  const double max_turn_rad = 30.0 * kPi / 180.0;
  const auto w = random_waypoints(50, 1.0, max_turn_rad, 7);
  ASSERT_EQ(w.size(), 50u);
  EXPECT_EQ(w[0], Eigen::Vector2d(0, 0));
  EXPECT_EQ(w[1], Eigen::Vector2d(1, 0));
  for (std::size_t i = 1; i + 1 < w.size(); ++i) {
    const Eigen::Vector2d a = w[i] - w[i - 1];
    const Eigen::Vector2d b = w[i + 1] - w[i];
    EXPECT_NEAR(b.norm(), 1.0, kExactM);
    const double turn = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    EXPECT_LE(std::abs(turn), max_turn_rad + 1e-12);
  }
  EXPECT_EQ(random_waypoints(50, 1.0, max_turn_rad, 7), w);
  EXPECT_NE(random_waypoints(50, 1.0, max_turn_rad, 8), w);
}

TEST(Path, SplineInterpolatesAndIsTwiceContinuouslyDifferentiable) {
  const auto w = random_waypoints(12, 1.0, 40.0 * kPi / 180.0, 3);
  const CubicSpline2d spline(w, Eigen::Vector2d(1.0, 0.0));
  for (std::size_t i = 0; i < w.size(); ++i) {
    EXPECT_NEAR((spline.position(static_cast<double>(i)) - w[i]).norm(), 0.0, kExactM);
  }
  EXPECT_NEAR((spline.derivative(0.0) - Eigen::Vector2d(1.0, 0.0)).norm(), 0.0, kExactM);
  EXPECT_NEAR(spline.second_derivative(spline.max_parameter()).norm(), 0.0, kExactM);  // natural
  for (std::size_t i = 1; i + 1 < w.size(); ++i) {
    const double t = static_cast<double>(i);
    EXPECT_NEAR((spline.position(t - 1e-9) - spline.position(t + 1e-9)).norm(), 0.0, kContinuity);
    EXPECT_NEAR((spline.derivative(t - 1e-9) - spline.derivative(t + 1e-9)).norm(), 0.0, kContinuity);
    EXPECT_NEAR((spline.second_derivative(t - 1e-9) - spline.second_derivative(t + 1e-9)).norm(), 0.0,
                kContinuity);
  }
  // The derivative is the derivative of the position (central differences).
  for (double t : {0.3, 2.5, 7.77}) {
    const Eigen::Vector2d numeric = (spline.position(t + 1e-6) - spline.position(t - 1e-6)) / 2e-6;
    EXPECT_NEAR((numeric - spline.derivative(t)).norm(), 0.0, 1e-8);
  }
}

TEST(Path, ArcLengthOfAStraightSplineIsItsLength) {
  const CubicSpline2d line({{0, 0}, {1, 0}, {2, 0}, {3, 0}}, Eigen::Vector2d(1, 0));
  const ArcLengthTable table(line);
  EXPECT_NEAR(table.length_m(), 3.0, 1e-12);
  EXPECT_NEAR(table.parameter_at(1.7), 1.7, 1e-12);
}

TEST(Path, SplineFramesAreFourCentimetresApartAndTurnSmoothly) {
  PathOptions options;
  options.kind = "spline";
  const auto path = plan_path(options, 300, 0.04, 11);  // 12 m
  ASSERT_EQ(path.size(), 300u);
  EXPECT_EQ(path[0].p_W, Eigen::Vector2d(0, 0));
  EXPECT_NEAR(path[0].yaw_rad, 0.0, kExactM);
  double total_turn = 0.0;
  double previous_turn = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) {
    // Straight-line distance between frames: 4 cm +- 1 % (the chord of a 4 cm arc).
    const double step = (path[k].p_W - path[k - 1].p_W).norm();
    EXPECT_NEAR(step, 0.04, 0.0004) << k;
    EXPECT_NEAR(path[k].distance_m, 0.04 * static_cast<double>(k), kExactM);
    // Heading follows the direction of travel and changes smoothly: less than 3 deg per
    // frame (curvature below 1.3 / m) and its rate changes little between frames.
    const Eigen::Vector2d chord = path[k].p_W - path[k - 1].p_W;
    const double turn = std::remainder(path[k].yaw_rad - path[k - 1].yaw_rad, 2 * kPi);
    const double mid_yaw = path[k - 1].yaw_rad + 0.5 * turn;
    // The chord points along the mean heading, up to the change of curvature x step^2
    // (here ~1e-4 rad).
    EXPECT_NEAR(std::remainder(std::atan2(chord.y(), chord.x()) - mid_yaw, 2 * kPi), 0.0, 1e-3);
    EXPECT_LT(std::abs(turn), 3.0 * kPi / 180.0) << k;
    if (k >= 2) {
      EXPECT_LT(std::abs(turn - previous_turn), 0.2 * kPi / 180.0) << k;
    }
    previous_turn = turn;
    total_turn += std::abs(turn);
  }
  EXPECT_GT(total_turn, 0.5);  // it does turn
  // Same seed, same path; other seed, other path.
  EXPECT_EQ(plan_path(options, 300, 0.04, 11).back().p_W, path.back().p_W);
  EXPECT_NE(plan_path(options, 300, 0.04, 12).back().p_W, path.back().p_W);
}

TEST(Path, StraightPathIsExact) {
  const auto path = plan_path(PathOptions(), 5, 0.04, 1);
  ASSERT_EQ(path.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(path[k].p_W, Eigen::Vector2d(k * 0.04, 0.0));
    EXPECT_EQ(path[k].yaw_rad, 0.0);
  }
}

TEST(Path, InvalidOptionsThrow) {
  PathOptions options;
  options.kind = "zigzag";
  EXPECT_THROW(plan_path(options, 3, 0.04, 1), Error);
  options = PathOptions();
  options.waypoint_spacing_m = 0.0;
  EXPECT_THROW(plan_path(options, 3, 0.04, 1), Error);
  EXPECT_THROW(CubicSpline2d({{0, 0}}, Eigen::Vector2d(1, 0)), Error);
}

}  // namespace
}  // namespace hazmap::sim
