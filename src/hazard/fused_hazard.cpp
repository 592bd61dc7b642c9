#include "hazmap/hazard/fused_hazard.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {

int fused_cells(double extent_m, double resolution_m) {
  const long n = std::lround(extent_m / resolution_m / 2.0) * 2;
  return static_cast<int>(std::max(2L, n));
}

void HazardFusion::fuse(const std::vector<FusionInput>& layers, double critical_height_m,
                        int cells, double resolution_m, double center_x_m, double center_y_m,
                        DenseGrid& fused, DenseGrid& clearance) {
  check(!layers.empty(), "fuse: no layers");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  fused.reset(cells, cells, resolution_m, center_x_m, center_y_m,
              static_cast<float>(HazardClass::unknown));
  clearance.reset(cells, cells, resolution_m, center_x_m, center_y_m, nan);
  const size_t n = static_cast<size_t>(cells);
  cols_.assign(n * layers.size(), -1);
  rows_.assign(n * layers.size(), -1);
  // Each fused column (row) falls in one layer column (row): look them up once.
  for (size_t l = 0; l < layers.size(); ++l) {
    const DenseGrid& g = *layers[l].hazard;
    for (int k = 0; k < cells; ++k) {
      int row = 0, col = 0;
      if (g.cell_at(fused.x_of_col(k), g.center_y_m, &row, &col)) cols_[l * n + k] = col;
      if (g.cell_at(g.center_x_m, fused.y_of_row(k), &row, &col)) rows_[l * n + k] = row;
    }
  }
  const auto hazard = static_cast<float>(HazardClass::hazard);
  const auto traversable = static_cast<float>(HazardClass::traversable);
  for (int row = 0; row < cells; ++row) {
    for (int col = 0; col < cells; ++col) {
      bool is_hazard = false;
      double smallest = std::numeric_limits<double>::infinity();
      for (size_t l = 0; l < layers.size(); ++l) {
        const int lr = rows_[l * n + row], lc = cols_[l * n + col];
        if (lr < 0 || lc < 0) continue;
        const float v = layers[l].hazard->at(lr, lc);
        if (v == hazard) is_hazard = true;
        else if (v == traversable) smallest = std::min(smallest, layers[l].h_min_m);
      }
      if (is_hazard) {
        fused.at(row, col) = hazard;
      } else if (std::isfinite(smallest)) {
        clearance.at(row, col) = static_cast<float>(smallest);
        if (smallest <= critical_height_m) fused.at(row, col) = traversable;
      }
    }
  }
}

void HazardFusion::footprint(const DenseGrid& fused, double radius_m, DenseGrid& footprint,
                             DenseGrid& hazard_distance) {
  const int rows = fused.rows, cols = fused.cols;
  const double r = fused.resolution_m;
  footprint.reset(rows, cols, r, fused.center_x_m, fused.center_y_m,
                  static_cast<float>(HazardClass::unknown));
  hazard_distance.reset(rows, cols, r, fused.center_x_m, fused.center_y_m, 0.0f);
  const size_t cells = fused.values.size();
  hazard_src_.resize(cells);
  unknown_src_.resize(cells);
  for (size_t i = 0; i < cells; ++i) {
    const auto k = static_cast<HazardClass>(static_cast<int>(fused.values[i]));
    hazard_src_[i] = k == HazardClass::hazard;
    unknown_src_[i] = k == HazardClass::unknown;
  }
  edt_.compute(hazard_src_.data(), rows, cols, hazard_d2_);
  edt_.compute(unknown_src_.data(), rows, cols, unknown_d2_);
  const double radius_cells = radius_m / r;
  const double radius2 = radius_cells * radius_cells * (1.0 + 1e-9);
  const double cap_m = 0.5 * std::min(rows, cols) * r;
  for (int row = 0; row < rows; ++row) {
    // Beyond the edge nothing is known: the nearest outside cell centre is this far.
    const int edge_row = std::min(row, rows - 1 - row) + 1;
    for (int col = 0; col < cols; ++col) {
      const size_t i = static_cast<size_t>(row) * cols + col;
      const int edge = std::min({edge_row, col + 1, cols - col});
      const double dh2 = hazard_d2_[i];
      hazard_distance.values[i] = static_cast<float>(std::min(cap_m, std::sqrt(dh2) * r));
      HazardClass k = HazardClass::traversable;
      if (dh2 <= radius2) k = HazardClass::hazard;
      else if (unknown_d2_[i] <= radius2 || double(edge) * edge <= radius2) k = HazardClass::unknown;
      footprint.values[i] = static_cast<float>(k);
    }
  }
}

}  // namespace hazmap
