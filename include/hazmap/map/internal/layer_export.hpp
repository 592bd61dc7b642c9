#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// A layer's cells -> the published grids (LayerGrids): what each known cell publishes
// (export_cells; SPEC 6.4 for plane cells) and the pose uncertainty added since each
// cell's last update (inflate_variance, SPEC 7). Image rows run from the window's largest
// y (row 0) down.

#include <array>
#include <cmath>

#include "hazmap/map/internal/layer_cells.hpp"
#include "hazmap/map/layer.hpp"
#include "hazmap/map/plane_cell_values.hpp"

namespace hazmap {
namespace layer_export {

/// The grids only layers with a plane fill.
inline std::array<DenseGrid*, 12> plane_grids(LayerGrids& out) {
  return {&out.count,     &out.slope_x,    &out.slope_y,    &out.roughness,
          &out.coverage,  &out.evaluable,  &out.noise_variance, &out.lateral_xx,
          &out.lateral_yy, &out.lateral_xy, &out.lateral_xz, &out.lateral_yz};
}

/// Writes the known cells of `rect` into grids that hold NaN there. `seen_whole`: cells
/// also evaluable by a hole-free view (map/seen_whole.hpp); null: none.
template <class Rule>
void export_cells(const LayerCells<Rule>& cells, const RollingGrid& grid, LayerGrids& out,
                  const GridRect& rect, const SeenWhole* seen_whole = nullptr) {
  const auto& config = cells.config();
  const int n = grid.size();
  const double r = grid.resolution_m();
  for (int row = rect.row0; row < rect.row1; ++row) {
    const CellIndex iy = grid.origin_y() + (n - 1 - row);
    for (int col = rect.col0; col < rect.col1; ++col) {
      const CellIndex ix = grid.origin_x() + col;
      const typename Rule::Cell c = cells.current(grid.slot(ix, iy));
      if (!Rule::known(c)) continue;
      if constexpr (Rule::kHasPlane) {
        // SPEC 6.4: an evaluable cell publishes its plane at the centre; any other its
        // mean height, no slopes, and a variance that covers the unmeasured tilt.
        const PlaneCellValues v = Rule::cell_values(c);
        const double coverage = Rule::coverage(c, r);
        const bool by_rule = Rule::evaluable(config, c, r);
        const bool by_mark = !by_rule && seen_whole &&
                             seen_whole->hole_free(row, col, coverage, v.count, Rule::occupied(c));
        const bool evaluable = by_rule || by_mark;
        if (evaluable) {
          double a, b;
          Rule::slopes(config, c, &a, &b);
          out.height.at(row, col) = static_cast<float>(Rule::height_at(config, c, 0.0, 0.0));
          out.slope_x.at(row, col) = static_cast<float>(a);
          out.slope_y.at(row, col) = static_cast<float>(b);
        } else {
          out.height.at(row, col) = static_cast<float>(Rule::mean_z(c));
        }
        out.variance.at(row, col) =
            static_cast<float>(Rule::published_variance(config, c, r, evaluable));
        out.roughness.at(row, col) = static_cast<float>(Rule::roughness(config, c));
        out.coverage.at(row, col) = static_cast<float>(coverage);
        out.evaluable.at(row, col) = by_rule ? 1.0f : by_mark ? kEvaluableOwnCell : 0.0f;
        out.count.at(row, col) = v.count;
        out.noise_variance.at(row, col) = v.noise_variance;
        out.lateral_xx.at(row, col) = v.lateral_xx;
        out.lateral_yy.at(row, col) = v.lateral_yy;
        out.lateral_xy.at(row, col) = v.lateral_xy;
        out.lateral_xz.at(row, col) = v.lateral_xz;
        out.lateral_yz.at(row, col) = v.lateral_yz;
      } else {
        out.height.at(row, col) = Rule::height(c);
        out.variance.at(row, col) = Rule::variance(c);
      }
    }
  }
}

/// SPEC 7: variance += g^T Sigma_lat g + Sigma_zz for the noise added since the
/// cell's last update; g from the plane (CCM) or central differences of heights.
template <class Rule>
void inflate_variance(const LayerCells<Rule>& cells, const RollingGrid& grid, LayerGrids& out,
                      const PoseUncertainty& pose, double rx, double ry) {
  const int n = grid.size();
  const double r = grid.resolution_m();
  auto h = [&](int row, int col) -> double {
    if (row < 0 || col < 0 || row >= n || col >= n) return std::nan("");
    return out.height.at(row, col);
  };
  auto diff = [](double lo, double mid, double hi, double step) {
    if (!std::isnan(lo) && !std::isnan(hi)) return (hi - lo) / (2 * step);
    if (!std::isnan(hi)) return (hi - mid) / step;
    if (!std::isnan(lo)) return (mid - lo) / step;
    return 0.0;
  };
  for (int row = 0; row < n; ++row) {
    const CellIndex iy = grid.origin_y() + (n - 1 - row);
    for (int col = 0; col < n; ++col) {
      const float v = out.variance.at(row, col);
      if (std::isnan(out.height.at(row, col))) continue;
      const CellIndex ix = grid.origin_x() + col;
      double gx = std::nan(""), gy = std::nan("");
      if constexpr (Rule::kHasPlane) {
        gx = out.slope_x.at(row, col);
        gy = out.slope_y.at(row, col);
      }
      // Piecewise-constant cells, and CCM cells without slopes (not evaluable).
      if (std::isnan(gx) || std::isnan(gy)) {
        const double mid = h(row, col);
        gx = diff(h(row, col - 1), mid, h(row, col + 1), r);
        gy = diff(h(row + 1, col), mid, h(row - 1, col), r);  // row 0 = largest y
      }
      const double added =
          pose.added_variance(cells.last_merge(grid.slot(ix, iy)), cell_center(ix, r) - rx,
                              cell_center(iy, r) - ry, gx, gy);
      out.variance.at(row, col) = static_cast<float>((std::isnan(v) ? 0.0 : v) + added);
    }
  }
}

}  // namespace layer_export
}  // namespace hazmap
