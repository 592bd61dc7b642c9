#include "hazmap/hazard/hole_marker.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace hazmap {
namespace {

/// The frame's camera, computed once per mark(): W -> rectified left camera, and the
/// pixels that give points.
struct Camera {
  const SensorView& view;
  Pose3d T_C_W;
  Eigen::Matrix3d R_W_C;
  Eigen::Vector3d origin_W;
  double u_lo, u_hi, v_lo, v_hi;  ///< the pixel centres that may give points, inclusive
  double fb;
  double ur_lo;  ///< the right image's first column a match may fall on
  double z_far;  ///< z_max, or nearer: the layer's lateral gate

  Camera(const SensorView& v, double max_depth_m) : view(v), z_far(std::min(v.z_max_m, max_depth_m)) {
    const Pose3d T_W_C = v.T_W_B * v.T_B_C;
    T_C_W = T_W_C.inverse();
    R_W_C = T_W_C.linear();
    origin_W = T_W_C.translation();
    const double m = v.edge_margin_px;
    u_lo = std::max({double(v.roi_x0), m, v.blank_left_px});
    u_hi = std::min(double(v.roi_x1 - 1), v.width_px - 1 - m);
    v_lo = std::max(double(v.roi_y0), m);
    v_hi = std::min(double(v.roi_y1 - 1), v.height_px - 1 - m);
    fb = v.focal_px * v.baseline_m;
    ur_lo = v.right_edge_margin_px > 0 ? v.right_edge_margin_px : -1e300;
  }

  /// Projects W point p; false outside the depth range or the pixels that give points,
  /// or where its match falls off the right image (within its margin): the pair cannot
  /// have matched it, so a missing disparity there is no hole.
  bool project(const Eigen::Vector3d& p, double* u, double* w) const {
    const Eigen::Vector3d c = T_C_W * p;
    if (!(c.z() >= view.z_min_m && c.z() <= z_far)) return false;
    *u = view.cx_px + view.focal_px * c.x() / c.z();
    *w = view.cy_px + view.focal_px * c.y() / c.z();
    return *u >= u_lo - 0.5 && *u <= u_hi + 0.5 && *w >= v_lo - 0.5 && *w <= v_hi + 0.5 &&
           *u - fb / c.z() >= ur_lo - 0.5;
  }

  float test(double x0, double x1, double y0, double y1, double z, double tol) const {
    double u_min = 1e300, u_max = -1e300, w_min = 1e300, w_max = -1e300;
    for (const double x : {x0, x1})
      for (const double y : {y0, y1}) {
        double u = 0, w = 0;
        if (!project({x, y, z}, &u, &w)) return 0.0f;  // not wholly in view at this frame
        u_min = std::min(u_min, u), u_max = std::max(u_max, u);
        w_min = std::min(w_min, w), w_max = std::max(w_max, w);
      }
    // Pixels of the stride grid whose centre may fall inside the projected cell.
    const int s = std::max(view.stride, 1);
    auto first_on_grid = [s](double lo, int origin) {
      const int k = static_cast<int>(std::ceil(lo));
      return origin + ((k - origin + s - 1) / s) * s;  // k >= origin: roi bounds the view
    };
    const int ua = first_on_grid(std::max(u_min, u_lo), view.roi_x0);
    const int wa = first_on_grid(std::max(w_min, v_lo), view.roi_y0);
    const int ub = static_cast<int>(std::floor(std::min(u_max, u_hi)));
    const int wb = static_cast<int>(std::floor(std::min(w_max, v_hi)));
    // Per quarter of the cell: pixels that saw its ground, that had no disparity, and
    // that read something else (nearer: hidden; farther: not this plane).
    int seen[4] = {0, 0, 0, 0}, missing[4] = {0, 0, 0, 0}, other[4] = {0, 0, 0, 0};
    const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
    // The pixel's ray in W, scaled to unit camera depth, moves by this per step in u.
    const Eigen::Vector3d ray_step = R_W_C.col(0) * (s / view.focal_px);
    for (int w = wa; w <= wb; w += s) {
      const std::int16_t* row = view.disparity_x16 + static_cast<std::ptrdiff_t>(w) * view.disparity_stride;
      Eigen::Vector3d ray =
          R_W_C * Eigen::Vector3d((ua - view.cx_px) / view.focal_px, (w - view.cy_px) / view.focal_px, 1.0);
      for (int u = ua; u <= ub; u += s, ray += ray_step) {
        // Where the pixel's ray meets the plane z.
        if (!(std::abs(ray.z()) > 1e-12)) continue;
        const double depth = (z - origin_W.z()) / ray.z();
        if (!(depth > 0)) continue;
        const double px = origin_W.x() + depth * ray.x(), py = origin_W.y() + depth * ray.y();
        if (px < x0 || px >= x1 || py < y0 || py >= y1) continue;  // another cell's pixel
        const int q = (px >= xm) + 2 * (py >= ym);
        const int d16 = row[u];
        if (d16 <= view.invalid_below_x16 || d16 <= 0) {
          ++missing[q];
          continue;
        }
        const double d = d16 / 16.0, expected = fb / depth;
        ++(std::abs(d - expected) <= tol ? seen[q] : other[q]);
      }
    }
    // A quarter that every pixel over it failed to match is a hole; the cell is seen whole
    // when each quarter has a pixel that saw its ground and none that saw something else
    // (a few pixels without a match are the matcher's noise, not a hole).
    int quarters_seen = 0;
    for (int q = 0; q < 4; ++q) {
      if (seen[q] == 0 && other[q] == 0 && missing[q] > 0) return kHoleSeen;
      quarters_seen += seen[q] > 0 && other[q] == 0;
    }
    return quarters_seen == 4 ? kSeenWhole : 0.0f;
  }
};

}  // namespace

