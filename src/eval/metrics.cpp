#include "hazmap/eval/metrics.hpp"

#include <algorithm>
#include <cmath>

#include "hazmap/core/error.hpp"
#include "hazmap/eval/grid_checks.hpp"

namespace hazmap::eval {

MetricSums& MetricSums::operator+=(const MetricSums& o) {
  extent_px += o.extent_px;
  known_px += o.known_px;
  height_px += o.height_px;
  sq_error_sum_m2 += o.sq_error_sum_m2;
  gt_hazard_px += o.gt_hazard_px;
  gt_hazard_known_px += o.gt_hazard_known_px;
  gt_hazard_found_px += o.gt_hazard_found_px;
  missed_px += o.missed_px;
  false_alarm_px += o.false_alarm_px;
  variance_px += o.variance_px;
  violation_px += o.violation_px;
  height_all_px += o.height_all_px;
  sq_error_all_sum_m2 += o.sq_error_all_sum_m2;
  variance_all_px += o.variance_all_px;
  violation_all_px += o.violation_all_px;
  if (pixel_area_m2 == 0.0) pixel_area_m2 = o.pixel_area_m2;
  height_cells += o.height_cells;
  max_below_m = std::max(max_below_m, o.max_below_m);
  return *this;
}

LayerMetrics derive_metrics(const MetricSums& s) {
  LayerMetrics m;
  const double a = s.pixel_area_m2;
  const auto ratio = [](std::size_t num, std::size_t den) {
    return den == 0 ? kNaN : static_cast<double>(num) / static_cast<double>(den);
  };
  m.extent_area_m2 = static_cast<double>(s.extent_px) * a;
  m.known_area_m2 = static_cast<double>(s.known_px) * a;
  m.unknown_fraction = s.extent_px == 0 ? kNaN : 1.0 - ratio(s.known_px, s.extent_px);
  m.height_samples = s.height_px;
  m.height_rms_m =
      s.height_px == 0 ? kNaN : std::sqrt(s.sq_error_sum_m2 / static_cast<double>(s.height_px));
  m.gt_hazard_area_m2 = static_cast<double>(s.gt_hazard_px) * a;
  m.gt_hazard_known_area_m2 = static_cast<double>(s.gt_hazard_known_px) * a;
  m.missed_area_m2 = static_cast<double>(s.missed_px) * a;
  m.missed_fraction = ratio(s.missed_px, s.known_px);
  m.missed_of_hazard = ratio(s.missed_px, s.gt_hazard_known_px);
  m.false_alarm_area_m2 = static_cast<double>(s.false_alarm_px) * a;
  m.false_alarm_fraction = ratio(s.false_alarm_px, s.known_px);
  m.variance_violation = ratio(s.violation_px, s.variance_px);
  m.hazard_recall = ratio(s.gt_hazard_found_px, s.gt_hazard_px);
  m.hazard_unknown = ratio(s.gt_hazard_px - s.gt_hazard_known_px, s.gt_hazard_px);
  m.height_samples_all = s.height_all_px;
  m.height_rms_all_m = s.height_all_px == 0
                           ? kNaN
                           : std::sqrt(s.sq_error_all_sum_m2 / static_cast<double>(s.height_all_px));
  m.variance_violation_all = ratio(s.violation_all_px, s.variance_all_px);
  m.max_below_m = s.height_cells == 0 ? kNaN : s.max_below_m;
  return m;
}

double layer_height_at(const LayerMaps& layer, double x_m, double y_m) {
  if (!layer.has_height()) return kNaN;
  int row = 0, col = 0;
  if (!layer.height.cell_at(x_m, y_m, &row, &col)) return kNaN;
  const double h = layer.height.at(row, col);
  if (!layer.has_plane() || !std::isfinite(h)) return h;
  const double sx = layer.slope_x.at(row, col), sy = layer.slope_y.at(row, col);
  if (!std::isfinite(sx) || !std::isfinite(sy)) return h;
  return h + sx * (x_m - layer.height.x_of_col(col)) + sy * (y_m - layer.height.y_of_row(row));
}

namespace {

bool same_geometry(const DenseGrid& a, const DenseGrid& b) {
  return a.rows == b.rows && a.cols == b.cols && a.resolution_m == b.resolution_m &&
         a.center_x_m == b.center_x_m && a.center_y_m == b.center_y_m;
}

// GT pixel rows/cols [r0, r1) x [c0, c1) that can land inside the window: the window's
// corners moved into W, plus a margin for the height's effect under a tilted T_map_W.
void pixel_bounds(const DenseGrid& window, const GroundTruth& gt, const Pose3d& T_map_W, int* r0,
                  int* r1, int* c0, int* c1) {
  const Pose3d T_W_map = T_map_W.inverse();
  const double hx = window.cols * window.resolution_m / 2.0;
  const double hy = window.rows * window.resolution_m / 2.0;
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d p_map(window.center_x_m + ((k & 1) ? hx : -hx),
                                window.center_y_m + ((k & 2) ? hy : -hy), 0.0);
    const Eigen::Vector3d p_W = T_W_map * p_map;
    min_x = std::min(min_x, p_W.x());
    max_x = std::max(max_x, p_W.x());
    min_y = std::min(min_y, p_W.y());
    max_y = std::max(max_y, p_W.y());
  }
  const Eigen::Matrix3d& R = T_W_map.linear();
  const double tilt = std::abs(R(0, 2)) + std::abs(R(1, 2));
  double margin = 2.0 * gt.height.resolution_m;
  if (tilt > 0.0) {
    double z_abs = 0.0;
    for (float z : gt.height.values)
      if (std::isfinite(z)) z_abs = std::max(z_abs, static_cast<double>(std::abs(z)));
    margin += tilt * z_abs;
  }
  const DenseGrid& g = gt.height;
  const auto col_of = [&](double x) { return (x - g.center_x_m) / g.resolution_m + g.cols / 2.0; };
  const auto row_of = [&](double y) { return (g.center_y_m - y) / g.resolution_m + g.rows / 2.0; };
  *c0 = std::max(0, static_cast<int>(std::floor(col_of(min_x - margin))));
  *c1 = std::min(g.cols, static_cast<int>(std::ceil(col_of(max_x + margin))));
  *r0 = std::max(0, static_cast<int>(std::floor(row_of(max_y + margin))));
  *r1 = std::min(g.rows, static_cast<int>(std::ceil(row_of(min_y - margin))));
  if (*c1 < *c0) *c1 = *c0;
  if (*r1 < *r0) *r1 = *r0;
}

}  // namespace

