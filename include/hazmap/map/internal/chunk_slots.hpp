#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// Pass 1 of a layer's insertion: each point of a chunk -> its storage slot in the layer's
// ring buffer and its cell-centred position. Straight-line arithmetic in SIMD lanes: one
// multiply per axis (no division by the resolution), a floor, a bounds test and a
// conditional subtract for the ring wrap (no modulo, no table, no branch). Written with
// AVX2 intrinsics where the CPU has AVX2, else as plain loops the compiler vectorises.

#include "hazmap/map/point_chunk.hpp"

namespace hazmap {

/// Where a layer's window sits, in the form pass 1 needs.
struct WindowIndex {
  double x0_m = 0, y0_m = 0;   ///< lower-left corner of the window's first cell [m]
  double inv_resolution = 1;   ///< 1 / cell size [1/m]
  int size = 0;                ///< N: the window is N x N cells
  int wrap_x = 0, wrap_y = 0;  ///< storage column / row of the window's first cell
};

/// A point's slot when it is outside the window or gated. locate_points' AVX2 path writes
/// it by OR-ing an all-ones compare mask into the slot, so it must be all bits set.
constexpr int kNoSlot = -1;
static_assert(kNoSlot == ~0, "locate_points (AVX2) marks a dropped point with an all-ones mask");

/// Points per vector in locate_points' AVX2 path (eight int or float lanes). It loads x, y
/// (and lateral_var) and stores slot, cx, cy as whole vectors, up to the chunk's size
/// rounded up to kLocateLanes, so chunk arrays and the layer's kStride buffers must reach
/// that far.
constexpr int kLocateLanes = 8;
static_assert(PointChunk::kPad >= kLocateLanes - 1,
              "locate_points (AVX2) reads chunk arrays up to size rounded up to kLocateLanes");
static_assert((PointChunk::kCapacity + kLocateLanes - 1) / kLocateLanes * kLocateLanes <=
                  PointChunk::kStride,
              "locate_points (AVX2) writes up to size rounded up to kLocateLanes (< kStride)");

/// Fills slot[i] for the chunk's points: kNoSlot when outside the window or when the point's
/// lateral_var exceeds gate_var (SPEC 4 max_std_ratio; +infinity: no gate, and
/// lateral_var is not read). With cx and cy (plane rules) also the cell-centred position
/// in cell units. Returns how many points inside the window the gate dropped. The output
/// arrays hold at least chunk.size entries. Where the CPU has AVX2 and N < 2^15, with
/// intrinsics (integer index lanes); the output arrays then hold chunk.size rounded up to
/// kLocateLanes entries.
int locate_points(const PointChunk& chunk, const WindowIndex& window, float gate_var, int* slot,
                  float* cx, float* cy);

/// The version locate_points runs without AVX2 or for N >= 2^15, for tests.
int locate_points_portable(const PointChunk& chunk, const WindowIndex& window, float gate_var,
                           int* slot, float* cx, float* cy);

}  // namespace hazmap
