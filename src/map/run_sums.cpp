#include "hazmap/map/internal/run_sums.hpp"

#include <cstdint>
#include <cstring>

#include "hazmap/map/internal/simd.hpp"

namespace hazmap {
namespace {

using simd::Mask4;
using simd::Vec4;
static_assert(sizeof(Vec4) / sizeof(float) == kRunPointLanes, "one Vec4 of points per step");

[[gnu::always_inline]] inline Vec4 load(const float* p) {
  Vec4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline Vec4 keep(Vec4 v, Mask4 live) {
  return reinterpret_cast<Vec4>(reinterpret_cast<Mask4>(v) & live);
}
/// occupancy_bit (map/moments.hpp) of four points: bit 4 j + i of sub-cell (i, j). Lanes
/// past a run's end may hold anything (the caller masks their bits); clamped both ways so
/// that no lane's shift leaves [0, 15].
[[gnu::always_inline]] inline Mask4 occupancy_bits(Vec4 x, Vec4 y) {
  const Vec4 lo{}, hi = {3.0f, 3.0f, 3.0f, 3.0f};
  Vec4 fi = (x + 0.5f) * 4.0f, fj = (y + 0.5f) * 4.0f;
  // Clamped as floats (NaN past the end: the comparisons keep it out of the shift).
  fi = fi > lo ? (fi < hi ? fi : hi) : lo;
  fj = fj > lo ? (fj < hi ? fj : hi) : lo;
  const Mask4 one = {1, 1, 1, 1};
  return one << (4 * __builtin_convertvector(fj, Mask4) + __builtin_convertvector(fi, Mask4));
}
[[gnu::always_inline]] inline double total(Vec4 v) {
  return (double(v[0]) + double(v[1])) + (double(v[2]) + double(v[3]));
}

}  // namespace

HAZMAP_KERNEL void add_plane_run(const RunPoints& run, double z_ref_m, FrameSums& sums,
                                 bool occupancy) {
  const float z0 = run.z[run.begin];
  WeightedSums<Vec4> lanes;
  Vec4 wv{};
  const Mask4 lane = {0, 1, 2, 3};
  if (run.w != nullptr) {
    for (int k = run.begin; k < run.end; k += kRunPointLanes) {
      // Lanes past the run's end are zeroed (their values may be anything, even NaN).
      const Mask4 live = (lane + k) < run.end;
      const Vec4 pw = keep(load(run.w + k), live);
      lanes.add(pw, keep(load(run.x + k), live), keep(load(run.y + k), live),
                keep(load(run.z + k) - z0, live));
      wv += pw * keep(load(run.var_z + k), live);
    }
  } else {
    // Unit weights: no weight array to read (its place in the memory traffic goes to
    // var_z) and no products by the weight.
    const Vec4 one = {1.0f, 1.0f, 1.0f, 1.0f};
    for (int k = run.begin; k < run.end; k += kRunPointLanes) {
      const Mask4 live = (lane + k) < run.end;
      lanes.add_unit(keep(one, live), keep(load(run.x + k), live), keep(load(run.y + k), live),
                     keep(load(run.z + k) - z0, live));
      wv += keep(load(run.var_z + k), live);
    }
  }
  const double W = total(lanes.w), X = total(lanes.x), Y = total(lanes.y), Z = total(lanes.z);
  const double d = double(z0) - z_ref_m;
  sums.w += W;
  sums.x += X;
  sums.y += Y;
  sums.z += Z + W * d;
  sums.xx += total(lanes.xx);
  sums.yy += total(lanes.yy);
  sums.xy += total(lanes.xy);
  sums.zz += total(lanes.zz) + d * (2.0 * Z + W * d);
  sums.xz += total(lanes.xz) + d * X;
  sums.yz += total(lanes.yz) + d * Y;
  sums.v += total(wv);
  sums.count += static_cast<std::uint32_t>(run.end - run.begin);
  if (!occupancy) return;
  // The sub-cells in a pass of their own, on the layers that keep them: in the loop above
  // they cost every CCM layer 14-18 % of its insertion (measured).
  Mask4 lanes_occupied{};
  for (int k = run.begin; k < run.end; k += kRunPointLanes) {
    const Mask4 live = (lane + k) < run.end;
    lanes_occupied |= occupancy_bits(load(run.x + k), load(run.y + k)) & live;
  }
  sums.occupied = static_cast<std::uint16_t>(sums.occupied | lanes_occupied[0] | lanes_occupied[1] |
                                             lanes_occupied[2] | lanes_occupied[3]);
}

HAZMAP_KERNEL HeightSums height_run(const RunPoints& run, double z_ref_m) {
  const float z0 = run.z[run.begin];
  Vec4 w{}, wz{}, wzz{};
  const Mask4 lane = {0, 1, 2, 3};
  for (int k = run.begin; k < run.end; k += kRunPointLanes) {
    const Mask4 live = (lane + k) < run.end;
    const Vec4 pw = keep(load(run.w + k), live);
    const Vec4 pz = keep(load(run.z + k) - z0, live);
    const Vec4 t = pw * pz;
    w += pw;
    wz += t;
    wzz += t * pz;
  }
  HeightSums s;
  const double W = total(w), WZ = total(wz), d = double(z0) - z_ref_m;
  s.w = W;
  s.wz = WZ + W * d;
  s.wzz = total(wzz) + d * (2.0 * WZ + W * d);
  return s;
}

}  // namespace hazmap
