#include "bench_points.hpp"

#include <cmath>

namespace hazmap::bench {

void scanline_ground_points(PointCloud& cloud, int width, int height, double x0_m,
                            double max_range_m) {
  cloud.clear();
  const double f = 671.0 * width / 1600.0, cx = (width - 1) / 2.0, cy = (height - 1) / 2.0;
  const double cam_h = 0.15, pitch = 34.0 * M_PI / 180.0, baseline = 0.05, m_px = 0.25, p_px = 0.5;
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      // Ray in camera (x right, y down, z forward) -> body (x fwd, y left, z up), pitched.
      const double rx = (u - cx) / f, ry = (v - cy) / f;
      const double fwd = cp * 1.0 - sp * ry, down = sp * 1.0 + cp * ry, left = -rx;
      if (down <= 1e-6) continue;
      const double t = cam_h / down;
      const double gx = t * fwd, gy = t * left;
      if (std::hypot(gx, gy) > max_range_m) continue;
      const double z_cam = t;  // depth along the optical axis (ray has unit z component)
      Measurement m{};
      const double bump = 0.01 * std::sin(7 * (x0_m + gx)) * std::cos(5 * gy);
      m.p_W = Eigen::Vector3f(float(x0_m + gx), float(gy), float(bump));
      const double lat = p_px * z_cam / f, dep = z_cam * z_cam * m_px / (f * baseline);
      m.cov_xx = float(dep * dep * 0.6 + lat * lat);
      m.cov_yy = float(lat * lat);
      m.cov_zz = float(dep * dep * 0.4 + lat * lat);
      m.cov_xz = float(dep * dep * 0.45);
      cloud.push_back(m);
    }
}

}  // namespace hazmap::bench
