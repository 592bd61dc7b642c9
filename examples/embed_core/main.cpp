// The map core without the pipeline: one 5 cm Kalman layer fed a frame of synthetic points
// on the plane z = 0.2 m with a rock (10 cm wide, 15 cm tall) on it through the core's
// facade (hazard/mapper.hpp), then a cell's height, the layer's hazard classes and the
// planner's fused and footprint maps there. No OpenCV, no YAML: the core's config structs.
// Exits non-zero when the height is off by more than 1 mm or the planner maps do not show
// flat ground as traversable and the rock as a hazard.
#include <cmath>
#include <cstdio>

#include "hazmap/hazard/mapper.hpp"

using namespace hazmap;

int main() {
  CoreConfig config;  // map, rules and hazard settings with their defaults
  LayerConfig layer;
  layer.rule = RuleKind::kalman;
  layer.resolution_m = 0.05;
  layer.size = 64;
  config.map.layers.push_back(layer);

  PointCloud cloud;
  for (double y = -1.0; y < 1.0; y += 0.01)
    for (double x = -1.0; x < 1.0; x += 0.01) {
      const bool rock = x > 0.5 && x < 0.6 && std::abs(y) < 0.05;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), rock ? 0.35f : 0.2f);
      m.cov_xx = m.cov_yy = m.cov_zz = 1e-6f;  // 1 mm
      cloud.push_back(m);
    }

  Mapper mapper(config);
  mapper.insert(cloud, 0.001, 0.001);  // the robot at (0.001, 0.001): the window's centre
  mapper.classify();                   // each layer's hazards, the fused and footprint maps
  const LayerView& view = mapper.layer_views().front();
  const PlannerMaps& planner = mapper.planner_maps();

  const char* names[] = {"unknown", "traversable", "hazard"};
  auto class_at = [](const DenseGrid& g, double x, double y) {
    int row = 0, col = 0;
    g.cell_at(x, y, &row, &col);
    return static_cast<HazardClass>(g.at(row, col));
  };
  int row = 0, col = 0;
  view.map.height.cell_at(-0.5, 0.0, &row, &col);
  const float height = view.map.height.at(row, col);
  std::printf("height at (-0.5, 0): %.4f m (expected 0.2000), class %s\n", height,
              names[int(class_at(view.hazard, -0.5, 0.0))]);
  view.map.height.cell_at(0.55, 0.0, &row, &col);
  std::printf("rock at (0.55, 0): %.4f m, class %s\n", view.map.height.at(row, col),
              names[int(class_at(view.hazard, 0.55, 0.0))]);
  const HazardClass flat_fused = class_at(planner.fused, -0.5, 0.0);
  const HazardClass rock_fused = class_at(planner.fused, 0.55, 0.0);
  const HazardClass flat_footprint = class_at(planner.footprint, -0.5, 0.0);
  const HazardClass rock_footprint = class_at(planner.footprint, 0.55, 0.0);
  std::printf("fused: %s at (-0.5, 0), %s at the rock; footprint (rover centre): %s, %s\n",
              names[int(flat_fused)], names[int(rock_fused)], names[int(flat_footprint)],
              names[int(rock_footprint)]);
  const HazardClass traversable = HazardClass::traversable, hazard = HazardClass::hazard;
  const bool ok = std::abs(height - 0.2) <= 0.001 && flat_fused == traversable &&
                  rock_fused == hazard && flat_footprint == traversable && rock_footprint == hazard;
  return ok ? 0 : 1;
}
