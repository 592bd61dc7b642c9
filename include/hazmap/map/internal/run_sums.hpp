#pragma once
// Used by RollingLayer's insertion and by the built-in rules, whose public types hold it
// (rules/omg.hpp, ccm.hpp, kalman.hpp): visible through them; a custom rule need not use it.
// Sums of one run: consecutive points of a chunk that fall in the same cell. Scan lines
// cross cells in runs (in the benchmark frame ~8 points per 1 cm cell, ~30 per 4 cm
// cell), so a layer finds a run's cell once and sums the run in registers.
//
// The plane sums run four points per step in float vector lanes. Heights are taken
// relative to the run's first point, so squares of nearby heights do not cancel in float;
// x and y are cell-centred (|x| <= 1/2 cell). The run's sums are shifted once, in double,
// to the accumulator's reference height:
//   z' = z + W d,  zz' = zz + 2 d z + W d^2,  xz' = xz + d x,  yz' = yz + d y.

#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/run_view.hpp"

namespace hazmap {

/// Points per step of add_plane_run and height_run (four float lanes): they load whole
/// vectors, past a run's end up to end + 3.
constexpr int kRunPointLanes = 4;
static_assert(PointChunk::kPad >= kRunPointLanes,
              "add_plane_run / height_run read a chunk's arrays up to end + 3");

/// Adds the run's raw weighted sums to `sums`, whose heights are relative to `z_ref_m`,
/// and sum w var_z to sums.v; with `occupancy`, the points' sub-cells to sums.occupied
/// (occupancy_bit, map/moments.hpp).
void add_plane_run(const RunPoints& run, double z_ref_m, FrameSums& sums, bool occupancy = false);

/// Weighted height sums of a run (w, x and y unused): sum w, sum w z, sum w z^2 with z
/// relative to `z_ref_m`, summed in float lanes about the run's first height like
/// add_plane_run.
struct HeightSums {
  double w = 0, wz = 0, wzz = 0;
};
HeightSums height_run(const RunPoints& run, double z_ref_m);

}  // namespace hazmap