float HoleMarker::test_cell(const SensorView& view, double x0, double x1, double y0, double y1,
                            double z, double tolerance_px, double max_depth_m) {
  if (view.disparity_x16 == nullptr) return 0.0f;
  return Camera(view, max_depth_m).test(x0, x1, y0, y1, z, tolerance_px);
}

GridRect HoleMarker::mark(const SensorView& view, const LayerGrids& map, double tolerance_px,
                          DenseGrid& marks, double max_depth_m, const ParallelFor* pool) {
  if (view.disparity_x16 == nullptr || map.coverage.rows == 0) return {};
  const Camera camera(view, max_depth_m);
  const DenseGrid& g = map.height;
  const double h = 0.5 * g.resolution_m;
  // Bands of rows, each cell's mark its own: each band's changed cells in its own hull.
  constexpr int kMaxBands = 16, kRowsPerBand = 4;
  std::array<GridRect, kMaxBands> changed{};
  const int bands =
      std::clamp(std::min(g.rows / kRowsPerBand, pool ? 2 * pool->threads() : 1), 1, kMaxBands);
  parallel_for(pool, bands, [&](int begin, int end) {
    for (int b = begin; b < end; ++b) {
      const EvenPart part = even_part(g.rows, bands, b);
      for (int row = part.begin; row < part.end; ++row) {
        const double y = g.y_of_row(row);
        for (int col = 0; col < g.cols; ++col) {
          float& mark = marks.at(row, col);
          if (mark == kHoleSeen) continue;
          const float z = g.at(row, col);
          // Every known cell, also one not yet covered enough: a hole seen now still
          // counts when more points come. A cell the rule itself gives a plane needs its
          // mark only for when its coverage falls (older points discounted as it leaves
          // the view), and once it is seen whole it is not tested again (measured:
          // testing every such cell every frame was a third of the hazard stage).
          if (std::isnan(z) || (mark == kSeenWhole && map.evaluable.at(row, col) == 1.0f)) continue;
          const double x = g.x_of_col(col);
          const float now = camera.test(x - h, x + h, y - h, y + h, z, tolerance_px);
          if (now <= mark) continue;
          mark = now;
          changed[static_cast<std::size_t>(b)] =
              changed[static_cast<std::size_t>(b)].hull({row, row + 1, col, col + 1});
        }
      }
    }
  });
  GridRect all;
  for (int b = 0; b < bands; ++b) all = all.hull(changed[static_cast<std::size_t>(b)]);
  return all;
}

}  // namespace hazmap
