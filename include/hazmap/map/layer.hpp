#pragma once
// One layer of the map: a rolling ring buffer of cells updated by one rule. The
// type-erased interface is called once per frame (never per point); the rule's cell
// update is inlined in RollingLayer<Rule>::insert.

#include <memory>
#include <string>

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/measurement.hpp"
#include "hazmap/map/rolling_grid.hpp"

namespace hazmap {

class Layer {
 public:
  virtual ~Layer() = default;

  /// Rolls the window to the robot's position (clearing cells that left) and applies
  /// the rule's per-frame update (e.g. Kalman time inflation) to the cells in view.
  virtual void begin_frame(double robot_x_m, double robot_y_m) = 0;

  /// Inserts every point whose cell is inside the window; returns how many were used.
  virtual size_t insert(const PointCloud& cloud) = 0;

  /// Dense height (cell-centre height, NaN unknown) and variance grids of the window.
  virtual void export_height(DenseGrid& out) const = 0;
  virtual void export_variance(DenseGrid& out) const = 0;

  virtual const char* rule_name() const = 0;
  virtual const RollingGrid& grid() const = 0;
};

}  // namespace hazmap
