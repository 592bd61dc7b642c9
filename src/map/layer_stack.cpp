#include "hazmap/map/layer_stack.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"
#include "hazmap/core/ticks.hpp"
#include "hazmap/map/internal/point_bounds.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/rule_registry.hpp"

namespace hazmap {

double gate_std_m(const LayerConfig& layer, const RulesConfig& rules) {
  const double ratio = layer.max_std_ratio.value_or(rules.ccm.max_std_ratio);
  return ratio > 0 ? ratio * layer.resolution_m / std::sqrt(12.0) : 0.0;
}

std::unique_ptr<Layer> make_layer(const MapConfig& map, const RulesConfig& rules,
                                  const HazardConfig& hazard, std::size_t index) {
  const LayerConfig& layer = map.layers[index];
  const bool pooled = map.insertion == Insertion::finest_then_pool && index > 0;
  const int n = layer.size;
  const double r = layer.resolution_m;
  const double gate = gate_std_m(layer, rules);
  if (static_cast<std::size_t>(layer.rule) >= Rules::size)
    throw Error("config: key 'map.layers." + std::to_string(index) + ".rule': unknown rule");
  return visit_rule(layer.rule, [&](auto tag) -> std::unique_ptr<Layer> {
    using Rule = typename decltype(tag)::type;
    using Entry = typename decltype(tag)::entry;
    auto config = rule_config<Entry>(rules, hazard);
    if constexpr (std::is_same_v<Rule, CcmRule>) config.occupancy = layer.hole_free_coverage > 0;
    return std::make_unique<RollingLayer<Rule>>(n, r, config, gate, pooled);
  });
}

std::unique_ptr<Layer> make_layer(const MapConfig& map, const RulesConfig& rules, std::size_t index) {
  return make_layer(map, rules, HazardConfig{}, index);
}

LayerStack::LayerStack(const MapConfig& map, const RulesConfig& rules, bool pose_uncertainty)
    : LayerStack(map, rules, HazardConfig{}, pose_uncertainty) {}

LayerStack::LayerStack(const MapConfig& map, const RulesConfig& rules, const HazardConfig& hazard,
                       bool pose_uncertainty)
    : pooling_(map.insertion == Insertion::finest_then_pool),
      track_pose_(pose_uncertainty) {
  for (std::size_t i = 0; i < map.layers.size(); ++i) layers_.push_back(make_layer(map, rules, hazard, i));
  pools_.resize(layers_.size());
  layer_ticks_.assign(layers_.size(), 0);
  if (pooling_)
    for (std::size_t i = 1; i < layers_.size(); ++i) {
      const auto n = static_cast<std::size_t>(map.layers[i].size);
      pools_[i].cells.assign(n * n, Moments{});
    }
}

void LayerStack::begin_frame(double robot_x_m, double robot_y_m, const PoseNoise& noise) {
  // Checked for every layer before any layer moves, so a rejected pose changes nothing.
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    const double r = layers_[i]->grid().resolution_m();
    if (!position_in_range(robot_x_m, r) || !position_in_range(robot_y_m, r))
      throw Error(robot_position_error(robot_x_m, robot_y_m, r) + " (layer " + std::to_string(i) +
                  ")");
  }
  if (started_) ++frame_;
  started_ = true;
  robot_x_m_ = robot_x_m;
  robot_y_m_ = robot_y_m;
  inserted_ = has_points_ = false;
  if (track_pose_) pose_.add_frame(frame_, noise);
  for (auto& layer : layers_) layer->begin_frame(robot_x_m, robot_y_m, frame_);
  if (pooling_)
    for (std::size_t i = 1; i < layers_.size(); ++i) layers_[i]->update_coverage(layers_[i - 1]->grid());
}

