#pragma once
// What an update rule (rules/update_rule.hpp) is handed of a chunk's points: runs, i.e.
// consecutive points that fall in the same cell (scan lines cross cells in runs: in the
// benchmark frame ~8 points per 1 cm cell, ~30 per 4 cm cell). The layer finds the runs;
// the rule sums and merges them.
//
//   RunPoints   one run's points (MergePolicy::per_frame rules: add_run)
//   ChunkRuns   a chunk's runs as a list, with per-run weighted height sums
//               (MergePolicy::per_run, per_chunk rules: run_sums, merge_chunk_runs)

#include <vector>

#include "hazmap/map/point_chunk.hpp"

namespace hazmap {

/// Points [begin, end) of a chunk: weights (null: all 1), cell-centred x and y in cell
/// units, heights [m], and height variances Sigma_zz [m^2] (plane runs only). Every array
/// is readable up to end + 3 (PointChunk::kPad), so that a rule may sum a run in vectors
/// of four lanes without a tail loop.
struct RunPoints {
  const float* w;
  const float* x;
  const float* y;
  const float* z;
  int begin;
  int end;
  const float* var_z = nullptr;
};

/// A chunk's runs in one layer, with the buffers sized once (PointChunk::kCapacity). The
/// layer fills it (find, sum_heights; map/internal/chunk_runs.hpp has the SIMD kernels);
/// a rule reads it: run r is points [begin(r), end(r)) of the chunk, all in slot(r).
class ChunkRuns {
 public:
  /// Entries past kStride in every list: the kernels store whole vectors of eight
  /// (kRunLanes, checked in internal/chunk_runs.hpp) past the last run.
  static constexpr int kListPad = 8;

  /// `height_sums`: also allocate the per-run sums (MergePolicy::per_chunk).
  explicit ChunkRuns(bool height_sums)
      : starts_(PointChunk::kStride + kListPad, 0),
        slots_(PointChunk::kStride + kListPad, 0),
        sum_w_(height_sums ? PointChunk::kStride + kListPad : 0, 0.0f),
        sum_wz_(sum_w_.size(), 0.0f),
        first_z_(sum_w_.size(), 0.0f) {}

  /// Lists the runs of slot[0, count) (the layer, each chunk).
  void find(const int* slot, int count);
  /// Sums each run's weighted heights about the run's first height (the layer, each
  /// chunk, MergePolicy::per_chunk).
  void sum_heights(const float* w, const float* z);

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
