#pragma once
// Internal to RollingLayer (and the update rules it is built with): not part of the hazmap API.
// Pass 2 of a layer's insertion for rules that merge each run straight into its cell
// (Kalman, the baseline): a chunk's runs of equal slots as a list of start indices and,
// for rules that fuse heights, each run's weighted sums.
//
// On a 1 cm layer a run is ~8 points. Walking runs point by point costs a mispredicted
// branch at every run end; here the list is made eight slots at a time without a branch
// (a compare, a bit mask and a table of its set bits), and each run is summed in two
// vectors of eight lanes (more only past 16 points), eight runs at a time, so that no
// branch, loop or call depends on where a run ends (below 17 points).

#include <vector>

#include "hazmap/map/point_chunk.hpp"

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

/// A chunk's runs in one layer, with the buffers sized once (PointChunk::kCapacity).
class ChunkRuns {
 public:
  /// Entries past kStride in every list: find_runs and run_height_sums store whole
  /// vectors of kRunLanes past the last run.
  static constexpr int kListPad = 8;
  static_assert(kListPad >= kRunLanes, "run lists are written kRunLanes entries at a time");

  /// `height_sums`: also allocate the per-run sums (Kalman).
  explicit ChunkRuns(bool height_sums)
      : starts_(PointChunk::kStride + kListPad, 0),
        slots_(PointChunk::kStride + kListPad, 0),
        sum_w_(height_sums ? PointChunk::kStride + kListPad : 0, 0.0f),
        sum_wz_(sum_w_.size(), 0.0f),
        first_z_(sum_w_.size(), 0.0f) {}

  /// Lists the runs of slot[0, count).
  void find(const int* slot, int count) {
    runs_ = find_runs(slot, count, starts_.data(), slots_.data());
  }
  /// Sums each run's weighted heights about the run's first height.
  void sum_heights(const float* w, const float* z) {
    run_height_sums(starts_.data(), runs_, w, z, sum_w_.data(), sum_wz_.data(), first_z_.data());
  }

  int size() const { return runs_; }
  int begin(int r) const { return starts_[r]; }
  int end(int r) const { return starts_[r + 1]; }
  int slot(int r) const { return slots_[r]; }  ///< the slot of run r's points
  const int* slots() const { return slots_.data(); }
  const int* starts() const { return starts_.data(); }
  const float* sums_w() const { return sum_w_.data(); }
  const float* sums_wz() const { return sum_wz_.data(); }
  const float* first_zs() const { return first_z_.data(); }
  float sum_w(int r) const { return sum_w_[r]; }
  float sum_wz(int r) const { return sum_wz_[r]; }  ///< relative to the run's first height
  float first_z(int r) const { return first_z_[r]; }

 private:
  std::vector<int> starts_, slots_;
  int runs_ = 0;
  std::vector<float> sum_w_, sum_wz_, first_z_;
};

}  // namespace hazmap
