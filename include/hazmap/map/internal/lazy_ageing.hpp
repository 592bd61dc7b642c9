#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// Lazy ageing: a cell is stamped with the frame of its last merge and catches up on the
// frames since then (Rule::age) when it is next merged or read, so that a frame does not
// pass over every cell.

#include <cstdint>

namespace hazmap {

/// Frames of ageing a cell stamped in frame `last` owes in frame `now`: none if frame
/// numbers went backwards.
inline std::uint32_t owed_frames(std::uint32_t now, std::uint32_t last) {
  return now > last ? now - last : 0;
}

}  // namespace hazmap
