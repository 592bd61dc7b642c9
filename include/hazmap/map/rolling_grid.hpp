#pragma once
// Geometry of one robot-centric rolling layer (SPEC 5): an N x N window of global cell
// indices, stored as a 2-D ring buffer. The window moves by whole cells and only when
// the robot leaves the four central cells (one-cell hysteresis); the caller clears the
// cells of the regions that entered, nothing else is copied.

#include <array>
#include <cmath>
#include <string>

#include "hazmap/map/grid_math.hpp"

namespace hazmap {

/// Half-open rectangle of global cell indices [x0, x1) x [y0, y1).
struct CellRange {
  CellIndex x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
};

/// True when a robot coordinate is finite and within kMaxRobotCells cells of W's origin
/// in a layer of this resolution (RollingGrid::move_to throws otherwise).
inline bool position_in_range(double x_m, double resolution_m) {
  return std::abs(x_m / resolution_m) < kMaxRobotCells;  // false for NaN and inf
}

/// One-line message for a robot position that fails position_in_range.
std::string robot_position_error(double x_m, double y_m, double resolution_m);

/// The regions that entered the window in one move (at most two strips).
struct NewRegions {
  std::array<CellRange, 2> ranges;
  int count = 0;
};

class RollingGrid {
 public:
  /// `size` even, >= 2.
  RollingGrid(int size, double resolution_m);

  int size() const { return size_; }
  double resolution_m() const { return resolution_m_; }
  bool placed() const { return placed_; }

  /// Places the window (first call) or moves it so that the robot at (x, y) is in one of
  /// the four central cells. Returns the regions that entered (the whole window on the
  /// first call, or after a jump of N cells or more); empty when nothing moved.
  NewRegions move_to(double x_m, double y_m);

  /// Global index of the window's first (smallest) cell along x and y.
  CellIndex origin_x() const { return origin_x_; }
  CellIndex origin_y() const { return origin_y_; }

  bool contains(CellIndex ix, CellIndex iy) const {
    return ix >= origin_x_ && ix < origin_x_ + size_ && iy >= origin_y_ && iy < origin_y_ + size_;
  }
  /// Storage slot of a cell inside the window: wrap(iy) * N + wrap(ix).
  int slot(CellIndex ix, CellIndex iy) const {
    return wrap_index(iy, size_) * size_ + wrap_index(ix, size_);
  }
  /// W coordinates of the window's geometric centre (the corner of the central cells).
  double center_x_m() const { return static_cast<double>(origin_x_ + size_ / 2) * resolution_m_; }
  double center_y_m() const { return static_cast<double>(origin_y_ + size_ / 2) * resolution_m_; }

 private:
  int size_;
  double resolution_m_;
  bool placed_ = false;
  CellIndex origin_x_ = 0;
  CellIndex origin_y_ = 0;
};

}  // namespace hazmap
