#include "hazmap/hazard/sensor_view.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace hazmap {
namespace {

/// The view's transforms, computed once per frame.
struct Projector {
  const SensorView& view;
  Pose3d T_C_W;
  Eigen::Vector3d normal, origin;  ///< the wheel plane in W

  explicit Projector(const SensorView& v)
      : view(v),
        T_C_W((v.T_W_B * v.T_B_C).inverse()),
        normal(v.T_W_B.linear().col(2)),
        origin(v.T_W_B.translation()) {}

  /// The W height where the vertical line through (x, y) meets the plane `h` above the
  /// wheel plane (along its normal).
  double height_at(double x, double y, double h) const {
    return origin.z() + (h - normal.x() * (x - origin.x()) - normal.y() * (y - origin.y())) / normal.z();
  }

  /// The column over (x, y) between the body band's heights.
  bool sees(double x, double y) const {
    // A body on its side or upside down: no plane to hang the band from; erring wide.
    if (normal.z() < 0.1) return true;
    return sees(x, y, height_at(x, y, -view.band_below_m), height_at(x, y, view.band_above_m));
  }

  /// The column over (x, y) between W heights z_lo and z_hi.
  bool sees(double x, double y, double z_lo_W, double z_hi_W) const {
    const Eigen::Vector3d a = T_C_W * Eigen::Vector3d(x, y, z_lo_W);
    const Eigen::Vector3d b = T_C_W * Eigen::Vector3d(x, y, z_hi_W);
    const Eigen::Vector3d d = b - a;
    // Clip t in [0, 1] to the depth range.
    double t0 = 0.0, t1 = 1.0;
    const double z_lo = std::max(view.z_min_m, 1e-3);
    if (!clip(a.z() - z_lo, d.z(), t0, t1) || !clip(view.z_max_m - a.z(), -d.z(), t0, t1)) return false;
    const Eigen::Vector3d p = a + t0 * d, q = a + t1 * d;
    const double f = view.focal_px;
    const double pu = view.cx_px + f * p.x() / p.z(), pv = view.cy_px + f * p.y() / p.z();
    const double qu = view.cx_px + f * q.x() / q.z(), qv = view.cy_px + f * q.y() / q.z();
    const double m = view.edge_margin_px;
    const double u0 = std::max(m, view.blank_left_px) - 0.5, u1 = view.width_px - 0.5 - m;
    const double v0 = m - 0.5, v1 = view.height_px - 0.5 - m;
    // Liang-Barsky: does the image segment p -> q meet the rectangle?
    double s0 = 0.0, s1 = 1.0;
    const double du = qu - pu, dv = qv - pv;
    return clip(pu - u0, du, s0, s1) && clip(u1 - pu, -du, s0, s1) && clip(pv - v0, dv, s0, s1) &&
           clip(v1 - pv, -dv, s0, s1);
  }

  /// Keeps the part of [t0, t1] where c + k t >= 0; false when nothing is left.
  static bool clip(double c, double k, double& t0, double& t1) {
    if (k == 0.0) return c >= 0.0;
    const double t = -c / k;
    if (k > 0.0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
    return t0 <= t1;
  }
};

}  // namespace

bool SensorView::sees_column(double x_m, double y_m) const {
  return Projector(*this).sees(x_m, y_m);
}

bool TerrainBand::at(double x_m, double y_m, double* lo, double* hi) const {
  for (const Source& s : sources_) {
    int row = 0, col = 0;
    if (!s.height->cell_at(x_m, y_m, &row, &col)) continue;
    const float z = s.height->at(row, col), var = s.variance->at(row, col);
    if (std::isnan(z) || !std::isfinite(var)) continue;
    const double m = s.k_sigma * std::sqrt(std::max(double(var), 0.0)) + s.spread_m;
    *lo = z - m;
    *hi = z + m;
    return true;
  }
  return false;
}

GridRect mark_viewed(const SensorView& view, DenseGrid& viewed, const TerrainBand* terrain) {
  const Projector projector(view);
  const double h = 0.5 * viewed.resolution_m;
  GridRect changed;
  for (int row = 0; row < viewed.rows; ++row) {
    const double y = viewed.y_of_row(row);
    int first = -1, last = -1;
    for (int col = 0; col < viewed.cols; ++col) {
      float& cell = viewed.at(row, col);
      if (cell >= kWhollyViewed) continue;
      const double x = viewed.x_of_col(col);
      double lo = 0, hi = 0;
      const bool known = terrain && terrain->at(x, y, &lo, &hi);
      // The cell's centre and corners (the view is convex): all seen, wholly; some, partly.
      int seen = 0;
      for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, {-h, -h}, {h, -h}, {-h, h}, {h, h}})
        seen += known ? projector.sees(x + dx, y + dy, lo, hi) : projector.sees(x + dx, y + dy);
      const float now = seen == 5 ? kWhollyViewed : seen > 0 ? kPartlyViewed : 0.0f;
      if (now <= cell) continue;
      cell = now;
      if (first < 0) first = col;
      last = col;
    }
    if (first >= 0) changed = changed.hull({row, row + 1, first, last + 1});
  }
  return changed;
}

}  // namespace hazmap
