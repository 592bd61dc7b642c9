// The map core without the pipeline: one 5 cm Kalman layer, a frame of synthetic points on
// the plane z = 0.2 m with a rock (10 cm wide, 15 cm tall) on it, then a cell's height and
// two cells' hazard classes. Exits non-zero when the height is off by more than 1 mm.
#include <cmath>
#include <cstdio>

#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/map/map_points.hpp"

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

  LayerStack stack(config.map, config.rules, config.hazard);
  stack.begin_frame(0.001, 0.001);
  stack.insert(MapPoints(cloud));
  LayerGrids grids;
  stack.export_layer(0, grids);
  DenseGrid hazard;
  HazardDiagnostics diagnostics;
  const HazardParams params = resolve_hazard_params(config);
  make_hazard_classifier(params.layers[0])->classify(grids, hazard, diagnostics);

  const char* names[] = {"unknown", "traversable", "hazard"};
  int row = 0, col = 0;
  grids.height.cell_at(-0.5, 0.0, &row, &col);
  const float height = grids.height.at(row, col);
  std::printf("height at (-0.5, 0): %.4f m (expected 0.2000), class %s\n", height,
              names[int(hazard.at(row, col))]);
  grids.height.cell_at(0.55, 0.0, &row, &col);
  std::printf("rock at (0.55, 0): %.4f m, class %s\n", grids.height.at(row, col),
              names[int(hazard.at(row, col))]);
  return std::abs(height - 0.2) <= 0.001 ? 0 : 1;
}
