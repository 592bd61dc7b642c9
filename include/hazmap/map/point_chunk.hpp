#pragma once
// A slice of a frame's points as a structure of arrays. The layer stack converts each
// slice of the Measurement stream once and every layer reads it while it is in cache;
// plain float arrays let the compiler run the per-point index arithmetic in SIMD lanes.

#include "hazmap/map/measurement.hpp"

namespace hazmap {

struct PointChunk {
  static constexpr int kCapacity = 1024;
  /// Readable lanes after the last point, so that vector loops may load whole vectors.
  static constexpr int kPad = 16;
  static constexpr int kStride = kCapacity + kPad;

  alignas(64) float x[kStride];  ///< world frame [m]
  alignas(64) float y[kStride];
  alignas(64) float z[kStride];
  alignas(64) float inv_var_z[kStride];    ///< Kalman and OMG weight
  alignas(64) float ccm_weight[kStride];   ///< CCM weight
  alignas(64) float lateral_var[kStride];  ///< CCM gate
  int size = 0;

  PointChunk();
  /// Copies `count` <= kCapacity points.
  void fill(const Measurement* points, int count);
};

}  // namespace hazmap
