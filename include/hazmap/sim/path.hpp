#pragma once
// The rover's path in the horizontal plane of W: a straight line along +x, or a smooth
// (C2) cubic spline through seeded random waypoints, sampled every step_m of arc length.
// Heights and attitude come later, from the terrain under the wheels (rover_pose.hpp).
//
// Frame W (x forward at the start, y left), metres; yaw from +x towards +y, radians.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hazmap::sim {

struct PathOptions {
  std::string kind = "straight";  ///< straight | spline
  /// Spline: distance between successive waypoints, and the largest heading change
  /// between successive legs (uniform in [-max_turn_deg, max_turn_deg]).
  double waypoint_spacing_m = 1.0;
  double max_turn_deg = 30.0;
};

/// Throws Error naming the option if it is unusable (unknown kind, spacing <= 0,
/// max_turn_deg outside [0, 90]).
void validate(const PathOptions& options);

/// A point of the path: position, heading (direction of travel) and the arc length
/// travelled from the start.
struct PathPoint {
  Eigen::Vector2d p_W = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  double distance_m = 0.0;
};

/// Waypoints of a random walk: w0 = (0, 0), w1 = (spacing, 0) (the rover starts heading
/// along +x), then each leg turns by a uniform angle in [-max_turn, max_turn] from the
/// previous one and has length spacing_m. Deterministic in (arguments, seed).
std::vector<Eigen::Vector2d> random_waypoints(int count, double spacing_m, double max_turn_rad,
                                              std::uint64_t seed);

/// Interpolating cubic spline through waypoints w_i, parameter t in [0, n - 1] with w_i
/// at t = i, per coordinate: C2 everywhere, first derivative at t = 0 fixed to
/// start_tangent (per unit t), zero second derivative at the end (natural).
class CubicSpline2d {
 public:
  /// Throws Error with fewer than two waypoints.
  CubicSpline2d(std::vector<Eigen::Vector2d> waypoints, const Eigen::Vector2d& start_tangent);

  double max_parameter() const { return static_cast<double>(points_.size() - 1); }
  /// Position, first and second derivative with respect to t; t is clamped to the range.
  Eigen::Vector2d position(double t) const;
  Eigen::Vector2d derivative(double t) const;
  Eigen::Vector2d second_derivative(double t) const;

 private:
  int segment(double& t) const;  ///< clamps t, returns i with t - i in [0, 1]

  std::vector<Eigen::Vector2d> points_;
  std::vector<Eigen::Vector2d> second_;  ///< second derivatives at the knots
};

/// Arc-length parameterisation of a spline: the parameter t at which the arc length
/// from t = 0 reaches s. Arc length is integrated with 5-point Gauss-Legendre on 64
/// pieces per segment; within a piece t is interpolated linearly in s (the speed varies
/// by far less than 1e-3 across a piece), so positions are exact to ~1e-7 m.
class ArcLengthTable {
 public:
  explicit ArcLengthTable(const CubicSpline2d& spline);
  double length_m() const { return s_.back(); }
  /// Parameter at arc length s_m (clamped to [0, length_m()]).
  double parameter_at(double s_m) const;

 private:
  std::vector<double> t_;
  std::vector<double> s_;
};

/// The path points of `frames` frames, step_m of arc length apart, starting at the W
/// origin heading +x. Straight: p = (k step_m, 0), yaw 0, exactly. Spline: through
/// random_waypoints(seed); yaw is the direction of the spline's tangent.
/// Throws Error on invalid options.
std::vector<PathPoint> plan_path(const PathOptions& options, int frames, double step_m,
                                 std::uint64_t seed);

}  // namespace hazmap::sim
