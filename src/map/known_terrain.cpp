#include "hazmap/map/known_terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

bool same_shape(const DenseGrid& a, const DenseGrid& b) {
  return a.rows == b.rows && a.cols == b.cols;
}

}  // namespace

void KnownTerrain::add_layer(const DenseGrid& height, const DenseGrid& variance,
                             const DenseGrid& slope_x, const DenseGrid& slope_y) {
  if (height.rows <= 0 || height.cols <= 0) return;
  check(variance.rows == 0 || same_shape(height, variance),
        "KnownTerrain: height and variance grids differ in size");
  const bool plane = slope_x.rows > 0 && slope_y.rows > 0;
  check(!plane || (same_shape(height, slope_x) && same_shape(height, slope_y)),
        "KnownTerrain: height and slope grids differ in size");
  Layer l;
  l.height = &height;
  l.variance = variance.rows > 0 ? &variance : nullptr;
  l.slope_x = plane ? &slope_x : nullptr;
  l.slope_y = plane ? &slope_y : nullptr;
  l.inv_resolution = 1.0 / height.resolution_m;
  l.x0_m = height.center_x_m - 0.5 * height.cols * height.resolution_m;
  l.y1_m = height.center_y_m + 0.5 * height.rows * height.resolution_m;
  layers_.push_back(l);
}

const KnownTerrain::Layer* KnownTerrain::find(double x_m, double y_m, int* row, int* col) const {
  for (const Layer& l : layers_) {
    // DenseGrid::cell_at without its divisions (this runs per ray sample).
    const double c = std::floor((x_m - l.x0_m) * l.inv_resolution);
    const double r = std::floor((l.y1_m - y_m) * l.inv_resolution);
    if (c < 0 || r < 0 || c >= l.height->cols || r >= l.height->rows) continue;
    *row = static_cast<int>(r);
    *col = static_cast<int>(c);
    if (std::isfinite(l.height->at(*row, *col))) return &l;
  }
  return nullptr;
}

bool KnownTerrain::height_at(double x_m, double y_m, double* height_m, double* variance_m2) const {
  int row = 0, col = 0;
  const Layer* l = find(x_m, y_m, &row, &col);
  if (!l) return false;
  double z = l->height->at(row, col);
  if (l->slope_x) {
    const double sx = l->slope_x->at(row, col), sy = l->slope_y->at(row, col);
    if (std::isfinite(sx) && std::isfinite(sy))
      z += sx * (x_m - l->height->x_of_col(col)) + sy * (y_m - l->height->y_of_row(row));
  }
  const double var = l->variance ? l->variance->at(row, col) : 0.0;
  *height_m = z;
  *variance_m2 = std::isfinite(var) && var > 0.0 ? var : 0.0;
  return true;
}

