#pragma once
// A layer whose cells follow update rule `Rule` (see rules/): a struct with Config,
// Cell, and static known / clear / update / begin_frame / height / variance.

#include <vector>

#include "hazmap/map/layer.hpp"

namespace hazmap {

template <class Rule>
class RollingLayer final : public Layer {
 public:
  RollingLayer(int size, double resolution_m, const typename Rule::Config& config,
               const char* name)
      : grid_(size, resolution_m),
        config_(config),
        name_(name),
        cells_(static_cast<size_t>(size) * size) {}

  void begin_frame(double robot_x_m, double robot_y_m) override {
    const NewRegions regions = grid_.move_to(robot_x_m, robot_y_m);
    for (int k = 0; k < regions.count; ++k) clear(regions.ranges[k]);
    for (auto& cell : cells_) Rule::begin_frame(config_, cell);
  }

  size_t insert(const PointCloud& cloud) override {
    const double r = grid_.resolution_m();
    size_t used = 0;
    for (const Measurement& m : cloud) {
      const CellIndex ix = cell_index(m.p_W.x(), r);
      const CellIndex iy = cell_index(m.p_W.y(), r);
      if (!grid_.contains(ix, iy)) continue;
      Rule::update(config_, cells_[grid_.slot(ix, iy)], m.p_W.z(), m.height_variance());
      ++used;
    }
    return used;
  }

  void export_height(DenseGrid& out) const override {
    export_values(out, [](const typename Rule::Cell& c) { return Rule::height(c); });
  }
  void export_variance(DenseGrid& out) const override {
    export_values(out, [](const typename Rule::Cell& c) { return Rule::variance(c); });
  }

  const char* rule_name() const override { return name_; }
  const RollingGrid& grid() const override { return grid_; }

  /// Direct cell access by global index (tests, queries). Requires contains(ix, iy).
  const typename Rule::Cell& cell(CellIndex ix, CellIndex iy) const {
    return cells_[grid_.slot(ix, iy)];
  }

 private:
  void clear(const CellRange& range) {
    for (CellIndex iy = range.y0; iy < range.y1; ++iy)
      for (CellIndex ix = range.x0; ix < range.x1; ++ix) Rule::clear(cells_[grid_.slot(ix, iy)]);
  }

  template <class Get>
  void export_values(DenseGrid& out, Get get) const {
    const int n = grid_.size();
    out.reset(n, n, grid_.resolution_m(), grid_.center_x_m(), grid_.center_y_m(), 0.0f);
    for (int row = 0; row < n; ++row) {
      const CellIndex iy = grid_.origin_y() + (n - 1 - row);
      for (int col = 0; col < n; ++col)
        out.at(row, col) = get(cells_[grid_.slot(grid_.origin_x() + col, iy)]);
    }
  }

  RollingGrid grid_;
  typename Rule::Config config_;
  const char* name_;
  std::vector<typename Rule::Cell> cells_;
};

}  // namespace hazmap
