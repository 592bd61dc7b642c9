#pragma once
// How an update rule's points reach its cells: the one choice a rule makes about the
// layer's insertion path (Rule::kMerge; rules/update_rule.hpp lists the members each
// policy needs, docs/insertion.md draws the paths). A chunk's points come to the rule as
// runs: consecutive points in one cell.

namespace hazmap {

enum class MergePolicy {
  /// Each run's sums (run_sums) merge straight into its cell (merge_run), chunk by chunk.
  /// For rules whose cell does not depend on how a frame's points are grouped into
  /// merges (the baseline: the last point wins).
  per_run,
  /// per_run, with the chunk's run list prepared for the rule: the layer sums each run's
  /// weighted heights in SIMD lanes (ChunkRuns::sum_heights, weights()), and an unpooled
  /// layer hands the whole list to the rule (merge_chunk_runs), which merges several
  /// runs at once (Kalman: eight cells in vector lanes).
  per_chunk,
  /// Each run is added (add_run) to its cell's sums for the frame, and every touched
  /// cell merges once, at the frame's end (merge_frame): for caps and decays that act
  /// once per frame (CCM, OMG; SPEC 6.3-6.4).
  per_frame,
};

/// Whether runs merge into their cells while a chunk is inserted (per_run, per_chunk),
/// rather than once per frame.
constexpr bool merges_runs(MergePolicy p) { return p != MergePolicy::per_frame; }

}  // namespace hazmap
