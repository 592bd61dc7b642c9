#include "hazmap/map/layer_stack.hpp"

#include "hazmap/core/error.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/bananas.hpp"
#include "hazmap/rules/kalman.hpp"

namespace hazmap {

std::unique_ptr<Layer> make_layer(const LayerConfig& layer, const RulesConfig& rules,
                                  size_t index) {
  switch (layer.rule) {
    case RuleKind::bananas:
      return std::make_unique<RollingLayer<BananasRule>>(layer.size, layer.resolution_m,
                                                         BananasRule::Config{}, "bananas");
    case RuleKind::kalman:
      return std::make_unique<RollingLayer<KalmanRule>>(layer.size, layer.resolution_m,
                                                        rules.kalman, "kalman");
    case RuleKind::omg:
    case RuleKind::ccm:
      break;
  }
  throw Error("config: key 'map.layers." + std::to_string(index) + ".rule': rule '" +
              rule_name(layer.rule) + "' is not implemented yet (available: kalman, bananas)");
}

LayerStack::LayerStack(const MapConfig& map, const RulesConfig& rules) {
  if (map.insertion != "all_layers")
    throw Error("config: key 'map.insertion': '" + map.insertion +
                "' is not implemented yet (available: all_layers)");
  for (size_t i = 0; i < map.layers.size(); ++i)
    layers_.push_back(make_layer(map.layers[i], rules, i));
}

void LayerStack::begin_frame(double robot_x_m, double robot_y_m) {
  for (auto& layer : layers_) layer->begin_frame(robot_x_m, robot_y_m);
}

size_t LayerStack::insert(const PointCloud& cloud) {
  size_t updates = 0;
  for (auto& layer : layers_) updates += layer->insert(cloud);
  return updates;
}

}  // namespace hazmap
