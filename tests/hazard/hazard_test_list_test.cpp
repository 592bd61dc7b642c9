// The seam for hazard tests (issue 36): a family classifier runs a list of small test
// types (hazard_test.hpp). A test-only test added to each shipped list changes the
// classes exactly where its own evidence says so, in list order, and reaches as far as
// it declares; turned off, the list classifies as the shipped one does.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "hazmap/hazard/kernel_classifier.hpp"
#include "hazmap/hazard/plane_classifier.hpp"
#include "hazmap/map/layer_stack.hpp"

namespace hazmap {
namespace {

/// Test-only: a cell whose height stands more than `ceiling` above z = 0 is a hazard (an
/// absolute ceiling; no shipped test does this). Its one setting: here h_min, read from
/// the layer's parameters as a real test reads its key.
struct HeightCeiling {
  static bool enabled(const LayerHazardParams& p) { return p.k_sigma > 0; }
  explicit HeightCeiling(const LayerHazardParams& p) : ceiling_m(p.h_min_m) {}
  int reach_cells(const TestReach&) const { return 0; }
  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    ev.evidence(c.z, std::sqrt(double(c.grids.variance.at(c.row, c.col))), ceiling_m);
  }
  double ceiling_m;
};

/// Test-only: records the order tests run in, and reaches `Reach` cells.
std::vector<std::string>* g_ran = nullptr;
template <int Id, bool On, int Reach>
struct Recorder {
  static bool enabled(const LayerHazardParams&) { return On; }
  explicit Recorder(const LayerHazardParams&) {}
  int reach_cells(const TestReach&) const { return Reach; }
  template <class Cell>
  void add(const Cell&, Evidence&) const {
    if (g_ran) g_ran->push_back("test " + std::to_string(Id));
  }
};

CoreConfig one_layer(RuleKind rule, double r) {
  CoreConfig c;
  LayerConfig l;
  l.rule = rule;
  l.resolution_m = r;
  l.size = static_cast<int>(std::lround(1.2 / r));
  c.map.layers.push_back(l);
  c.rules.ccm.max_weight = 1e6;
  return c;
}

/// Ground at height z0 tilted 5 deg along x, with height noise, a 6 cm box on it and a
/// hole; the layer's export.
LayerGrids map_ground(const CoreConfig& config, double z0) {
  std::mt19937_64 rng(36);
  std::normal_distribution<double> noise(0.0, 0.001);
  const double tan5 = std::tan(5.0 * M_PI / 180.0);
  PointCloud cloud;
  for (double y = -0.5; y < 0.5; y += 0.004)
    for (double x = -0.5; x < 0.5; x += 0.004) {
      if (std::hypot(x + 0.2, y - 0.2) < 0.05) continue;
      const bool box = std::abs(x - 0.2) < 0.05 && std::abs(y) < 0.05;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), float(z0 + tan5 * x + (box ? 0.06 : 0.0) + noise(rng)));
      m.cov_xx = m.cov_yy = 1e-6f;
      m.cov_zz = 1e-6f;
      cloud.push_back(m);
    }
  LayerStack stack(config.map, config.rules);
  stack.begin_frame(0.001, 0.001);
  stack.insert(MapPoints(cloud));
  LayerGrids g;
  stack.export_layer(0, g);
  return g;
}

DenseGrid classify(HazardClassifier& c, const LayerGrids& g) {
  DenseGrid hazard;
  HazardDiagnostics diag;
  c.classify(g, hazard, diag);
  return hazard;
}

