#pragma once
// A slice of a frame's points as the layers read them: one float array per field
// (structure of arrays), so that the per-point index arithmetic runs in SIMD lanes. A
// view into MapPoints; the layer stack hands each slice to every layer in turn while it
// is in cache.

namespace hazmap {

struct PointChunk {
  static constexpr int kCapacity = 1024;
  /// Readable lanes after the last point, so that vector loops may load whole vectors.
  /// What each kernel needs of it is a static_assert in map/internal/ (chunk_slots.hpp,
  /// chunk_runs.hpp, run_sums.hpp).
  static constexpr int kPad = 16;
  static constexpr int kStride = kCapacity + kPad;

  const float* x = nullptr;  ///< world frame [m]
  const float* y = nullptr;
  const float* z = nullptr;
  const float* inv_var_z = nullptr;    ///< Kalman and OMG weight 1 / Sigma_zz
  const float* ccm_weight = nullptr;   ///< CCM weight (SPEC 4)
  bool unit_ccm_weight = false;        ///< every ccm_weight is 1 (constant weighting)
  const float* lateral_var = nullptr;  ///< major-axis variance of Sigma_xy: the SPEC 4 gate
  /// Sigma_zz [m^2] itself (not 1 / inv_var_z: exact, and no division per point): the
  /// baseline's variance, the CCM noise variance and the SPEC 4 consistency gate.
  const float* var_z = nullptr;
  int size = 0;                        ///< <= kCapacity; every array readable to size + kPad
};

}  // namespace hazmap