void KnownTerrain::prepare_near_field(double x0_m, double y0_m, double x1_m, double y1_m,
                                      double fill_m, double k_sigma) {
  fill_.rows = fill_.cols = 0;
  max_top_ = max_unseen_ = -std::numeric_limits<double>::infinity();
  if (layers_.empty() || !std::isfinite(x0_m) || !std::isfinite(y0_m) || !std::isfinite(x1_m) ||
      !std::isfinite(y1_m))
    return;
  const double r = finest_resolution_m();
  // Cells with borders at multiples of r, one beyond the region on every side; a config
  // cannot blow the raster up (at most kMaxCells a side, centred on the region).
  constexpr double kMaxCells = 4096;
  double i0 = std::floor(std::min(x0_m, x1_m) / r) - 1, i1 = std::floor(std::max(x0_m, x1_m) / r) + 2;
  double j0 = std::floor(std::min(y0_m, y1_m) / r) - 1, j1 = std::floor(std::max(y0_m, y1_m) / r) + 2;
  if (i1 - i0 > kMaxCells) i0 = std::floor(0.5 * (i0 + i1 - kMaxCells)), i1 = i0 + kMaxCells;
  if (j1 - j0 > kMaxCells) j0 = std::floor(0.5 * (j0 + j1 - kMaxCells)), j1 = j0 + kMaxCells;
  const int cols = static_cast<int>(i1 - i0), rows = static_cast<int>(j1 - j0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float none = -std::numeric_limits<float>::infinity();
  fill_.reset(rows, cols, r, 0.5 * (i0 + i1) * r, 0.5 * (j0 + j1) * r, nan);
  known_.assign(static_cast<std::size_t>(rows) * cols, none);
  block_rows_ = (rows + kBlockCells - 1) / kBlockCells;
  block_cols_ = (cols + kBlockCells - 1) / kBlockCells;
  block_top_.assign(static_cast<std::size_t>(block_rows_) * block_cols_, none);
  block_unseen_.assign(block_top_.size(), none);
  const auto block = [&](int row, int col) {
    return static_cast<std::size_t>(row / kBlockCells) * block_cols_ + col / kBlockCells;
  };
  bool any_unknown = false;
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      int lr = 0, lc = 0;
      const Layer* l = find(fill_.x_of_col(col), fill_.y_of_row(row), &lr, &lc);
      if (!l) {
        any_unknown = true;
        continue;
      }
      double top = l->height->at(lr, lc);
      if (l->slope_x) {
        const double sx = l->slope_x->at(lr, lc), sy = l->slope_y->at(lr, lc);
        if (std::isfinite(sx) && std::isfinite(sy))
          top += 0.5 * l->height->resolution_m * (std::abs(sx) + std::abs(sy));
      }
      known_[static_cast<std::size_t>(row) * cols + col] = static_cast<float>(top);
      double sigma_top = top;
      if (k_sigma > 0.0 && l->variance) {
        const double var = l->variance->at(lr, lc);
        if (std::isfinite(var) && var > 0.0) sigma_top += k_sigma * std::sqrt(var);
      }
      max_top_ = std::max(max_top_, sigma_top);
      float& b = block_top_[block(row, col)];
      b = std::max(b, static_cast<float>(sigma_top));
    }
  // Unseen cells: the highest known top within `fill` cells in x and y (a separable max),
  // fill_m rounded up to whole cells.
  const int fill = static_cast<int>(std::min(std::ceil(fill_m / r - 1e-9), kMaxCells));
  if (!any_unknown || fill <= 0) return;
  row_max_.assign(known_.size(), none);
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      float m = none;
      for (int c = std::max(0, col - fill); c <= std::min(cols - 1, col + fill); ++c)
        m = std::max(m, known_[static_cast<std::size_t>(row) * cols + c]);
      row_max_[static_cast<std::size_t>(row) * cols + col] = m;
    }
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      if (known_[static_cast<std::size_t>(row) * cols + col] > none) continue;  // seen
      float m = none;
      for (int rr = std::max(0, row - fill); rr <= std::min(rows - 1, row + fill); ++rr)
        m = std::max(m, row_max_[static_cast<std::size_t>(rr) * cols + col]);
      if (m > none) {
        fill_.at(row, col) = m;
        max_unseen_ = std::max(max_unseen_, static_cast<double>(m));
        float& b = block_unseen_[block(row, col)];
        b = std::max(b, m);
      }
    }
}

KnownTerrain::Levels KnownTerrain::max_levels_in(double x0_m, double y0_m, double x1_m,
                                                double y1_m) const {
  Levels all{max_top_, max_unseen_};
  if (fill_.rows == 0) return all;
  const double r = fill_.resolution_m;
  const double left = fill_.center_x_m - 0.5 * fill_.cols * r;
  const double top = fill_.center_y_m + 0.5 * fill_.rows * r;
  const double c0 = std::floor((std::min(x0_m, x1_m) - left) / r);
  const double c1 = std::floor((std::max(x0_m, x1_m) - left) / r);
  const double r0 = std::floor((top - std::max(y0_m, y1_m)) / r);
  const double r1 = std::floor((top - std::min(y0_m, y1_m)) / r);
  if (!(c0 >= 0 && r0 >= 0 && c1 < fill_.cols && r1 < fill_.rows)) return all;
  Levels out{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (int br = static_cast<int>(r0) / kBlockCells; br <= static_cast<int>(r1) / kBlockCells; ++br)
    for (int bc = static_cast<int>(c0) / kBlockCells; bc <= static_cast<int>(c1) / kBlockCells;
         ++bc) {
      const std::size_t k = static_cast<std::size_t>(br) * block_cols_ + bc;
      out.top_m = std::max(out.top_m, static_cast<double>(block_top_[k]));
      out.unseen_m = std::max(out.unseen_m, static_cast<double>(block_unseen_[k]));
    }
  return out;
}

bool KnownTerrain::unseen_height_at(double x_m, double y_m, double* height_m) const {
  int row = 0, col = 0;
  if (fill_.rows == 0 || !fill_.cell_at(x_m, y_m, &row, &col)) return false;
  const float h = fill_.at(row, col);
  if (!std::isfinite(h)) return false;
  *height_m = h;
  return true;
}

}  // namespace hazmap
