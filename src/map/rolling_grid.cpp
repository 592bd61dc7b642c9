#include "hazmap/map/rolling_grid.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

/// New origin so that cell c is one of the two central cells origin + N/2 - 1, origin + N/2.
CellIndex follow(CellIndex origin, CellIndex c, int n) {
  if (c < origin + n / 2 - 1) return c - n / 2 + 1;
  if (c > origin + n / 2) return c - n / 2;
  return origin;
}

}  // namespace

RollingGrid::RollingGrid(int size, double resolution_m) : size_(size), resolution_m_(resolution_m) {
  check(size >= 2 && size % 2 == 0, "rolling grid: size must be even and >= 2");
  check(resolution_m > 0, "rolling grid: resolution must be positive");
}

std::string robot_position_error(double x_m, double y_m, double resolution_m) {
  const bool x_bad = !position_in_range(x_m, resolution_m);
  const double v = x_bad ? x_m : y_m;
  char text[320];
  std::snprintf(text, sizeof text,
                "map: robot position %s = %g m is %g cells of a %g m layer: |%s / resolution| "
                "must stay below 2^30 cells (a pose far outside any traverse, or a bad pose file)",
                x_bad ? "x" : "y", v, v / resolution_m, resolution_m, x_bad ? "x" : "y");
  return text;
}

NewRegions RollingGrid::move_to(double x_m, double y_m) {
  // Before any index arithmetic: llround / floor of a value beyond int64 is undefined and
  // gave an origin near INT64_MIN (a map centred at -9.2e16 m, exit 0).
  if (!position_in_range(x_m, resolution_m_) || !position_in_range(y_m, resolution_m_))
    throw Error(robot_position_error(x_m, y_m, resolution_m_));
  NewRegions out;
  const CellIndex n = size_;
  if (!placed_) {
    // Centre the window on the cell corner nearest to the robot.
    origin_x_ = static_cast<CellIndex>(std::llround(x_m / resolution_m_)) - n / 2;
    origin_y_ = static_cast<CellIndex>(std::llround(y_m / resolution_m_)) - n / 2;
    placed_ = true;
    out.ranges[0] = {origin_x_, origin_x_ + n, origin_y_, origin_y_ + n};
    out.count = 1;
    return out;
  }
  const CellIndex new_x = follow(origin_x_, cell_index(x_m, resolution_m_), size_);
  const CellIndex new_y = follow(origin_y_, cell_index(y_m, resolution_m_), size_);
  const CellIndex dx = new_x - origin_x_, dy = new_y - origin_y_;
  if (dx == 0 && dy == 0) return out;
  if (std::llabs(dx) >= n || std::llabs(dy) >= n) {
    out.ranges[out.count++] = {new_x, new_x + n, new_y, new_y + n};
  } else {
    // Entering columns over the full new height, then entering rows over the rest.
    CellRange cols{dx > 0 ? origin_x_ + n : new_x, dx > 0 ? new_x + n : origin_x_, new_y,
                   new_y + n};
    if (!cols.empty()) out.ranges[out.count++] = cols;
    CellRange rows{dx > 0 ? new_x : origin_x_, dx > 0 ? origin_x_ + n : new_x + n,
                   dy > 0 ? origin_y_ + n : new_y, dy > 0 ? new_y + n : origin_y_};
    if (!rows.empty()) out.ranges[out.count++] = rows;
  }
  origin_x_ = new_x;
  origin_y_ = new_y;
  return out;
}

}  // namespace hazmap
