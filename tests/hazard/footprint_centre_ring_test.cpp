// hazard.footprint_centre_ring (issue 34): the rover's wheels stand on the ring around its
// centre, so a cell under its body needs its own tests, not its own wheel ring. Real layer
// stack, real hazard stage, points generated on analytic ground seen up to x = 0.3 m.

#include <gtest/gtest.h>

#include "hazard/analytic_points.hpp"
#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {
namespace {

constexpr float kU = float(HazardClass::unknown), kT = float(HazardClass::traversable);
constexpr double kSeenTo = 0.3;  // m: no points beyond (the edge of what was measured)

/// One CCM 4 cm layer (h_min 3 cm, critical height 3 cm), 1.28 m window.
Config one_layer(bool centre_ring) {
  Config c;
  LayerConfig l;
  l.rule = RuleKind::ccm;
  l.resolution_m = 0.04;
  l.size = 32;
  c.map.layers.push_back(l);
  c.rules.ccm.max_weight = 1e6;
  c.hazard.footprint_centre_ring = centre_ring;
  return c;
}

using testing::Surface;

/// Points on `h` for x < kSeenTo (analytic_points.hpp), classified by a whole-pass
/// hazard stage.
struct Mapped {
  LayerStack stack;
  HazardStage stage;
  Mapped(const Config& config, const Surface& h)
      : stack(config.map, config.rules), stage(resolve_hazard_params(config), false) {
    stack.begin_frame(0.0, 0.0);
    stack.insert(MapPoints(
        testing::analytic_points(h, [](double x, double) { return x < kSeenTo; }, 5)));
    stage.run(stack);
  }
  static float at(const DenseGrid& g, double x, double y) {
    int row = 0, col = 0;
    EXPECT_TRUE(g.cell_at(x, y, &row, &col)) << x << ", " << y;
    return g.at(row, col);
  }
  float hazard(double x, double y) const { return at(stage.layers()[0].hazard, x, y); }
  float ring_only(double x, double y) const { return at(stage.layers()[0].ring_only, x, y); }
  float footprint(double x, double y) const { return at(stage.planner_maps().footprint, x, y); }
};

TEST(FootprintCentreRing, ABodyCellUnknownOnlyForItsRingIsClearAndTheCentreMustBeProven) {
  const Surface flat = [](double, double) { return 0.0; };
  const Mapped on(one_layer(true), flat), off(one_layer(false), flat);
  // 0.22 m: its ring reaches 0.37 m, beyond what was measured; every other test proved it.
  EXPECT_EQ(on.hazard(0.22, 0.02), kU);
  EXPECT_EQ(on.ring_only(0.22, 0.02), 1.0f);
  EXPECT_EQ(on.hazard(0.02, 0.02), kT);  // its ring lies on measured ground
  EXPECT_EQ(on.ring_only(0.02, 0.02), 0.0f);
  EXPECT_EQ(on.ring_only(0.5, 0.02), 0.0f);  // no points: not clear
  EXPECT_TRUE(off.stage.layers()[0].ring_only.values.empty());  // kept only with the key
  // A centre at 0.02 m: its body (15 cm and half a cell's diagonal) reaches 0.198 m,
  // cells whose rings are cut. Proven only with the key; hazards and maps otherwise alike.
  EXPECT_EQ(off.footprint(0.02, 0.02), kU);
  EXPECT_EQ(on.footprint(0.02, 0.02), kT);
  EXPECT_EQ(on.stage.planner_maps().fused.values, off.stage.planner_maps().fused.values);
  // A centre whose own ring is cut is not proven, however clear its body.
  EXPECT_EQ(on.footprint(0.18, 0.02), kU);
  // Beyond the measured ground the disc holds cells without points: unknown.
  EXPECT_EQ(on.footprint(0.3, 0.02), kU);
}

TEST(FootprintCentreRing, AStepOnACellEdgeKeepsBothCellsFromCountingAsClear) {
  // A 4 cm step exactly on the cell edge at x = 0.16 m: each cell is a level plane, so
  // only the comparison with the neighbour's plane shows the step.
  const Surface step = [](double x, double) { return x >= 0.16 ? 0.04 : 0.0; };
  const Mapped m(one_layer(true), step);
  int row = 0, col = 0, col_left = 0;
  ASSERT_TRUE(m.stage.layers()[0].hazard.cell_at(0.161, 0.02, &row, &col));
  ASSERT_TRUE(m.stage.layers()[0].hazard.cell_at(0.159, 0.02, &row, &col_left));
  ASSERT_EQ(col, col_left + 1);  // the step lies on the edge between two cells
  EXPECT_EQ(m.hazard(0.18, 0.02), kU);        // its ring is cut at 0.3 m
  EXPECT_EQ(m.ring_only(0.18, 0.02), 0.0f);   // but it stands 4 cm above its neighbour
  EXPECT_EQ(m.ring_only(0.26, 0.02), 1.0f);   // on the plateau, level with its neighbours
  // Every body disc that holds the step's upper edge stays unknown.
  for (double x = 0.0; x <= 0.1; x += 0.04) EXPECT_EQ(m.footprint(x, 0.02), kU) << x;
  // Far enough from the step, a centre on the ground is proven.
  EXPECT_EQ(m.footprint(-0.1, 0.02), kT);
}

}  // namespace
}  // namespace hazmap