namespace {
/// LayerStack::insert's work for the layers `take(i)` selects: `lap(i)` is called after
/// each piece of layer i's work. `bounds` (if given) grows by every chunk's points.
template <class Take, class Lap>
std::size_t insert_layers(std::vector<std::unique_ptr<Layer>>& layers, std::vector<PoolGrid>& pools,
                          bool pooling, const MapPoints& points, PointBounds* bounds, Take&& take,
                          Lap&& lap) {
  // Each chunk is read by every layer while it is in cache. The first layer to read it
  // pays for bringing it in (~0.5-0.8 ns per point on the flight stack, measured), so the
  // coarsest layer, with the most room under its target, goes first and the 1 cm layer
  // last. A layer's state depends only on its own points: the order changes no result.
  std::size_t updates = 0;
  const std::size_t n = layers.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!take(i)) continue;
    layers[i]->begin_insert();
    lap(i);
  }
  points.for_each_chunk([&](const PointChunk& chunk) {
    // The bounding box (changed_cells) in the same loop: the chunk is read once from
    // memory, not once for the box and again for the layers.
    if (bounds) bounds->extend(chunk.x, chunk.y, chunk.size);
    for (std::size_t i = n; i-- > 0;) {
      if (!take(i)) continue;
      updates += layers[i]->insert_chunk(chunk);
      lap(i);
    }
  });
  for (std::size_t i = 0; i < n; ++i) {
    if (!take(i)) continue;
    layers[i]->end_insert();
    lap(i);
  }
  if (pooling) {
    // Fine to coarse, so that a layer's covered cells are rebuilt before it is pooled.
    for (std::size_t i = 1; i < n; ++i) {
      layers[i - 1]->pool_into(pools[i], *layers[i]);
      layers[i]->rebuild_covered(pools[i]);
      lap(i);
    }
  }
  return updates;
}

/// insert_layers' lap: adds the cycle-counter ticks since the previous lap to layer i's.
struct LayerLap {
  std::uint64_t* ticks;
  std::uint64_t last = read_ticks();
  void operator()(std::size_t i) {
    const std::uint64_t now = read_ticks();
    ticks[i] += now - last;
    last = now;
  }
};

/// Splits `ms` of wall time over the layers in proportion to their ticks (of `total`).
void share_ms(double ms, std::uint64_t total, const std::vector<std::uint64_t>& ticks,
              double* layer_ms) {
  for (std::size_t i = 0; i < ticks.size(); ++i)
    layer_ms[i] = total > 0 ? ms * static_cast<double>(ticks[i]) / static_cast<double>(total) : 0.0;
}
}  // namespace

void LayerStack::set_parallel(const ParallelFor* pool) {
  const std::size_t n = layers_.size();
  const int sets = pool ? static_cast<int>(std::min<std::size_t>(pool->threads(), n)) : 1;
  pool_ = sets > 1 && !pooling_ ? pool : nullptr;
  group_of_.assign(n, 0);
  by_time_.resize(n);
  group_load_.assign(static_cast<std::size_t>(sets), 0);
  group_updates_.assign(static_cast<std::size_t>(sets), 0);
}