GroundTruth dilate_obstacles(const GroundTruth& gt, double radius_m) {
  check(radius_m >= 0.0 && std::isfinite(radius_m),
        "evaluation: the footprint radius must be a non-negative number");
  GroundTruth out = gt;
  const DenseGrid& src = gt.hazard;
  const int reach = static_cast<int>(std::floor(radius_m / src.resolution_m + 1e-9));
  const double r2 = (radius_m / src.resolution_m) * (radius_m / src.resolution_m) + 1e-9;
  // Obstacles cover a few percent of a scene: splat each one into its disc.
  for (int r = 0; r < src.rows; ++r)
    for (int c = 0; c < src.cols; ++c) {
      const float h = src.at(r, c);
      if (!(h > 0.0f)) continue;
      for (int dr = -reach; dr <= reach; ++dr)
        for (int dc = -reach; dc <= reach; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= src.rows || cc >= src.cols ||
              double(dr * dr + dc * dc) > r2)
            continue;
          float& o = out.hazard.at(rr, cc);
          if (std::isfinite(o) && o < h) o = h;
        }
    }
  return out;
}

namespace {

/// Both grids of the truth and of the layer agree in geometry; h_min and the near radius
/// are numbers in range.
void check_score_inputs(const LayerMaps& layer, const GroundTruth& gt, double h_min_m,
                        const NearRegion* near) {
  check(gt.height.rows > 0 && gt.height.cols > 0, "evaluation: empty ground-truth height grid");
  check(same_geometry(gt.height, gt.hazard),
        "evaluation: ground-truth height and hazard grids differ in size or placement");
  check(h_min_m > 0.0 && std::isfinite(h_min_m), "evaluation: h_min must be positive");
  check(near == nullptr || (near->radius_m >= 0.0 && std::isfinite(near->radius_m)),
        "evaluation: the near radius must be a non-negative number");
  const DenseGrid& window = layer.hazard;
  check(window.rows > 0, "evaluation: layer without a hazard grid");
  if (layer.has_height()) {
    check(same_geometry(layer.height, window), "evaluation: layer height and hazard grids differ");
    check(layer.variance.rows == 0 || same_geometry(layer.variance, window),
          "evaluation: layer variance and hazard grids differ");
  }
  if (layer.has_plane())
    check(same_geometry(layer.slope_x, window) && same_geometry(layer.slope_y, window),
          "evaluation: layer slope and hazard grids differ");
}

/// The error maps cover the GT pixel block [r0, r1) x [c0, c1): NaN errors, outcome
/// "outside" until a pixel is scored.
void reset_error_maps(ErrorMaps& maps, const DenseGrid& g, int r0, int r1, int c0, int c1) {
  const int rows = r1 - r0, cols = c1 - c0;
  const double cx = g.x_of_col(c0) + (cols - 1) * g.resolution_m / 2.0;
  const double cy = g.y_of_row(r0) - (rows - 1) * g.resolution_m / 2.0;
  maps.abs_error_m.reset(rows, cols, g.resolution_m, cx, cy, static_cast<float>(kNaN));
  maps.outcome.reset(rows, cols, g.resolution_m, cx, cy, static_cast<float>(PixelOutcome::outside));
}

/// One GT pixel's contribution to the sums, given what the layer says there (its class,
/// its height h, NaN if none, and that height's variance, NaN if none) and the truth (the
/// obstacle height and the ground's z in the map frame); its outcome goes to `outcome`.
MetricSums pixel_sums(HazardClass cls, double h, double var, double obstacle_m, double z_gt,
                      double h_min_m, PixelOutcome* outcome) {
  MetricSums px;
  px.extent_px = 1;
  const bool gt_hazard = obstacle_m >= h_min_m;
  const bool gt_free = obstacle_m <= 0.0;
  px.gt_hazard_px = gt_hazard;
  const bool known = cls != HazardClass::unknown;
  *outcome = PixelOutcome::unknown;
  if (known) {
    px.known_px = 1;
    px.gt_hazard_known_px = gt_hazard;
    const bool says_hazard = cls == HazardClass::hazard;
    if (gt_hazard) {
      *outcome = says_hazard ? PixelOutcome::hazard_ok : PixelOutcome::missed;
      px.gt_hazard_found_px = says_hazard;
      px.missed_px = !says_hazard;
    } else if (gt_free) {
      *outcome = says_hazard ? PixelOutcome::false_alarm : PixelOutcome::free_ok;
      px.false_alarm_px = says_hazard;
    } else {
      *outcome = PixelOutcome::below_h_min;
    }
  }
  // Heights count whatever the class ("all" sums); the plain sums keep known cells only.
  if (std::isfinite(h)) {
    const double e = h - z_gt;
    if (gt_free) {
      px.height_all_px = 1;
      px.sq_error_all_sum_m2 = e * e;
    }
    if (std::isfinite(var) && var >= 0.0) {
      px.variance_all_px = 1;
      px.violation_all_px = std::abs(e) > 3.0 * std::sqrt(var);
    }
    if (known) {
      px.height_px = px.height_all_px;
      px.sq_error_sum_m2 = px.sq_error_all_sum_m2;
      px.variance_px = px.variance_all_px;
      px.violation_px = px.violation_all_px;
    }
  }
  return px;
}

/// Deepest below the terrain, over the layer's cells: each published height against the
/// GT pixel holding the cell centre; into `s` and, inside the near disc, `near_sums`
/// (`near` and `near_sums` both given or both null).
void add_depth_below(const LayerMaps& layer, const GroundTruth& gt, const Pose3d& T_map_W,
                     const NearRegion* near, MetricSums& s, MetricSums* near_sums) {
  const DenseGrid& window = layer.hazard;
  const DenseGrid& g = gt.height;
  const Pose3d T_W_map = T_map_W.inverse();
  for (int mr = 0; mr < window.rows; ++mr)
    for (int mc = 0; mc < window.cols; ++mc) {
      const double h = layer.height.at(mr, mc);
      if (!std::isfinite(h)) continue;
      const Eigen::Vector3d q_W =
          T_W_map * Eigen::Vector3d(window.x_of_col(mc), window.y_of_row(mr), h);
      int r = 0, c = 0;
      if (!g.cell_at(q_W.x(), q_W.y(), &r, &c)) continue;
      const double z_gt_W = g.at(r, c);
      if (!std::isfinite(z_gt_W) || !std::isfinite(static_cast<double>(gt.hazard.at(r, c))))
        continue;
      const double z_gt_map = (T_map_W * Eigen::Vector3d(q_W.x(), q_W.y(), z_gt_W)).z();
      const double below = z_gt_map - h;
      ++s.height_cells;
      s.max_below_m = std::max(s.max_below_m, below);
      if (near != nullptr && near->contains(q_W.x(), q_W.y())) {
        ++near_sums->height_cells;
        near_sums->max_below_m = std::max(near_sums->max_below_m, below);
      }
    }
}

}  // namespace

