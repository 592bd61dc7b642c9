#pragma once
// Pass 2 of a layer's insertion for rules that merge each run straight into its cell
// (Kalman, the baseline): a chunk's runs of equal slots as a list of start indices and,
// for rules that fuse heights, each run's weighted sums.
//
// On a 1 cm layer a run is ~8 points. Walking runs point by point costs a mispredicted
// branch at every run end; here the list is made eight slots at a time without a branch
// (a compare, a bit mask and a table of its set bits), and each run is summed in two
// vectors of eight lanes (more only past 16 points), eight runs at a time, so that no
// branch, loop or call depends on where a run ends.

#include <vector>

#include "hazmap/map/point_chunk.hpp"

namespace hazmap {

/// Start indices of the runs of equal slots in slot[0, count): starts[0] = 0, run r is
/// [starts[r], starts[r + 1]) and starts[runs] = count. Returns the number of runs.
/// `starts` holds at least count + 8 entries.
int find_runs(const int* slot, int count, int* starts);

/// The portable version of find_runs (what it runs where AVX2 is missing), for tests.
int find_runs_portable(const int* slot, int count, int* starts);

/// Weighted height sums of each run, heights relative to z0:
///   sum_w[r] = sum w,  sum_wz[r] = sum w (z - z0)   over run r of `starts`.
/// Summed in float lanes about the run's first height (as height_run), shifted to z0 in
/// double. `w` and `z` must be readable up to count + 15 (PointChunk::kPad).
void run_height_sums(const int* starts, int runs, const float* w, const float* z, double z0,
                     double* sum_w, double* sum_wz);

/// A chunk's runs in one layer, with the buffers sized once (PointChunk::kCapacity).
class ChunkRuns {
 public:
  /// `height_sums`: also allocate the per-run sums (Kalman).
  explicit ChunkRuns(bool height_sums)
      : starts_(PointChunk::kStride + 8, 0),
        sum_w_(height_sums ? PointChunk::kStride : 0, 0.0),
        sum_wz_(sum_w_.size(), 0.0) {}

  /// Lists the runs of slot[0, count).
  void find(const int* slot, int count) { runs_ = find_runs(slot, count, starts_.data()); }
  /// Sums each run's heights about the chunk's first height (0 if that is not finite).
  void sum_heights(const float* w, const float* z, int count);

  int size() const { return runs_; }
  int begin(int r) const { return starts_[r]; }
  int end(int r) const { return starts_[r + 1]; }
  double z0() const { return z0_; }
  double sum_w(int r) const { return sum_w_[r]; }
  double sum_wz(int r) const { return sum_wz_[r]; }  ///< relative to z0()

 private:
  std::vector<int> starts_;
  int runs_ = 0;
  double z0_ = 0;
  std::vector<double> sum_w_, sum_wz_;
};

}  // namespace hazmap