/// `few_points_apart`: the family runs cells with fewer than min_points points through
/// its other list (FewPointsTests), to which the ceiling was not added.
template <class Shipped, class Extended>
void expect_ceiling_adds_exactly_its_evidence(const CoreConfig& config, bool few_points_apart) {
  const LayerHazardParams p = resolve_hazard_params(config).layers[0];
  for (double z0 : {0.0, 0.25}) {
    SCOPED_TRACE("ground at " + std::to_string(z0) + " m");
    const LayerGrids g = map_ground(config, z0);
    Shipped shipped(p);
    Extended extended(p);
    const DenseGrid a = classify(shipped, g), b = classify(extended, g);
    ASSERT_EQ(a.rows, b.rows);
    int added = 0, traversable = 0;
    for (int row = 0; row < a.rows; ++row)
      for (int col = 0; col < a.cols; ++col) {
        const float z = g.height.at(row, col);
        // Independently: the ceiling's evidence, k sigma above h_min.
        const bool listed = !few_points_apart || double(g.count.at(row, col)) >= p.min_points;
        const bool over = listed && std::isfinite(z) &&
                          z - p.k_sigma * std::sqrt(double(g.variance.at(row, col))) > p.h_min_m;
        const float want = over ? static_cast<float>(HazardClass::hazard) : a.at(row, col);
        ASSERT_EQ(b.at(row, col), want) << "cell " << row << ", " << col << " z " << z;
        added += over && a.at(row, col) != static_cast<float>(HazardClass::hazard);
        traversable += a.at(row, col) == static_cast<float>(HazardClass::traversable);
      }
    // The terrain leaves the shipped tests cells to prove, and the ceiling turns many of
    // them over (at z0 = 0 only the box and the tilted ground's high side).
    EXPECT_GT(traversable, 100);
    EXPECT_GT(added, z0 > 0 ? 100 : 0);
    EXPECT_EQ(extended.reach_cells(), shipped.reach_cells());
  }
}

TEST(HazardTestList, AnAddedTestChangesExactlyTheCellsItsEvidenceNames) {
  {
    SCOPED_TRACE("piecewise constant, 1 cm Kalman");
    CoreConfig config = one_layer(RuleKind::kalman, 0.01);
    config.hazard.roughness = RoughnessStatistic::detrended;
    expect_ceiling_adds_exactly_its_evidence<
        PiecewiseConstantClassifier,
        KernelFamilyClassifier<HazardTests<KernelRoughness, KernelFace, RingSlope, RingStep,
                                           HeightCeiling>>>(config, false);
  }
  {
    SCOPED_TRACE("plane, 4 cm CCM");
    expect_ceiling_adds_exactly_its_evidence<
        PlaneClassifier,
        PlaneFamilyClassifier<HazardTests<PlaneRoughness, PlaneInclination, RingSlope, RingStep,
                                          HeightCeiling>,
                              FewPointsTests>>(one_layer(RuleKind::ccm, 0.04), true);
  }
}

TEST(HazardTestList, TestsRunInListOrderAndAnOffTestNeitherRunsNorReaches) {
  const CoreConfig config = one_layer(RuleKind::kalman, 0.01);
  const LayerHazardParams p = resolve_hazard_params(config).layers[0];
  const HazardTests<Recorder<1, true, 2>, Recorder<2, false, 40>, Recorder<3, true, 9>> tests(p);
  EXPECT_EQ(tests.reach_cells(TestReach{}), 9);
  std::vector<std::string> ran;
  g_ran = &ran;
  const LayerGrids g = map_ground(config, 0.0);
  const WheelRing ring(0.15, 3.0);
  const HazardDiagnostics diag;
  const int dr[WheelRing::kSamples] = {}, dc[WheelRing::kSamples] = {};
  KernelCell cell(g, diag, ring, 10, 10, dr, dc, 0.3);
  Evidence ev(3.0);
  tests.run(cell, ev);
  g_ran = nullptr;
  EXPECT_EQ(ran, (std::vector<std::string>{"test 1", "test 3"}));

  // In a family: the classifier reaches as far as its farthest enabled test.
  const PiecewiseConstantClassifier shipped(p);
  const KernelFamilyClassifier<HazardTests<KernelRoughness, RingStep, Recorder<4, true, 40>>> far(p);
  const KernelFamilyClassifier<HazardTests<KernelRoughness, RingStep, Recorder<5, false, 40>>> off(p);
  EXPECT_EQ(far.reach_cells(), 40);
  EXPECT_EQ(off.reach_cells(), shipped.reach_cells());
  EXPECT_LT(shipped.reach_cells(), 40);
}

}  // namespace
}  // namespace hazmap
