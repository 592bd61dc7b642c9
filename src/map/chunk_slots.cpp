#include "hazmap/map/chunk_slots.hpp"

#include "hazmap/core/kernel.hpp"

namespace hazmap {
namespace {

// Restrict-qualified arrays and selects instead of && or early exits: this is what lets
// the loop vectorise. Inlined into each HAZMAP_KERNEL clone, so it is compiled per target.
// Float lanes (twice as many as double): the position error this adds is below 3e-5 cell
// on a 1000-cell window (0.3 um at 1 cm), the order of the float input's own at 5 m.
template <bool kPlane>
[[gnu::always_inline]] inline void locate(const float* __restrict px, const float* __restrict py,
                                          const float* __restrict lateral_var, int count,
                                          const WindowIndex& w, float gate_var,
                                          int* __restrict slot, float* __restrict cx,
                                          float* __restrict cy) {
  const int n = w.size;
  const float x0 = static_cast<float>(w.x0_m), y0 = static_cast<float>(w.y0_m);
  const float inv_r = static_cast<float>(w.inv_resolution), upper = static_cast<float>(n);
  const int wrap_x = w.wrap_x, wrap_y = w.wrap_y;
  for (int i = 0; i < count; ++i) {
    float fx = (px[i] - x0) * inv_r, fy = (py[i] - y0) * inv_r;
    // Clamped to [-1, n] so that the int conversion is defined (NaN lands on -1).
    fx = fx > -1.0f ? fx : -1.0f;
    fy = fy > -1.0f ? fy : -1.0f;
    fx = fx < upper ? fx : upper;
    fy = fy < upper ? fy : upper;
    // floor by truncation of f + 1 (exact for f >= -1).
    const int lx = static_cast<int>(fx + 1.0f) - 1, ly = static_cast<int>(fy + 1.0f) - 1;
    int sx = lx + wrap_x, sy = ly + wrap_y;
    sx -= sx >= n ? n : 0;
    sy -= sy >= n ? n : 0;
    bool keep = (static_cast<unsigned>(lx) < static_cast<unsigned>(n)) &
                (static_cast<unsigned>(ly) < static_cast<unsigned>(n));
    if constexpr (kPlane) {
      keep = keep & !(lateral_var[i] > gate_var);
      cx[i] = fx - static_cast<float>(lx) - 0.5f;
      cy[i] = fy - static_cast<float>(ly) - 0.5f;
    }
    slot[i] = keep ? sy * n + sx : -1;
  }
}

HAZMAP_KERNEL void locate_plane(const PointChunk& c, const WindowIndex& w, float gate_var,
                                int* slot, float* cx, float* cy) {
  locate<true>(c.x, c.y, c.lateral_var, c.size, w, gate_var, slot, cx, cy);
}

HAZMAP_KERNEL void locate_cells(const PointChunk& c, const WindowIndex& w, int* slot) {
  locate<false>(c.x, c.y, c.lateral_var, c.size, w, 0.0f, slot, nullptr, nullptr);
}

}  // namespace

void locate_points(const PointChunk& chunk, const WindowIndex& window, float gate_var, int* slot,
                   float* cx, float* cy) {
  if (cx && cy)
    locate_plane(chunk, window, gate_var, slot, cx, cy);
  else
    locate_cells(chunk, window, slot);
}

}  // namespace hazmap
