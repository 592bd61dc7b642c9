#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// A layer's cells with their lazy ageing (lazy_ageing.hpp): each cell is stamped with the
// frame of its last merge, in the cell (Rule::kStampInCell) or beside it, and catches up
// on the frames since then (Rule::age) when it is next merged (catch_up) or read
// (current). Pooled layers are aged every frame instead (age_all: their covered cells are
// rebuilt from a prior every frame, which is not a merge), so they owe nothing.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hazmap/map/internal/lazy_ageing.hpp"

namespace hazmap {

template <class Rule>
class LayerCells {
 public:
  using Cell = typename Rule::Cell;
  using Config = typename Rule::Config;

  LayerCells(std::size_t count, const Config& config, bool pooled)
      : config_(config), cells_(count), stamps_(Rule::kStampInCell ? 0 : count, 0), pooled_(pooled) {}

  const Config& config() const { return config_; }
  bool pooled() const { return pooled_; }
  std::size_t size() const { return cells_.size(); }

  /// The frame merges are stamped with and ageing is owed up to.
  void set_frame(std::uint32_t frame) { frame_ = frame; }
  std::uint32_t frame() const { return frame_; }

  /// Raw storage, for the insertion loops (internal/layer_insertion.hpp).
  Cell* data() { return cells_.data(); }
  std::uint32_t* stamps() { return stamps_.data(); }
  Cell& raw(int slot) { return cells_[slot]; }
  const Cell& raw(int slot) const { return cells_[slot]; }

  /// The frame of a cell's last merge: in the cell (Rule::kStampInCell) or beside it.
  static std::uint32_t& stamp(Cell* cells, std::uint32_t* stamps, int slot) {
    if constexpr (Rule::kStampInCell)
      return cells[slot].stamp;
    else
      return stamps[slot];
  }
  std::uint32_t last_merge(int slot) const {
    if constexpr (Rule::kStampInCell)
      return cells_[slot].stamp;
    else
      return stamps_[slot];
  }

  /// Frames of Rule::age a cell last merged in frame `last` still owes in frame `now`:
  /// none on pooled layers (aged every frame), and none if frame numbers went backwards.
  static std::uint32_t owed_frames(std::uint32_t now, std::uint32_t last, bool pooled) {
    return pooled ? 0 : hazmap::owed_frames(now, last);
  }
  std::uint32_t owed_frames(int slot) const {
    return owed_frames(frame_, last_merge(slot), pooled_);
  }

  /// Applies the owed ageing before a merge (the merge then stamps the frame).
  void catch_up(int slot) {
    const std::uint32_t owed = owed_frames(slot);
    if (owed > 0) Rule::age(config_, cells_[slot], owed);
  }
  /// The cell as of this frame, for reading.
  Cell current(int slot) const {
    Cell c = cells_[slot];
    Rule::age(config_, c, owed_frames(slot));
    return c;
  }
  /// One frame of ageing for every cell (pooled layers, each frame).
  void age_all() {
    for (auto& cell : cells_) Rule::age(config_, cell, 1);
  }

 private:
  Config config_;
  std::uint32_t frame_ = 0;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> stamps_;  ///< each cell's last merge, unless in the cell
  bool pooled_;
};

}  // namespace hazmap
