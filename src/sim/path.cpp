#include "hazmap/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "hazmap/core/error.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kPiecesPerSegment = 64;

// Solves the tridiagonal system a_i x_{i-1} + b_i x_i + c_i x_{i+1} = d_i (Thomas).
std::vector<Eigen::Vector2d> solve_tridiagonal(std::vector<double> a, std::vector<double> b,
                                               std::vector<double> c,
                                               std::vector<Eigen::Vector2d> d) {
  const std::size_t n = b.size();
  for (std::size_t i = 1; i < n; ++i) {
    const double m = a[i] / b[i - 1];
    b[i] -= m * c[i - 1];
    d[i] -= m * d[i - 1];
  }
  std::vector<Eigen::Vector2d> x(n);
  x[n - 1] = d[n - 1] / b[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) x[i] = (d[i] - c[i] * x[i + 1]) / b[i];
  return x;
}

}  // namespace

void validate(const PathOptions& options) {
  check(options.kind == "straight" || options.kind == "spline",
        "path: unknown kind '" + options.kind + "' (straight | spline)");
  check(options.waypoint_spacing_m > 0.0 && std::isfinite(options.waypoint_spacing_m),
        "path: waypoint_spacing_m must be positive");
  check(options.max_turn_deg >= 0.0 && options.max_turn_deg <= 90.0,
        "path: max_turn_deg must be in [0, 90]");
}

std::vector<Eigen::Vector2d> random_waypoints(int count, double spacing_m, double max_turn_rad,
                                              std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector2d> points;
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;
  for (int i = 0; i < count; ++i) {
    points.push_back(p);
    p += spacing_m * Eigen::Vector2d(std::cos(heading_rad), std::sin(heading_rad));
    if (i >= 1) heading_rad += max_turn_rad * (2.0 * unit_double(rng()) - 1.0);
  }
  return points;
}

CubicSpline2d::CubicSpline2d(std::vector<Eigen::Vector2d> waypoints,
                             const Eigen::Vector2d& start_tangent)
    : points_(std::move(waypoints)) {
  check(points_.size() >= 2, "path: a spline needs at least two waypoints");
  // Unknowns: second derivatives M_i at the knots (unit knot spacing). Interior rows:
  // M_{i-1} + 4 M_i + M_{i+1} = 6 (P_{i+1} - 2 P_i + P_{i-1}). Clamped start:
  // 2 M_0 + M_1 = 6 (P_1 - P_0 - v0). Natural end: M_{n-1} = 0.
  const std::size_t n = points_.size();
  std::vector<double> a(n, 1.0), b(n, 4.0), c(n, 1.0);
  std::vector<Eigen::Vector2d> d(n, Eigen::Vector2d::Zero());
  a[0] = 0.0;
  b[0] = 2.0;
  c[0] = 1.0;
  d[0] = 6.0 * (points_[1] - points_[0] - start_tangent);
  for (std::size_t i = 1; i + 1 < n; ++i) d[i] = 6.0 * (points_[i + 1] - 2.0 * points_[i] + points_[i - 1]);
  a[n - 1] = 0.0;
  b[n - 1] = 1.0;
  c[n - 1] = 0.0;
  d[n - 1] = Eigen::Vector2d::Zero();
  second_ = solve_tridiagonal(a, b, c, d);
}

int CubicSpline2d::segment(double& t) const {
  t = std::clamp(t, 0.0, max_parameter());
  const int i = std::min(static_cast<int>(t), static_cast<int>(points_.size()) - 2);
  t -= i;
  return i;
}

// On a segment with local u in [0, 1]:
// S(u) = (1-u) P_i + u P_{i+1} + ((1-u)^3 - (1-u)) M_i / 6 + (u^3 - u) M_{i+1} / 6.
Eigen::Vector2d CubicSpline2d::position(double t) const {
  const int i = segment(t);
  const double u = t, w = 1.0 - u;
  return w * points_[i] + u * points_[i + 1] + (w * w * w - w) / 6.0 * second_[i] +
         (u * u * u - u) / 6.0 * second_[i + 1];
}

