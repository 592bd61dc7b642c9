#include "hazmap/hazard/sensor_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace hazmap {
namespace {

/// The view as seven half-spaces in W, computed once per frame: a point p is seen when
/// a_i . p + b_i >= 0 for all i (depth z_min .. z_max, the matchable image's four
/// edges; for depth > 0, u >= u0 is f X + (cx - u0) Z >= 0, and likewise; and the right
/// image's left edge, u - f B / Z >= m: f X + (cx - m) Z - f B >= 0). A vertical segment
/// is clipped against them (Liang-Barsky), which projecting it would equal.
struct Projector {
  const SensorView& view;
  Eigen::Vector3d normal, origin;  ///< the wheel plane in W
  static constexpr int kMaxPlanes = 7;
  Eigen::Vector3d a[kMaxPlanes];
  double b[kMaxPlanes];
  int planes;  ///< 6, or 7 with the right image's edge (SensorView::right_edge_margin_px)
  double x_min, x_max, y_min, y_max;  ///< W bounds of the frustum: nothing seen outside

  explicit Projector(const SensorView& v)
      : view(v), normal(v.T_W_B.linear().col(2)), origin(v.T_W_B.translation()) {
    const Pose3d T_C_W = (v.T_W_B * v.T_B_C).inverse();
    const double f = v.focal_px, m = v.edge_margin_px;
    const double u0 = std::max(m, v.blank_left_px) - 0.5, u1 = v.width_px - 0.5 - m;
    const double v0 = m - 0.5, v1 = v.height_px - 0.5 - m;
    // Camera-frame planes n . p_C + c >= 0.
    // The right image's left edge, where the view checks it.
    const double ur0 = v.right_edge_margin_px - 0.5;
    planes = v.right_edge_margin_px > 0 && v.baseline_m > 0 ? 7 : 6;
    const Eigen::Vector3d n[kMaxPlanes] = {{0, 0, 1},
                                           {0, 0, -1},
                                           {f, 0, v.cx_px - u0},
                                           {-f, 0, u1 - v.cx_px},
                                           {0, f, v.cy_px - v0},
                                           {0, -f, v1 - v.cy_px},
                                           {f, 0, v.cx_px - ur0}};
    const double c[kMaxPlanes] = {-std::max(v.z_min_m, 1e-3), v.z_max_m, 0, 0, 0, 0,
                                  -f * v.baseline_m};
    for (int i = 0; i < planes; ++i) {  // n . (R p_W + t) + c
      a[i] = T_C_W.linear().transpose() * n[i];
      b[i] = n[i].dot(T_C_W.translation()) + c[i];
    }
    // The frustum is the hull of its eight corners.
    const Pose3d T_W_C = T_C_W.inverse();
    x_min = y_min = std::numeric_limits<double>::infinity();
    x_max = y_max = -x_min;
    for (const double z : {std::max(v.z_min_m, 1e-3), v.z_max_m})
      for (const double u : {u0, u1})
        for (const double w : {v0, v1}) {
          const Eigen::Vector3d p = T_W_C * Eigen::Vector3d((u - v.cx_px) * z / f, (w - v.cy_px) * z / f, z);
          x_min = std::min(x_min, p.x());
          x_max = std::max(x_max, p.x());
          y_min = std::min(y_min, p.y());
          y_max = std::max(y_max, p.y());
        }
  }

  /// False where no column can be seen.
  bool may_see(double x, double y) const { return x >= x_min && x <= x_max && y >= y_min && y <= y_max; }

  /// The W height where the vertical line through (x, y) meets the plane `h` above the
  /// wheel plane (along its normal).
  double height_at(double x, double y, double h) const {
    return origin.z() + (h - normal.x() * (x - origin.x()) - normal.y() * (y - origin.y())) / normal.z();
  }

  /// The column over (x, y) between the body band's heights.
  bool sees(double x, double y) const {
    if (!may_see(x, y)) return false;
    // A body on its side or upside down: no plane to hang the band from; erring wide.
    if (normal.z() < 0.1) return true;
    return sees(x, y, height_at(x, y, -view.band_below_m), height_at(x, y, view.band_above_m));
  }

  /// The column over (x, y) between W heights z_lo and z_hi; callers reject (x, y)
  /// outside the frustum's bounds first (may_see).
  bool sees(double x, double y, double z_lo, double z_hi) const {
    double t0 = 0.0, t1 = 1.0;
    const double dz = z_hi - z_lo;
    for (int i = 0; i < planes; ++i)
      if (!clip(a[i].x() * x + a[i].y() * y + a[i].z() * z_lo + b[i], a[i].z() * dz, t0, t1))
        return false;
    return true;
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

GridRect ViewMarker::mark(const SensorView& view, DenseGrid& viewed, const TerrainBand* terrain) {
  const Projector projector(view);
  const double h = 0.5 * viewed.resolution_m;
  const auto sees = [&](double x, double y) {
    if (!projector.may_see(x, y)) return false;
    double lo = 0, hi = 0;
    return terrain && terrain->at(x, y, &lo, &hi) ? projector.sees(x, y, lo, hi) : projector.sees(x, y);
  };
  // Corners are shared by up to four cells: two rows of them, tested on first use.
  constexpr std::uint8_t kUntested = 2;
  const std::size_t corners = static_cast<std::size_t>(viewed.cols) + 1;
  if (top_.size() < corners) {  // the first frame of the largest layer only
    top_.resize(corners);
    bottom_.resize(corners);
  }
  std::fill(top_.begin(), top_.begin() + corners, kUntested);
  const auto corner = [&](std::vector<std::uint8_t>& line, int k, double y) {
    if (line[k] == kUntested) line[k] = sees(viewed.x_of_col(0) - h + k * viewed.resolution_m, y);
    return line[k];
  };
  GridRect changed;
  for (int row = 0; row < viewed.rows; ++row) {
    const double y = viewed.y_of_row(row);
    std::fill(bottom_.begin(), bottom_.begin() + corners, kUntested);
    int first = -1, last = -1;
    for (int col = 0; col < viewed.cols; ++col) {
      float& cell = viewed.at(row, col);
      if (cell >= kWhollyViewed) continue;
      // The cell's centre and corners (the view is convex): all seen, wholly; some, partly.
      const int seen = sees(viewed.x_of_col(col), y) + corner(top_, col, y + h) +
                       corner(top_, col + 1, y + h) + corner(bottom_, col, y - h) +
                       corner(bottom_, col + 1, y - h);
      const float now = seen == 5 ? kWhollyViewed : seen > 0 ? kPartlyViewed : 0.0f;
      if (now <= cell) continue;
      cell = now;
      if (first < 0) first = col;
      last = col;
    }
    if (first >= 0) changed = changed.hull({row, row + 1, first, last + 1});
    std::swap(top_, bottom_);  // this row's lower corners are the next row's upper ones
  }
  return changed;
}

}  // namespace hazmap
