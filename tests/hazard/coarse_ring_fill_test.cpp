// hazard.coarse_ring_fill (issue 34): a fine layer's wheel-ring sample that the layer did
// not measure comes from the next coarser CCM layer's plane, where that layer measured
// the ground; ground no layer measured stays unknown. Real layer stack, real hazard stage,
// points generated on analytic ground.

#include <gtest/gtest.h>

#include <cmath>

#include "hazard/analytic_points.hpp"
#include "hazmap/hazard/coarse_ring_fill.hpp"
#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {
namespace {

constexpr double kRadius = 0.15;           // wheelbase 0.3 m / 2
constexpr double kXc = 0.305, kYc = 0.105;  // the 1 cm cell whose ring is examined

/// Kalman 1 cm (the ring's layer) over CCM 4 cm (the fill's), 1.28 m windows.
Config two_layers(bool fill) {
  Config c;
  for (auto [rule, r, size] : {std::tuple{RuleKind::kalman, 0.01, 128}, std::tuple{RuleKind::ccm, 0.04, 32}}) {
    LayerConfig l;
    l.rule = rule;
    l.resolution_m = r;
    l.size = size;
    l.hazard.kernel = r < 0.02 ? 7 : 5;
    c.map.layers.push_back(l);
  }
  c.rules.ccm.max_weight = 1e6;
  c.hazard.coarse_ring_fill = fill;
  return c;
}

using testing::Surface;
using testing::Visible;

/// Points on `h` where `visible` (analytic_points.hpp), mapped and classified by a
/// whole-pass hazard stage.
struct Mapped {
  LayerStack stack;
  HazardStage stage;
  Mapped(const Config& config, const Surface& h, const Visible& visible)
      : stack(config.map, config.rules), stage(resolve_hazard_params(config), false) {
    stack.begin_frame(0.001, 0.001);
    stack.insert(MapPoints(testing::analytic_points(h, visible, 11)));
    stage.run(stack);
  }
  float fine_class_at(double x, double y) const {
    int row = 0, col = 0;
    const DenseGrid& h = stage.layers()[0].hazard;
    EXPECT_TRUE(h.cell_at(x, y, &row, &col));
    return h.at(row, col);
  }
};

/// True outside squares of half-width `half` around the cells holding ring samples 0-2
/// of the cell at (kXc, kYc): with 3 x 3 cells gone no neighbour stands in, and without
/// hazard.partial_ring_proof (the default) a ring with a sample missing cannot prove.
/// (Sample 3's 4 cm cell would lose its plane to such a hole.)
Visible without_ring_samples(double half) {
  return [=](double x, double y) {
    for (int k = 0; k < 3; ++k) {
      const double sx = kXc + kRadius * std::cos(k * M_PI / 4), sy = kYc + kRadius * std::sin(k * M_PI / 4);
      const double cx = std::floor(sx / 0.01) * 0.01 + 0.005, cy = std::floor(sy / 0.01) * 0.01 + 0.005;
      if (std::abs(x - cx) < half && std::abs(y - cy) < half) return false;
    }
    return true;
  };
}

TEST(CoarseRingFill, SamplesTheCoarsePlaneWithItsVarianceAndNothingUnmeasured) {
  // A 10 deg plane: the fill's height at a point is the 4 cm plane there (not the cell's
  // mean), within the points' noise; its variance covers the residuals about the plane.
  const double t = std::tan(10.0 * M_PI / 180.0);
  const Surface plane = [=](double x, double y) { return 0.02 + t * x - 0.5 * t * y; };
  const Mapped m(two_layers(true), plane, [](double x, double) { return x < 0.3; });
  const LayerHazardParams coarse = resolve_hazard_params(two_layers(true)).layers[1];
  CoarseRingFill fill(coarse);
  EXPECT_FALSE(fill.at(0.1, 0.1).known);  // no grids yet
  fill.set_grids(&m.stage.layers()[1].map);
  const LayerGrids& g = m.stage.layers()[1].map;
  for (auto [x, y] : {std::pair{0.013, -0.21}, std::pair{-0.37, 0.05}, std::pair{0.25, 0.31}}) {
    const RingSample s = fill.at(x, y);
    ASSERT_TRUE(s.exact) << x << ", " << y;
    EXPECT_NEAR(s.z_m, plane(x, y), 0.001) << x << ", " << y;  // 2 sigma of the noise
    int row = 0, col = 0;
    ASSERT_TRUE(g.height.cell_at(x, y, &row, &col));
    EXPECT_GE(s.var_m2, double(g.roughness.at(row, col)));
    EXPECT_LT(s.var_m2, 4 * 0.0005 * 0.0005);  // a few times the noise variance
  }
  EXPECT_FALSE(fill.at(0.45, 0.0).known);  // never seen: x >= 0.3
  EXPECT_FALSE(fill.at(5.0, 0.0).known);   // off the layer
}

TEST(CoarseRingFill, RingSamplesTheFineLayerMissedAreProvenFromTheCoarsePlaneOnlyWithTheFill) {
  const Surface flat = [](double, double) { return 0.0; };
  // 3 x 3 cm holes: the 4 cm cells around them keep their planes.
  const Visible holes = without_ring_samples(0.015);
  EXPECT_EQ(Mapped(two_layers(false), flat, holes).fine_class_at(kXc, kYc), float(HazardClass::unknown));
  EXPECT_EQ(Mapped(two_layers(true), flat, holes).fine_class_at(kXc, kYc), float(HazardClass::traversable));
  // Unseen by every layer (12 cm squares: no 4 cm plane there either): still unknown.
  EXPECT_EQ(Mapped(two_layers(true), flat, without_ring_samples(0.06)).fine_class_at(kXc, kYc),
            float(HazardClass::unknown));
}

TEST(CoarseRingFill, AStepUnderTheFilledSamplesIsStillAStep) {
  // The cell stands 5 cm above ground (a table-top 4 x 4 cm wide; the 1 cm Kalman layer's
  // h_min is below that): with the samples the fine layer missed filled from the coarse
  // planes of the ground, the ring shows the step: a hazard, not a proof.
  const Surface table = [](double x, double y) {
    return std::abs(x - kXc) < 0.02 && std::abs(y - kYc) < 0.02 ? 0.05 : 0.0;
  };
  const Mapped m(two_layers(true), table, without_ring_samples(0.015));
  EXPECT_EQ(m.fine_class_at(kXc, kYc), float(HazardClass::hazard));
}

}  // namespace
}  // namespace hazmap