MetricSums score_layer(const LayerMaps& layer, const GroundTruth& gt, const Pose3d& T_map_W,
                       double h_min_m, ErrorMaps* maps, const NearRegion* near,
                       MetricSums* near_sums) {
  check_score_inputs(layer, gt, h_min_m, near);
  const DenseGrid& window = layer.hazard;
  int r0, r1, c0, c1;
  pixel_bounds(window, gt, T_map_W, &r0, &r1, &c0, &c1);
  const DenseGrid& g = gt.height;
  MetricSums s;
  s.pixel_area_m2 = g.resolution_m * g.resolution_m;
  const bool with_near = near != nullptr && near_sums != nullptr;
  if (with_near) {
    *near_sums = MetricSums{};
    near_sums->pixel_area_m2 = s.pixel_area_m2;
  }
  if (maps) reset_error_maps(*maps, g, r0, r1, c0, c1);
  const bool with_variance = layer.has_height() && layer.variance.rows > 0;
  for (int r = r0; r < r1; ++r) {
    for (int c = c0; c < c1; ++c) {
      const double z_gt_W = g.at(r, c);
      const double obstacle_m = gt.hazard.at(r, c);
      if (!std::isfinite(z_gt_W) || !std::isfinite(obstacle_m)) continue;  // GT has no data
      const Eigen::Vector3d p_map = T_map_W * Eigen::Vector3d(g.x_of_col(c), g.y_of_row(r), z_gt_W);
      int mr = 0, mc = 0;
      if (!window.cell_at(p_map.x(), p_map.y(), &mr, &mc)) continue;
      HazardClass cls;
      if (!hazard_class_of(window.at(mr, mc), &cls))
        throw Error("evaluation: hazard grid cell (" + std::to_string(mr) + ", " +
                    std::to_string(mc) + ") holds no hazard class (0, 1, 2 or nodata)");
      const double h = layer_height_at(layer, p_map.x(), p_map.y());
      const double var = with_variance ? layer.variance.at(mr, mc) : kNaN;
      PixelOutcome outcome;
      const MetricSums px = pixel_sums(cls, h, var, obstacle_m, p_map.z(), h_min_m, &outcome);
      // Added to the window's sums and, inside the near disc (tested at the GT pixel centre
      // in W, where the rover truly is), to the near sums.
      s += px;
      if (with_near && near->contains(g.x_of_col(c), g.y_of_row(r))) *near_sums += px;
      if (maps) {
        if (cls != HazardClass::unknown && std::isfinite(h))
          maps->abs_error_m.at(r - r0, c - c0) = static_cast<float>(std::abs(h - p_map.z()));
        maps->outcome.at(r - r0, c - c0) = static_cast<float>(outcome);
      }
    }
  }
  if (layer.has_height())
    add_depth_below(layer, gt, T_map_W, with_near ? near : nullptr, s,
                    with_near ? near_sums : nullptr);
  return s;
}

}  // namespace hazmap::eval
