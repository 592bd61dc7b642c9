// An update rule written outside the library (min_height_rule.hpp) run by the map core's
// own layer: RollingLayer<MinHeightRule> checks the rule's interface at compile time, then
// rolls, inserts and exports like any layer of the map. A 5 cm layer gets two points per
// cell, on the planes z = 0.2 m and z = 0.3 m; every known cell must publish the lower one
// with its variance. Exits non-zero otherwise.
#include <cmath>
#include <cstdio>

#include "hazmap/map/map_points.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "min_height_rule.hpp"

using namespace hazmap;
using custom_rule::MinHeightRule;

static_assert(check_update_rule<MinHeightRule>(), "MinHeightRule is an update rule");

int main() {
  RollingLayer<MinHeightRule> layer(/*size=*/32, /*resolution_m=*/0.05, MinHeightRule::Config{});
  layer.begin_frame(0.001, 0.001, /*frame=*/0);  // the window centred on the robot

  const float var_low = 4e-6f, var_high = 1e-6f;  // Sigma_zz of each plane's points [m^2]
  PointCloud cloud;
  for (double y = -0.7; y < 0.7; y += 0.05)
    for (double x = -0.7; x < 0.7; x += 0.05)
      for (const float z : {0.2f, 0.3f}) {  // the lower first: a last-point rule keeps 0.3
        Measurement m{};
        m.p_W = Eigen::Vector3f(float(x + 0.01), float(y + 0.02), z);
        m.cov_xx = m.cov_yy = 1e-6f;
        m.cov_zz = z < 0.25f ? var_low : var_high;
        cloud.push_back(m);
      }
  const std::size_t used = layer.insert(MapPoints(cloud));

  LayerGrids grids;
  layer.export_grids(grids, /*pose=*/nullptr, 0.001, 0.001);
  int known = 0, wrong = 0;
  for (int row = 0; row < grids.height.rows; ++row)
    for (int col = 0; col < grids.height.cols; ++col) {
      const float h = grids.height.at(row, col);
      if (std::isnan(h)) continue;
      ++known;
      if (h != 0.2f || grids.variance.at(row, col) != var_low) ++wrong;
    }
  std::printf("%s layer: %zu points used, %d cells known, %d not at the lower plane\n",
              layer.rule_name(), used, known, wrong);
  return known > 0 && wrong == 0 ? 0 : 1;
}
