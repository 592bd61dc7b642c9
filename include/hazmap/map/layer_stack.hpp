#pragma once
// The multi-resolution map: layers finest first (SPEC 5), built once from the config.

#include <memory>
#include <vector>

#include "hazmap/io/config.hpp"
#include "hazmap/map/layer.hpp"

namespace hazmap {

/// Builds the layer for `layer` with its rule (one switch over the YAML rule name).
/// Throws Error naming the key for rules that are not available.
std::unique_ptr<Layer> make_layer(const LayerConfig& layer, const RulesConfig& rules,
                                  size_t index);

class LayerStack {
 public:
  LayerStack(const MapConfig& map, const RulesConfig& rules);

  /// Rolls every layer to the robot position and applies per-frame rule updates.
  void begin_frame(double robot_x_m, double robot_y_m);
  /// Inserts the frame's points (map.insertion = all_layers). Returns the number of
  /// point-into-layer updates.
  size_t insert(const PointCloud& cloud);

  size_t size() const { return layers_.size(); }
  const Layer& layer(size_t i) const { return *layers_[i]; }
  Layer& layer(size_t i) { return *layers_[i]; }

 private:
  std::vector<std::unique_ptr<Layer>> layers_;
};

}  // namespace hazmap
