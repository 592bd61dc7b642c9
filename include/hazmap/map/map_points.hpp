#pragma once
// A frame's points as the map reads them: one float array per field (structure of
// arrays), with the per-point weights derived once. Built from the Measurement records in
// one pass (the pipeline's points stage); the layer stack then reads it in chunks, so
// insertion touches at most 28 bytes per point instead of a 36-byte record per point and
// layer (each rule reads only the arrays it needs).

#include <vector>

#include "hazmap/core/core_config.hpp"
#include "hazmap/map/measurement.hpp"
#include "hazmap/map/point_chunk.hpp"

namespace hazmap {

/// CCM point weight from the world-frame covariance: constant 1 (the thesis' final
/// choice), trace 1 / trace(Sigma_W) [1/m^2] or det 1 / det(Sigma_W) [1/m^6]. Computed in
/// double: det Sigma_W of a near point is ~1e-24 m^6, whose cubic terms underflow float.
/// The covariance must be positive definite (validate() requires pointing and disparity
/// errors > 0 for `det`); a singular one gives an infinite weight.
float ccm_weight(CcmWeighting weighting, const Measurement& m);

class MapPoints {
 public:
  MapPoints() = default;
  explicit MapPoints(const PointCloud& cloud, CcmWeighting weighting = CcmWeighting::constant) {
    assign(cloud, weighting);
  }

  /// Converts a frame's points and derives their weights. Reuses its buffers: no
  /// allocation once a frame at least as large has been seen.
  void assign(const PointCloud& cloud, CcmWeighting weighting);

  /// Writable arrays for a producer that computes the fields itself (the points stage's
  /// direct path, PointCloudBuilder::build_map_points): each holds max_points (+ padding)
  /// floats. ccm_weight is only read when end_fill says the weights are not all 1.
  struct Fill {
    float *x, *y, *z, *inv_var_z, *var_z, *lateral_var, *ccm_weight;
  };
  /// Sizes every array for up to `max_points` points (no allocation once grown).
  Fill begin_fill(std::size_t max_points);
  /// The first `count` points written through begin_fill's arrays are the frame's.
  void end_fill(int count, bool unit_ccm_weight);

  int size() const { return size_; }
  /// Points [begin, begin + count), count <= PointChunk::kCapacity.
  PointChunk chunk(int begin, int count) const;
  /// Calls f(chunk) for consecutive chunks of kCapacity points (the last may be shorter).
  template <class F>
  void for_each_chunk(F&& f) const {
    for (int start = 0; start < size_; start += PointChunk::kCapacity)
      f(chunk(start, size_ - start < PointChunk::kCapacity ? size_ - start : PointChunk::kCapacity));
  }

 private:
  /// Writes 1 to ccm_weight_[0, size_) where it does not hold 1 already.
  void fill_unit_weights();

  std::vector<float> x_, y_, z_, inv_var_z_, ccm_weight_, lateral_var_, var_z_;  ///< size_ + kPad
  int size_ = 0;
  bool unit_ccm_weight_ = true;
  int unit_weights_ = 0;  ///< ccm_weight_[0, unit_weights_) hold 1

};

}  // namespace hazmap
