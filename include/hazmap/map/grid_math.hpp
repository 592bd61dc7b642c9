#pragma once
// Index <-> position arithmetic shared by every grid (SPEC 1, 5). Cell i of a grid with
// resolution r covers [i r, (i + 1) r) in W, for every layer, so coarse and fine cells
// share borders.

#include <cmath>
#include <cstdint>

namespace hazmap {

using CellIndex = std::int64_t;  ///< global (unwrapped) cell index along one axis

/// Largest layer side (cells): storage slots `wrap(iy) * N + wrap(ix)` are computed in
/// int, so N^2 must fit in an int (46341^2 does not). Checked by config validation.
constexpr int kMaxLayerSize = 46340;
static_assert(static_cast<std::int64_t>(kMaxLayerSize) * kMaxLayerSize <= INT32_MAX,
              "a layer's N * N cells must be addressable with int slots");

/// Layer resolution bounds (m), checked by config validation: below 0.1 mm a cell is
/// far finer than any stereo point's error; above 1 km a layer maps nothing a rover meets.
constexpr double kMinResolutionM = 1e-4;
constexpr double kMaxResolutionM = 1e3;

/// Largest |x / r| (cells) a robot position may have in a layer: keeps every global cell
/// index, window origin and origin + N far from int64 overflow (and llround/floor from
/// an out-of-range conversion). 2^30 cells is 107 km at 0.1 mm, 10 700 km at 1 cm.
constexpr double kMaxRobotCells = 1073741824.0;  // 2^30

/// Global index of the cell holding coordinate x (floor(x / r)).
inline CellIndex cell_index(double x_m, double resolution_m) {
  return static_cast<CellIndex>(std::floor(x_m / resolution_m));
}

/// W coordinate of the centre of cell i.
inline double cell_center(CellIndex i, double resolution_m) {
  return (static_cast<double>(i) + 0.5) * resolution_m;
}

/// Ring-buffer slot of global index i in a buffer of n cells: ((i mod n) + n) mod n.
inline int wrap_index(CellIndex i, int n) {
  const CellIndex m = i % n;
  return static_cast<int>(m < 0 ? m + n : m);
}

}  // namespace hazmap
