#pragma once
// Baseline rule (SPEC 6.1): the cell holds the height of the last point that fell in
// it. No fusion, no variance; the reference the other rules are measured against.

#include <cmath>
#include <limits>

namespace hazmap {

struct BananasRule {
  struct Config {};
  struct Cell {
    float height_m = std::numeric_limits<float>::quiet_NaN();
  };
  static bool known(const Cell& c) { return !std::isnan(c.height_m); }
  static void clear(Cell& c) { c = Cell{}; }
  static void update(const Config&, Cell& c, double z_m, double /*vm_m2*/) {
    c.height_m = static_cast<float>(z_m);
  }
  static void begin_frame(const Config&, Cell&) {}
  static float height(const Cell& c) { return c.height_m; }
  /// The baseline has no variance model.
  static float variance(const Cell&) { return std::numeric_limits<float>::quiet_NaN(); }
};

}  // namespace hazmap