Eigen::Vector2d CubicSpline2d::derivative(double t) const {
  const int i = segment(t);
  const double u = t, w = 1.0 - u;
  return points_[i + 1] - points_[i] - (3.0 * w * w - 1.0) / 6.0 * second_[i] +
         (3.0 * u * u - 1.0) / 6.0 * second_[i + 1];
}

Eigen::Vector2d CubicSpline2d::second_derivative(double t) const {
  const int i = segment(t);
  return (1.0 - t) * second_[i] + t * second_[i + 1];
}

ArcLengthTable::ArcLengthTable(const CubicSpline2d& spline) {
  // 5-point Gauss-Legendre nodes and weights on [-1, 1].
  static const double kNodes[5] = {0.0, -0.5384693101056831, 0.5384693101056831,
                                   -0.9061798459386640, 0.9061798459386640};
  static const double kWeights[5] = {0.5688888888888889, 0.4786286704993665,
                                     0.4786286704993665, 0.2369268850561891,
                                     0.2369268850561891};
  const int pieces = static_cast<int>(spline.max_parameter()) * kPiecesPerSegment;
  const double dt = 1.0 / kPiecesPerSegment;
  t_.push_back(0.0);
  s_.push_back(0.0);
  for (int k = 0; k < pieces; ++k) {
    const double mid = (k + 0.5) * dt;
    double length = 0.0;
    for (int q = 0; q < 5; ++q)
      length += kWeights[q] * spline.derivative(mid + 0.5 * dt * kNodes[q]).norm();
    t_.push_back((k + 1) * dt);
    s_.push_back(s_.back() + 0.5 * dt * length);
  }
}

double ArcLengthTable::parameter_at(double s_m) const {
  s_m = std::clamp(s_m, 0.0, s_.back());
  const auto it = std::upper_bound(s_.begin(), s_.end(), s_m);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - s_.begin()), s_.size() - 1);
  const std::size_t j = k == 0 ? 0 : k - 1;
  const double span = s_[k] - s_[j];
  return span > 0.0 ? t_[j] + (t_[k] - t_[j]) * (s_m - s_[j]) / span : t_[j];
}

std::vector<PathPoint> plan_path(const PathOptions& options, int frames, double step_m,
                                 std::uint64_t seed) {
  validate(options);
  check(frames >= 1, "path: frames must be >= 1");
  check(step_m >= 0.0 && std::isfinite(step_m), "path: step_m must be >= 0");
  std::vector<PathPoint> path;
  if (options.kind == "straight") {
    for (int k = 0; k < frames; ++k) {
      PathPoint point;
      point.p_W = Eigen::Vector2d(k * step_m, 0.0);
      point.distance_m = k * step_m;
      path.push_back(point);
    }
    return path;
  }
  // Enough waypoints that the spline outlasts the path by two legs (the natural end
  // condition straightens the last leg).
  const double length_m = (frames - 1) * step_m;
  const int count = static_cast<int>(std::ceil(length_m / options.waypoint_spacing_m)) + 4;
  const CubicSpline2d spline(
      random_waypoints(count, options.waypoint_spacing_m, options.max_turn_deg * kPi / 180.0, seed),
      Eigen::Vector2d(options.waypoint_spacing_m, 0.0));
  const ArcLengthTable table(spline);
  for (int k = 0; k < frames; ++k) {
    const double t = table.parameter_at(k * step_m);
    const Eigen::Vector2d tangent = spline.derivative(t);
    PathPoint point;
    point.p_W = spline.position(t);
    point.yaw_rad = std::atan2(tangent.y(), tangent.x());
    point.distance_m = k * step_m;
    path.push_back(point);
  }
  return path;
}

}  // namespace hazmap::sim
