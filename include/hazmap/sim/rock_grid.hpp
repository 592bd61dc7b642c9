#pragma once
// A uniform 2-D grid over the rocks' footprints, so that a ray only tests the rocks near
// its path instead of all of them. With hundreds of rocks (a rock density over a 12 m
// field) testing every rock for every ray and every shadow ray would dominate rendering.
//
// Frame W, metres. A rock is a sphere (centre, radius); it is listed in every cell its
// footprint circle's bounding square touches.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace hazmap::sim {

class RockGrid {
 public:
  RockGrid() = default;

  /// Indexes spheres i (centre centers_W[i], radius radii_m[i]); the two vectors have
  /// the same length. The cell size follows the rock density (about one rock per cell),
  /// at least the largest rock diameter / 4, and the grid has at most ~1e6 cells.
  RockGrid(const std::vector<Eigen::Vector3d>& centers_W, const std::vector<double>& radii_m);

  bool empty() const { return cells_x_ == 0; }

  /// Highest point of any sphere (centre z + radius); -inf without rocks.
  double max_top_z_m() const { return max_top_z_m_; }

  /// Visits the cells that the horizontal projection of the ray origin_W + t dir_W
  /// (dir_W need not be unit; t in [0, t_max]) passes through, in order of increasing t.
  /// For each cell that lists rocks calls visit(begin, end, t_exit): the rock indices
  /// [begin, end) of the cell and the t at which the ray leaves it. Stops when visit
  /// returns false, or the ray leaves the grid or passes t_max. A rock may be visited
  /// more than once (it is listed in every cell it overlaps).
  /// A vertical ray visits the one cell below its origin.
  template <typename Visit>
  void traverse(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& dir_W, double t_max,
                Visit&& visit) const;

 private:
  const int* cell_begin(int ix, int iy) const {
    return indices_.data() + offsets_[static_cast<std::size_t>(iy) * cells_x_ + ix];
  }
  const int* cell_end(int ix, int iy) const {
    return indices_.data() + offsets_[static_cast<std::size_t>(iy) * cells_x_ + ix + 1];
  }

  double min_x_m_ = 0.0;
  double min_y_m_ = 0.0;
  double cell_m_ = 1.0;
  int cells_x_ = 0;
  int cells_y_ = 0;
  std::vector<int> offsets_;  ///< CSR: cell c holds indices_[offsets_[c], offsets_[c+1])
  std::vector<int> indices_;
  double max_top_z_m_ = -std::numeric_limits<double>::infinity();
};

// ---------------------------------------------------------------------------------------
// Implementation (templated: inlined into the ray caster's hot loop).

template <typename Visit>
void RockGrid::traverse(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& dir_W,
                        double t_max, Visit&& visit) const {
  if (empty() || !(t_max > 0.0)) return;
  const double ox = origin_W.x();
  const double oy = origin_W.y();
  const double dx = dir_W.x();
  const double dy = dir_W.y();
  const double max_x = min_x_m_ + cells_x_ * cell_m_;
  const double max_y = min_y_m_ + cells_y_ * cell_m_;

  // Clip [0, t_max] to the grid's box (slab test).
  double t0 = 0.0;
  double t1 = t_max;
  auto clip = [&](double o, double d, double lo, double hi) {
    if (d == 0.0) return o >= lo && o < hi;
    double ta = (lo - o) / d;
    double tb = (hi - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    return t0 <= t1;
  };
  if (!clip(ox, dx, min_x_m_, max_x) || !clip(oy, dy, min_y_m_, max_y)) return;

  // Amanatides-Woo walk from the entry point.
  const double ex = (ox + t0 * dx - min_x_m_) / cell_m_;
  const double ey = (oy + t0 * dy - min_y_m_) / cell_m_;
  int ix = std::clamp(static_cast<int>(std::floor(ex)), 0, cells_x_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor(ey)), 0, cells_y_ - 1);
  const int step_x = dx > 0.0 ? 1 : -1;
  const int step_y = dy > 0.0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  // t at which the ray crosses the next cell border in x (y), and the t per cell.
  double t_next_x = dx == 0.0 ? inf
                              : (min_x_m_ + (ix + (dx > 0.0 ? 1 : 0)) * cell_m_ - ox) / dx;
  double t_next_y = dy == 0.0 ? inf
                              : (min_y_m_ + (iy + (dy > 0.0 ? 1 : 0)) * cell_m_ - oy) / dy;
  const double t_delta_x = dx == 0.0 ? inf : cell_m_ / std::abs(dx);
  const double t_delta_y = dy == 0.0 ? inf : cell_m_ / std::abs(dy);

  while (true) {
    const double t_exit = std::min({t_next_x, t_next_y, t1});
    const int* begin = cell_begin(ix, iy);
    const int* end = cell_end(ix, iy);
    if (begin != end && !visit(begin, end, t_exit)) return;
    if (t_exit >= t1) return;
    if (t_next_x < t_next_y) {
      ix += step_x;
      t_next_x += t_delta_x;
    } else {
      iy += step_y;
      t_next_y += t_delta_y;
    }
    if (ix < 0 || ix >= cells_x_ || iy < 0 || iy >= cells_y_) return;
  }
}

}  // namespace hazmap::sim
