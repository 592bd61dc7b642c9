#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// Pass 2 of a layer's insertion for rules that merge each run straight into its cell
// (MergePolicy::per_run, per_chunk): the kernels behind ChunkRuns (rules/run_view.hpp),
// a chunk's runs of equal slots as a list of start indices and, for per_chunk rules
// (Kalman), each run's weighted height sums.
//
// On a 1 cm layer a run is ~8 points. Walking runs point by point costs a mispredicted
// branch at every run end; here the list is made eight slots at a time without a branch
// (a compare, a bit mask and a table of its set bits), and each run is summed in two
// vectors of eight lanes (more only past 16 points), eight runs at a time, so that no
// branch, loop or call depends on where a run ends (below 17 points).

#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/run_view.hpp"

namespace hazmap {

/// Lanes of the run kernels: find_runs (AVX2) compares eight slots at a time and stores
/// eight candidate starts; run_height_sums sums eight runs at a time and stores whole
/// vectors of eight sums.
constexpr int kRunLanes = 8;
/// Vectors of kRunLanes points run_height_sums loads per run without a loop (runs of up
/// to 16 points): it reads w and z that far past a run's first point.
constexpr int kRunSumVectors = 2;
static_assert(PointChunk::kPad >= kRunSumVectors * kRunLanes,
              "run_height_sums reads w and z up to count + 15: PointChunk::kPad must cover it");

/// Start indices of the runs of equal slots in slot[0, count): starts[0] = 0, run r is
/// [starts[r], starts[r + 1]) and starts[runs] = count, and run_slot[r] = slot[starts[r]]
/// (so that the merge loop reads the runs' slots in order). Returns the number of runs.
/// `starts` and `run_slot` hold at least count + kRunLanes entries.
int find_runs(const int* slot, int count, int* starts, int* run_slot);

/// The portable version of find_runs (what it runs where AVX2 is missing), for tests.
int find_runs_portable(const int* slot, int count, int* starts, int* run_slot);

/// Weighted height sums of each run, heights relative to the run's first height:
///   sum_w[r] = sum w,  sum_wz[r] = sum w (z - z[starts[r]])   over run r of `starts`,
/// and first_z[r] = z[starts[r]].
/// Float lanes: about the run's first height they keep ~1e-10 m of the run's mean.
/// `w` and `z` must be readable up to count + 15 (PointChunk::kPad); sum_w and sum_wz
/// hold runs + kRunLanes entries (results are stored as whole vectors), first_z the same.
void run_height_sums(const int* starts, int runs, const float* w, const float* z, float* sum_w,
                     float* sum_wz, float* first_z);

static_assert(ChunkRuns::kListPad >= kRunLanes,
              "run lists are written kRunLanes entries at a time: ChunkRuns::kListPad must cover it");

}  // namespace hazmap
