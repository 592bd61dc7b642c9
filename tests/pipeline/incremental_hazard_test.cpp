// SPEC 8.6: the incremental hazard stage gives the maps of a whole pass, cell for cell,
// in every frame, and re-classifies only what a frame can have changed.

#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/pipeline.hpp"
#include "hazmap/sim/simulate.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// Same geometry, and every value bit for bit except that any NaN equals any NaN.
::testing::AssertionResult identical(const DenseGrid& a, const DenseGrid& b) {
  if (a.rows != b.rows || a.cols != b.cols || a.center_x_m != b.center_x_m ||
      a.center_y_m != b.center_y_m || a.resolution_m != b.resolution_m)
    return ::testing::AssertionFailure() << "geometry differs";
  long differ = 0;
  int first = -1;
  for (size_t i = 0; i < a.values.size(); ++i) {
    const float x = a.values[i], y = b.values[i];
    const bool same = (std::isnan(x) && std::isnan(y)) || std::memcmp(&x, &y, sizeof x) == 0;
    if (!same && differ++ == 0) first = static_cast<int>(i);
  }
  if (differ == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << differ << " cells differ, first at row " << first / a.cols << " col " << first % a.cols
         << ": " << a.values[first] << " vs " << b.values[first];
}

/// A drive over rocks along a curving path, long steps so that every layer rolls, in x
/// and in y. Rendered once for every configuration.
class IncrementalHazards : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    sim::SimulationOptions sim;
    sim.scenario = "rocks";
    sim.seed = 1907;
    sim.frames = 7;
    sim.scale = 0.3;
    sim.step_m = 0.12;
    sim.path.kind = "spline";
    sim.path.waypoint_spacing_m = 0.5;
    sim.path.max_turn_deg = 60;
    sim::simulate_sequence(sim, *dir_ / "seq");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static testing::TempDir* dir_;
};
testing::TempDir* IncrementalHazards::dir_ = nullptr;

Config variant(const std::string& name) {
  if (name == "cadre_flight") return load_config(testing::source_dir() / "config/cadre_flight.yaml");
  if (name == "cadre_flight_static") {  // no time inflation: the Kalman layer goes incremental
    Config c = load_config(testing::source_dir() / "config/cadre_flight.yaml");
    c.rules.kalman.time_inflation_m2 = 0;
    return c;
  }
  if (name == "cadre_flight_pose") {  // pose uncertainty: every layer whole, planner incremental
    Config c = load_config(testing::source_dir() / "config/cadre_flight.yaml");
    c.pose_uncertainty.enabled = true;
    return c;
  }
  if (name == "thesis_ccm_fill") {  // CCM rings filled from the coarser CCM layer
    Config c = load_config(testing::source_dir() / "config/thesis_ccm.yaml");
    c.hazard.coarse_ring_fill = true;
    return c;
  }
  if (name == "cadre_flight_no_fill") {
    Config c = load_config(testing::source_dir() / "config/cadre_flight.yaml");
    c.hazard.coarse_ring_fill = false;
    return c;
  }
  if (name == "thesis_ccm_centre_ring") {  // footprint from the centre's ring (CCM only)
    Config c = load_config(testing::source_dir() / "config/thesis_ccm.yaml");
    c.hazard.footprint_centre_ring = true;
    return c;
  }
  if (name == "thesis_pwc_decay") {  // pooled OMG layers; decay scales weights only
    Config c = load_config(testing::source_dir() / "config/thesis_pwc.yaml");
    c.rules.omg.decay = 0.9;
    return c;
  }
  return load_config(testing::source_dir() / ("config/" + name + ".yaml"));
}

TEST_P(IncrementalHazards, EqualToAWholePassInEveryFrame) {
  Config whole_config = variant(GetParam());
  whole_config.hazard.incremental = false;
  Config incremental_config = whole_config;
  incremental_config.hazard.incremental = true;
  const Sequence seq = load_sequence(*dir_ / "seq");
  Pipeline whole(whole_config, seq.calibration), incremental(incremental_config, seq.calibration);
  const PoseNoise noise{1e-6, 1e-6, 1e-6, 1e-6};
  long classified = 0, cells = 0;
  for (size_t f = 0; f < seq.frames.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const cv::Mat left = read_image(seq.frames[f].left_path);
    const cv::Mat right = read_image(seq.frames[f].right_path);
    whole.process(left, right, seq.frames[f].pose.T_W_B, noise);
    incremental.process(left, right, seq.frames[f].pose.T_W_B, noise);
    for (size_t i = 0; i < whole.layers().size(); ++i) {
      SCOPED_TRACE("layer " + std::to_string(i));
      const LayerView& a = whole.layers()[i];
      const LayerView& b = incremental.layers()[i];
      EXPECT_TRUE(identical(a.hazard, b.hazard));
      EXPECT_TRUE(identical(a.map.height, b.map.height));
      EXPECT_TRUE(identical(a.map.variance, b.map.variance));
      EXPECT_TRUE(identical(a.map.evaluable, b.map.evaluable));
      EXPECT_TRUE(identical(a.map.slope_x, b.map.slope_x));
      EXPECT_TRUE(identical(a.map.roughness, b.map.roughness));
      EXPECT_TRUE(identical(a.diagnostics.kernel_range, b.diagnostics.kernel_range));
      EXPECT_TRUE(identical(a.diagnostics.kernel_sigma, b.diagnostics.kernel_sigma));
      EXPECT_TRUE(identical(a.diagnostics.kernel_fill, b.diagnostics.kernel_fill));
      EXPECT_TRUE(identical(a.ring_only, b.ring_only));
      if (f > 0) {
        classified += incremental.hazard_stage().classified(i).area();
        cells += long(a.hazard.rows) * a.hazard.cols;
      }
    }
    const PlannerMaps& a = whole.planner_maps();
    const PlannerMaps& b = incremental.planner_maps();
    EXPECT_TRUE(identical(a.fused, b.fused)) << "fused";
    EXPECT_TRUE(identical(a.clearance, b.clearance)) << "clearance";
    EXPECT_TRUE(identical(a.footprint, b.footprint)) << "footprint";
    EXPECT_TRUE(identical(a.clear, b.clear)) << "clear";
    EXPECT_TRUE(identical(a.hazard_distance, b.hazard_distance)) << "hazard distance";
  }
  // Something was left out, except where every layer's exports change every frame (pose
  // uncertainty; default.yaml's only layer is Kalman with time inflation).
  if (GetParam() == "cadre_flight_pose" || GetParam() == "default") {
    EXPECT_EQ(classified, cells);
  } else {
    EXPECT_LT(classified, cells);
  }
}

