#include "hazmap/hazard/mapper.hpp"

namespace hazmap {

Mapper::Mapper(const CoreConfig& config, bool pose_uncertainty)
    : map_(config.map, config.rules, config.hazard, pose_uncertainty),
      weighting_(config.rules.ccm.weighting),
      layer_ms_(config.map.layers.size(), 0.0),
      layer_gates_(config.map.layers.size()),
      hazards_(resolve_hazard_params(config), config.hazard.incremental) {}

std::size_t Mapper::insert(const MapPoints& points, double robot_x_m, double robot_y_m,
                           const PoseNoise& noise) {
  map_.begin_frame(robot_x_m, robot_y_m, noise);
  const std::size_t updates = map_.insert(points, layer_ms_.data());
  gated_ = {};
  for (std::size_t i = 0; i < map_.size(); ++i) {
    layer_gates_[i] = map_.gate_counts(i);
    gated_ += layer_gates_[i];
  }
  return updates;
}

const MapPoints& Mapper::assign_points(const PointCloud& cloud) {
  points_.assign(cloud, weighting_);
  return points_;
}

std::size_t Mapper::insert(const PointCloud& cloud, double robot_x_m, double robot_y_m,
                           const PoseNoise& noise) {
  return insert(assign_points(cloud), robot_x_m, robot_y_m, noise);
}

void Mapper::set_parallel(const ParallelFor* pool) {
  map_.set_parallel(pool);
  hazards_.set_parallel(pool);
}

void Mapper::classify(const SensorView* view) {
  hazards_.run(map_, view);
  terrain_.clear();
  if (!hazards_.layers().empty()) {
    const LayerGrids& finest = hazards_.layers().front().map;
    terrain_.add_layer(finest.height, finest.variance, finest.slope_x, finest.slope_y);
  }
}

}  // namespace hazmap
