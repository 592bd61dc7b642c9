#pragma once
// Points on analytic ground for the hazard tests that map them with a real layer stack:
// every 3 mm over [-0.6, 0.6)^2 m, jittered by up to half a step, with 0.5 mm height noise,
// where `visible` says the ground was seen.

#include <functional>
#include <random>

#include "hazmap/map/map_points.hpp"

namespace hazmap::testing {

using Surface = std::function<double(double, double)>;
using Visible = std::function<bool(double, double)>;

inline PointCloud analytic_points(const Surface& h, const Visible& visible, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  PointCloud cloud;
  for (double y = -0.6; y < 0.6; y += 0.003)
    for (double x = -0.6; x < 0.6; x += 0.003) {
      const double px = x + jitter(rng) * 0.003, py = y + jitter(rng) * 0.003;
      if (!visible(px, py)) continue;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(px), float(py), float(h(px, py) + noise(rng)));
      m.cov_xx = m.cov_yy = 1e-6f;
      m.cov_zz = float(0.0005 * 0.0005);
      cloud.push_back(m);
    }
  return cloud;
}

}  // namespace hazmap::testing