std::size_t LayerStack::insert(const MapPoints& points, double* layer_ms) {
  // The points' bounding box: which cells this insert may change (changed_cells), grown
  // chunk by chunk in the insertion loop (internal/point_bounds.hpp).
  inserted_ = true;
  has_points_ = points.size() > 0;
  PointBounds bounds;
  auto keep_bounds = [&] {
    min_x_ = bounds.lo_x, max_x_ = bounds.hi_x, min_y_ = bounds.lo_y, max_y_ = bounds.hi_y;
  };
  auto all = [](std::size_t) { return true; };
  using Clock = std::chrono::steady_clock;
  if (pool_) {
    // Longest layer of the frame before to the least loaded set (the first frame, every
    // time 0: in turn).
    const std::size_t n = layers_.size(), sets = group_load_.size();
    // Insertion sort, stable (std::stable_sort may allocate; a stack has a few layers).
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t k = i;
      for (; k > 0 && layer_ticks_[static_cast<std::size_t>(by_time_[k - 1])] < layer_ticks_[i];
           --k)
        by_time_[k] = by_time_[k - 1];
      by_time_[k] = static_cast<int>(i);
    }
    std::fill(group_load_.begin(), group_load_.end(), 0);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = static_cast<std::size_t>(by_time_[k]);
      std::size_t lightest = 0;
      for (std::size_t g = 1; g < sets; ++g)
        if (group_load_[g] < group_load_[lightest]) lightest = g;
      group_of_[i] = static_cast<int>(lightest);
      group_load_[lightest] += std::max<std::uint64_t>(layer_ticks_[i], 1);
    }
    std::fill(layer_ticks_.begin(), layer_ticks_.end(), 0);
    const Clock::time_point start = Clock::now();
    const std::uint64_t start_ticks = read_ticks();
    parallel_for(pool_, static_cast<int>(sets), [&](int begin, int end) {
      for (int g = begin; g < end; ++g) {
        // Each set its layers: no two threads add to one layer's ticks.
        LayerLap lap{layer_ticks_.data()};
        group_updates_[static_cast<std::size_t>(g)] = insert_layers(
            layers_, pools_, false, points, g == 0 ? &bounds : nullptr,
            [&](std::size_t i) { return group_of_[i] == g; }, lap);
      }
    });
    const double ms = ms_since(start);
    std::size_t updates = 0;
    for (const std::size_t u : group_updates_) updates += u;
    if (layer_ms) share_ms(ms, read_ticks() - start_ticks, layer_ticks_, layer_ms);
    keep_bounds();
    return updates;
  }
  if (layer_ms == nullptr) {
    const std::size_t updates =
        insert_layers(layers_, pools_, pooling_, points, &bounds, all, [](std::size_t) {});
    keep_bounds();
    return updates;
  }
  std::fill(layer_ticks_.begin(), layer_ticks_.end(), 0);
  const Clock::time_point start = Clock::now();
  LayerLap lap{layer_ticks_.data()};
  const std::uint64_t start_ticks = lap.last;
  const std::size_t updates = insert_layers(layers_, pools_, pooling_, points, &bounds, all, lap);
  const double ms = ms_since(start);
  share_ms(ms, lap.last - start_ticks, layer_ticks_, layer_ms);
  keep_bounds();
  return updates;
}

CellRange LayerStack::changed_cells(std::size_t i) const {
  const RollingGrid& g = layers_[i]->grid();
  const CellRange window{g.origin_x(), g.origin_x() + g.size(), g.origin_y(), g.origin_y() + g.size()};
  auto cut = [&](CellRange r) {
    return CellRange{std::max(r.x0, window.x0), std::min(r.x1, window.x1),
                     std::max(r.y0, window.y0), std::min(r.y1, window.y1)};
  };
  CellRange changed;  // empty
  if (has_points_ && std::isfinite(min_x_ + max_x_ + min_y_ + max_y_)) {
    const double r = g.resolution_m();
    // One cell wider: the layers' own index arithmetic (chunk_slots) may round a point
    // on a cell border the other way.
    changed = cut({cell_index(min_x_, r) - 1, cell_index(max_x_, r) + 2, cell_index(min_y_, r) - 1,
                   cell_index(max_y_, r) + 2});
  }
  if (pooling_ && i > 0 && inserted_) {
    const RollingGrid& f = layers_[i - 1]->grid();
    const auto ratio = static_cast<CellIndex>(std::llround(g.resolution_m() / f.resolution_m()));
    auto down = [ratio](CellIndex a) {  // floor(a / ratio)
      return a >= 0 ? a / ratio : -((-a + ratio - 1) / ratio);
    };
    const CellRange covered = cut({down(f.origin_x()), down(f.origin_x() + f.size() - 1) + 1,
                                   down(f.origin_y()), down(f.origin_y() + f.size() - 1) + 1});
    if (changed.empty()) changed = covered;
    else if (!covered.empty())
      changed = {std::min(changed.x0, covered.x0), std::max(changed.x1, covered.x1),
                 std::min(changed.y0, covered.y0), std::max(changed.y1, covered.y1)};
  }
  return changed;
}

void LayerStack::export_layer(std::size_t i, LayerGrids& out, const SeenWhole* seen_whole) const {
  layers_[i]->export_grids(out, track_pose_ ? &pose_ : nullptr, robot_x_m_, robot_y_m_, seen_whole);
}

}  // namespace hazmap
