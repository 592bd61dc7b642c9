#pragma once
// Index <-> position arithmetic shared by every grid (SPEC 1, 5). Cell i of a grid with
// resolution r covers [i r, (i + 1) r) in W, for every layer, so coarse and fine cells
// share borders.

#include <cmath>
#include <cstdint>

namespace hazmap {

using CellIndex = std::int64_t;  ///< global (unwrapped) cell index along one axis

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
