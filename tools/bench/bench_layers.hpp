#pragma once
// Layer stacks of the insertion benchmarks, written as (rule, resolution, size) lists.
// Header-only and limited to LayerConfig's rule, resolution_m and size, which every
// revision since ba7e030 has: tools/bench/compare/insertion_compare.cpp includes it too and
// is compiled against older libraries (tools/bench/compare.sh).

#include <tuple>
#include <vector>

#include "hazmap/map/layer_stack.hpp"

namespace hazmap::bench {

/// (rule, resolution [m], size [cells per side]) of one layer.
using LayerSpec = std::tuple<RuleKind, double, int>;

/// Appends one layer per spec to `map`, every other key at its default.
inline void add_layers(MapConfig& map, const std::vector<LayerSpec>& layers) {
  for (const auto& [rule, r, n] : layers) {
    LayerConfig l;
    l.rule = rule;
    l.resolution_m = r;
    l.size = n;
    map.layers.push_back(l);
  }
}

}  // namespace hazmap::bench
