#include "hazmap/map/layer_stack.hpp"

#include <cmath>

#include "hazmap/core/error.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/bananas.hpp"
#include "hazmap/rules/ccm.hpp"
#include "hazmap/rules/kalman.hpp"
#include "hazmap/rules/omg.hpp"

namespace hazmap {

CcmWeighting ccm_weighting(const CcmConfig& ccm) {
  if (ccm.weighting == "trace") return CcmWeighting::trace;
  if (ccm.weighting == "det") return CcmWeighting::det;
  return CcmWeighting::constant;
}

std::unique_ptr<Layer> make_layer(const MapConfig& map, const RulesConfig& rules, std::size_t index) {
  const LayerConfig& layer = map.layers[index];
  const bool pooled = map.insertion == "finest_then_pool" && index > 0;
  const int n = layer.size;
  const double r = layer.resolution_m;
  switch (layer.rule) {
    case RuleKind::bananas:
      return std::make_unique<RollingLayer<BananasRule>>(n, r, BananasRule::Config{}, 0.0, pooled);
    case RuleKind::kalman:
      return std::make_unique<RollingLayer<KalmanRule>>(n, r, rules.kalman, 0.0, pooled);
    case RuleKind::omg:
      return std::make_unique<RollingLayer<OmgRule>>(
          n, r, OmgRule::Config{rules.omg.max_weight, rules.omg.decay}, 0.0, pooled);
    case RuleKind::ccm: {
      const CcmRule::Config cfg{rules.ccm.max_weight, rules.ccm.min_points, rules.ccm.min_coverage,
                                rules.ccm.full_plane};
      // SPEC 4: drop points whose lateral std exceeds max_std_ratio * r / sqrt(12).
      const double gate = rules.ccm.max_std_ratio * r / std::sqrt(12.0);
      return std::make_unique<RollingLayer<CcmRule>>(n, r, cfg, gate, pooled);
    }
  }
  throw Error("config: key 'map.layers." + std::to_string(index) + ".rule': unknown rule");
}

LayerStack::LayerStack(const MapConfig& map, const RulesConfig& rules, bool pose_uncertainty)
    : pooling_(map.insertion == "finest_then_pool"),
      track_pose_(pose_uncertainty) {
  for (std::size_t i = 0; i < map.layers.size(); ++i) layers_.push_back(make_layer(map, rules, i));
  pools_.resize(layers_.size());
  if (pooling_)
    for (std::size_t i = 1; i < layers_.size(); ++i) {
      const auto n = static_cast<std::size_t>(map.layers[i].size);
      pools_[i].cells.assign(n * n, Moments{});
    }
}

void LayerStack::begin_frame(double robot_x_m, double robot_y_m, const PoseNoise& noise) {
  if (started_) ++frame_;
  started_ = true;
  robot_x_m_ = robot_x_m;
  robot_y_m_ = robot_y_m;
  if (track_pose_) pose_.add_frame(frame_, noise);
  for (auto& layer : layers_) layer->begin_frame(robot_x_m, robot_y_m, frame_);
  if (pooling_)
    for (std::size_t i = 1; i < layers_.size(); ++i) layers_[i]->update_coverage(layers_[i - 1]->grid());
}

std::size_t LayerStack::insert(const MapPoints& points) {
  // Each chunk is read by every layer while it is in cache.
  std::size_t updates = 0;
  for (auto& layer : layers_) layer->begin_insert();
  points.for_each_chunk([&](const PointChunk& chunk) {
    for (auto& layer : layers_) updates += layer->insert_chunk(chunk);
  });
  for (auto& layer : layers_) layer->end_insert();
  if (pooling_) {
    // Fine to coarse, so that a layer's covered cells are rebuilt before it is pooled.
    for (std::size_t i = 1; i < layers_.size(); ++i) {
      layers_[i - 1]->pool_into(pools_[i], *layers_[i]);
      layers_[i]->rebuild_covered(pools_[i]);
    }
  }
  return updates;
}

void LayerStack::export_layer(std::size_t i, LayerGrids& out) const {
  layers_[i]->export_grids(out, track_pose_ ? &pose_ : nullptr, robot_x_m_, robot_y_m_);
}

}  // namespace hazmap
