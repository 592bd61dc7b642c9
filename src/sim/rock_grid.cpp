#include "hazmap/sim/rock_grid.hpp"

#include "hazmap/core/error.hpp"

namespace hazmap::sim {

RockGrid::RockGrid(const std::vector<Eigen::Vector3d>& centers_W,
                   const std::vector<double>& radii_m) {
  check(centers_W.size() == radii_m.size(), "rock grid: centres and radii differ in count");
  if (centers_W.empty()) return;
  // Padding keeps a hit exactly on a footprint's edge inside the rock's listed cells.
  constexpr double kPadM = 1e-9;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  double max_radius_m = 0.0;
  for (std::size_t i = 0; i < centers_W.size(); ++i) {
    const double r = radii_m[i] + kPadM;
    x0 = std::min(x0, centers_W[i].x() - r);
    x1 = std::max(x1, centers_W[i].x() + r);
    y0 = std::min(y0, centers_W[i].y() - r);
    y1 = std::max(y1, centers_W[i].y() + r);
    max_radius_m = std::max(max_radius_m, radii_m[i]);
    max_top_z_m_ = std::max(max_top_z_m_, centers_W[i].z() + radii_m[i]);
  }
  const double area_m2 = (x1 - x0) * (y1 - y0);
  cell_m_ = std::max(std::sqrt(area_m2 / static_cast<double>(centers_W.size())),
                     0.5 * max_radius_m);
  cell_m_ = std::max(cell_m_, std::sqrt(area_m2 / 1e6));
  min_x_m_ = x0;
  min_y_m_ = y0;
  cells_x_ = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell_m_)));
  cells_y_ = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell_m_)));

  // Two passes (count, then fill) build the compressed cell lists.
  auto cell_range = [&](std::size_t i, int& ix0, int& ix1, int& iy0, int& iy1) {
    const double r = radii_m[i] + kPadM;
    ix0 = std::clamp(static_cast<int>(std::floor((centers_W[i].x() - r - x0) / cell_m_)), 0,
                     cells_x_ - 1);
    ix1 = std::clamp(static_cast<int>(std::floor((centers_W[i].x() + r - x0) / cell_m_)), 0,
                     cells_x_ - 1);
    iy0 = std::clamp(static_cast<int>(std::floor((centers_W[i].y() - r - y0) / cell_m_)), 0,
                     cells_y_ - 1);
    iy1 = std::clamp(static_cast<int>(std::floor((centers_W[i].y() + r - y0) / cell_m_)), 0,
                     cells_y_ - 1);
  };
  const std::size_t cells = static_cast<std::size_t>(cells_x_) * cells_y_;
  offsets_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < centers_W.size(); ++i) {
    int ix0, ix1, iy0, iy1;
    cell_range(i, ix0, ix1, iy0, iy1);
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) ++offsets_[static_cast<std::size_t>(iy) * cells_x_ + ix + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) offsets_[c + 1] += offsets_[c];
  indices_.resize(static_cast<std::size_t>(offsets_[cells]));
  std::vector<int> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t i = 0; i < centers_W.size(); ++i) {
    int ix0, ix1, iy0, iy1;
    cell_range(i, ix0, ix1, iy0, iy1);
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix)
        indices_[static_cast<std::size_t>(fill[static_cast<std::size_t>(iy) * cells_x_ + ix]++)] =
            static_cast<int>(i);
  }
}

}  // namespace hazmap::sim
