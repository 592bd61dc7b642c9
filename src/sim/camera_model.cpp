#include "hazmap/sim/camera_model.hpp"

#include <Eigen/Dense>

namespace hazmap::sim {

Eigen::Vector2d PinholeCamera::distort(const Eigen::Vector2d& xy) const {
  const auto& [k1, k2, p1, p2, k3] = distortion;
  const double x = xy.x();
  const double y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return Eigen::Vector2d(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                         y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
}

Eigen::Vector2d PinholeCamera::undistort(const Eigen::Vector2d& xy_d) const {
  const auto& [k1, k2, p1, p2, k3] = distortion;
  // Newton on f(xy) = distort(xy) - xy_d from xy = xy_d; the model is a small perturbation
  // of the identity, so a handful of iterations reach rounding level.
  constexpr int kMaxIterations = 20;
  constexpr double kTolerance = 1e-15;
  Eigen::Vector2d xy = xy_d;
  for (int i = 0; i < kMaxIterations; ++i) {
    const double x = xy.x();
    const double y = xy.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dradial_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
    const Eigen::Vector2d residual = distort(xy) - xy_d;
    if (residual.cwiseAbs().maxCoeff() < kTolerance) break;
    Eigen::Matrix2d J;
    J(0, 0) = radial + 2.0 * x * x * dradial_dr2 + 2.0 * p1 * y + 6.0 * p2 * x;
    J(0, 1) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
    J(1, 0) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
    J(1, 1) = radial + 2.0 * y * y * dradial_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
    xy -= J.inverse() * residual;
  }
  return xy;
}

}  // namespace hazmap::sim