INSTANTIATE_TEST_SUITE_P(Configs, IncrementalHazards,
                         ::testing::Values("cadre_flight", "cadre_flight_static", "cadre_flight_no_fill",
                                           "thesis_ccm_fill", "thesis_ccm_centre_ring",
                                           "cadre_flight_pose", "thesis_pwc_decay", "thesis_ccm",
                                           "default"));

/// One layer and its hazard stage, fed one point per frame.
struct OnePointMap {
  explicit OnePointMap(LayerConfig layer, double kalman_inflation = 0.0) {
    config.map.layers = {layer};
    config.rules.kalman.time_inflation_m2 = kalman_inflation;
    stack = std::make_unique<LayerStack>(config.map, config.rules, config.hazard);
    stage = std::make_unique<HazardStage>(resolve_hazard_params(config), true);
  }
  /// A frame with the robot at the origin and one point at (x, y) (none if NaN).
  void frame(double x, double y) {
    stack->begin_frame(0.0, 0.0);
    PointCloud cloud;
    if (!std::isnan(x)) {
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), 0.01f);
      m.cov_xx = m.cov_yy = 1e-8f;
      m.cov_zz = 1e-6f;
      cloud.push_back(m);
    }
    stack->insert(MapPoints(cloud));
    stage->run(*stack);
  }
  /// Image row and column of the cell holding (x, y) on layer 0.
  void cell_of(double x, double y, int* row, int* col) const {
    ASSERT_TRUE(stage->layers()[0].hazard.cell_at(x, y, row, col));
  }
  Config config;
  std::unique_ptr<LayerStack> stack;
  std::unique_ptr<HazardStage> stage;
};

LayerConfig layer(RuleKind rule, double resolution, int size) {
  LayerConfig l;
  l.rule = rule;
  l.resolution_m = resolution;
  l.size = size;
  l.hazard.kernel = 7;
  return l;
}

TEST(IncrementalHazardsDirtyRegion, OneInsertedPointDirtiesItsCellGrownByTheReach) {
  struct Case {
    RuleKind rule;
    double resolution;
    int size;
    int reach;  // kernel / ring reach in cells
  };
  // Kalman 1 cm: the ring (15 cm = 15 cells, + 1 for a sample from a neighbour) reaches
  // beyond the 7-cell kernel. CCM 4 cm:
  // ceil(15 / 4) + 1 cells for the sub-cell ring samples, + 1 for a sample taken from a
  // neighbour of a cell that is not evaluable.
  for (const Case& c : {Case{RuleKind::kalman, 0.01, 128, 16}, Case{RuleKind::ccm, 0.04, 64, 6}}) {
    OnePointMap m(layer(c.rule, c.resolution, c.size));
    m.frame(0.2, 0.1);
    EXPECT_EQ(m.stage->classified(0).area(), long(c.size) * c.size);  // first frame: whole
    m.frame(0.33, -0.27);
    int row = 0, col = 0;
    m.cell_of(0.33, -0.27, &row, &col);
    // The cell, one more on each side (changed_cells' rounding margin), and the reach.
    const int g = 1 + c.reach;
    ASSERT_EQ(m.stage->classified(0).size(), 1);
    EXPECT_TRUE(m.stage->classified(0)[0] == (GridRect{row - g, row + g + 1, col - g, col + g + 1}))
        << "rule " << int(c.rule);
    // A frame without points or motion changes nothing, and re-classifies nothing.
    m.frame(std::nan(""), 0);
    EXPECT_TRUE(m.stage->classified(0).empty());
    EXPECT_TRUE(m.stage->fused_region().empty());
    EXPECT_TRUE(m.stage->footprint_region().empty());
  }
}

TEST(IncrementalHazardsDirtyRegion, TimeInflationMakesTheLayerWhole) {
  OnePointMap m(layer(RuleKind::kalman, 0.01, 64), 1e-6);
  m.frame(0.1, 0.1);
  m.frame(0.2, 0.1);
  EXPECT_EQ(m.stage->classified(0).area(), 64L * 64);
}

}  // namespace
}  // namespace hazmap
