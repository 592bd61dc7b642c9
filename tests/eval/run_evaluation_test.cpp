// hazmap evaluate on runs whose maps are built straight from the ground truth: the
// answers are known exactly (SPEC 10 acceptance).

#include "hazmap/eval/run_evaluation.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "eval/oracle_run.hpp"
#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap::eval {
namespace {

using hazmap::testing::TempDir;
using hazmap::testing::TestWorld;

constexpr double kPixelArea = 1e-4;         // 1 cm ground-truth pixels [m^2]
constexpr double kAreaTolerance = 1e-9;     // m^2: areas are whole pixel counts
constexpr double kFloatHeightTol = 2e-6;    // m: heights pass through float JDEMs

// Expected RMS of a piecewise-constant cell of k x k pixels of size p on the plane
// z = a x + b y: the pixel offsets from the cell centre are uniform on (i + 1/2) p - kp/2,
// variance p^2 (k^2 - 1) / 12 per axis.
double plane_discretisation_rms(double a, double b, double p, int k) {
  return std::sqrt((a * a + b * b) * p * p * (k * k - 1) / 12.0);
}

TestWorld rocky_world() {
  TestWorld w;
  w.rocks = {{0.6, 0.3, 0.10}, {1.3, -0.35, 0.12}, {1.2, 0.45, 0.07}};
  return w;
}

struct Oracle {
  TempDir dir;
  std::filesystem::path seq = dir / "seq";
  std::filesystem::path run = dir / "run";
  Config config = hazmap::testing::oracle_config();
  std::vector<std::string> frames = {"000000", "000001"};

  // Layers for one frame in the world frame, centred on (0.96, 0).
  std::vector<hazmap::testing::OracleLayer> layers(const TestWorld& w) const {
    return {hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
            hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)};
  }
  void write(const TestWorld& w, const std::vector<std::vector<hazmap::testing::OracleLayer>>& per_frame) {
    hazmap::testing::write_ground_truth(seq, w);
    hazmap::testing::write_poses(seq / "poses.txt", frames, {{0.0, 0.0}, {0.04, 0.0}});
    hazmap::testing::write_oracle_run(run, config, frames, per_frame);
  }
  RunEvaluation evaluate() const {
    EvaluationOptions o;
    o.run_dir = run;
    o.sequence_dir = seq;
    return evaluate_run(o);
  }
};

TEST(RunEvaluation, MapFromGroundTruthHasDiscretisationRmsAndNoMissedHazard) {
  Oracle t;
  const TestWorld w;  // plane only: every pixel scores height
  const auto layers = t.layers(w);
  t.write(w, {layers, layers});
  const RunEvaluation ev = t.evaluate();

  ASSERT_EQ(ev.layers.size(), 3u);  // L0 ccm, L1 kalman, fused
  EXPECT_EQ(ev.layers[0].rule, "ccm");
  EXPECT_DOUBLE_EQ(ev.layers[0].h_min_m, 0.03);
  EXPECT_EQ(ev.layers[1].h_min_source, "roughness threshold");
  EXPECT_DOUBLE_EQ(ev.layers[1].h_min_m, 0.05);
  ASSERT_EQ(ev.frames, t.frames);
  const LayerMetrics ccm = derive_metrics(ev.pooled[0]);
  const LayerMetrics pwc = derive_metrics(ev.pooled[1]);
  // The CCM oracle carries the exact plane: sub-cell queries reproduce the ground truth.
  EXPECT_LT(ccm.height_rms_m, kFloatHeightTol);
  // The piecewise-constant oracle is the block average: RMS is the discretisation error.
  EXPECT_NEAR(pwc.height_rms_m, plane_discretisation_rms(w.a, w.b, 0.01, 8), kFloatHeightTol);
  // 1.6 m x 1.6 m windows, all known, two frames.
  EXPECT_NEAR(ccm.extent_area_m2, 2 * 1.6 * 1.6, kAreaTolerance);
  EXPECT_DOUBLE_EQ(ccm.unknown_fraction, 0.0);
  EXPECT_EQ(ccm.missed_area_m2, 0.0);
  EXPECT_EQ(ccm.false_alarm_area_m2, 0.0);
  EXPECT_EQ(ccm.variance_violation, 0.0);  // |e| < 5.3 mm < 3 sigma = 30 mm
  EXPECT_TRUE(std::isnan(ccm.missed_of_hazard));  // no obstacle at all

  for (const char* f : {"metrics.csv", "summary.csv", "metrics.json", "metrics_over_time.png",
                        "errors_000001.png", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(t.run / "eval" / f)) << f;
  // metrics.csv: header + one row per frame and layer.
  std::ifstream csv(t.run / "eval" / "metrics.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 1 + 2 * 3);
}

TEST(RunEvaluation, DeletedRockIsMissedByExactlyItsArea) {
  Oracle t;
  const TestWorld w = rocky_world();
  const auto good = t.layers(w);
  auto bad = good;
  // Delete rock 1 (r = 12 cm) from the CCM layer: every cell near it says traversable.
  hazmap::testing::delete_rock(bad[0], w.rocks[1].x_m, w.rocks[1].y_m, w.rocks[1].radius_m + 0.08);
  t.write(w, {good, bad});
  const RunEvaluation ev = t.evaluate();

  const LayerMetrics first = derive_metrics(ev.sums[0][0]);
  const LayerMetrics second = derive_metrics(ev.sums[1][0]);
  EXPECT_EQ(first.missed_area_m2, 0.0);
  const double rock_area = w.rock_pixels_at_least(1, 0.03) * kPixelArea;
  ASSERT_GT(rock_area, 0.03);  // pi (0.12^2 - 0.03^2) = 0.0424 m^2
  EXPECT_NEAR(second.missed_area_m2, rock_area, kAreaTolerance);
  // All three rocks are inside the window: the missed share of obstacle area is rock 1's.
  double all_rocks = 0;
  for (size_t k = 0; k < w.rocks.size(); ++k) all_rocks += w.rock_pixels_at_least(k, 0.03) * kPixelArea;
  EXPECT_NEAR(second.gt_hazard_known_area_m2, all_rocks, kAreaTolerance);
  EXPECT_NEAR(second.missed_of_hazard, rock_area / all_rocks, 1e-12);
  EXPECT_NEAR(second.missed_fraction, rock_area / second.known_area_m2, 1e-12);
  // Oracle cells are hazard where any pixel reaches h_min, so free pixels sharing a rock's
  // cells are false alarms; deleting the rock removes some of them.
  EXPECT_GT(first.false_alarm_area_m2, 0.0);
  EXPECT_LT(second.false_alarm_area_m2, first.false_alarm_area_m2);
  // The untouched Kalman layer stays clean in both frames.
  EXPECT_EQ(derive_metrics(ev.sums[1][1]).missed_area_m2, 0.0);
}

TEST(RunEvaluation, DriftedRunIsScoredAtTheTruePose) {
  // The run used poses 16 cm / -8 cm off the truth, so its maps sit shifted by that much in
  // its frame. With poses_true.txt the ground truth is moved into that frame: the scores
  // equal those of the undrifted oracle. Without it, rocks land in the wrong cells.
  const TestWorld w = rocky_world();
  const Eigen::Vector2d shift(0.16, -0.08);
  Oracle t;
  auto layers = t.layers(w);
  for (auto& l : layers) hazmap::testing::shift_layer(l, shift.x(), shift.y());
  t.write(w, {layers, layers});
  hazmap::testing::write_poses(t.seq / "poses.txt", t.frames, {shift, shift + Eigen::Vector2d(0.04, 0)});
  hazmap::testing::write_poses(t.seq / "poses_true.txt", t.frames, {{0.0, 0.0}, {0.04, 0.0}});
  const RunEvaluation drifted = t.evaluate();
  EXPECT_TRUE(drifted.used_true_poses);

  Oracle reference;
  const auto straight = reference.layers(w);
  reference.write(w, {straight, straight});
  const RunEvaluation truth = reference.evaluate();

  for (size_t l = 0; l < 2; ++l) {
    const LayerMetrics a = derive_metrics(drifted.pooled[l]), b = derive_metrics(truth.pooled[l]);
    EXPECT_NEAR(a.height_rms_m, b.height_rms_m, kFloatHeightTol) << l;
    EXPECT_NEAR(a.missed_area_m2, 0.0, kAreaTolerance) << l;
    EXPECT_NEAR(a.false_alarm_area_m2, b.false_alarm_area_m2, kAreaTolerance) << l;
    EXPECT_NEAR(a.gt_hazard_known_area_m2, b.gt_hazard_known_area_m2, kAreaTolerance) << l;
  }

  std::filesystem::remove(t.seq / "poses_true.txt");
  const RunEvaluation naive = t.evaluate();
  EXPECT_FALSE(naive.used_true_poses);
  EXPECT_GT(derive_metrics(naive.pooled[0]).missed_area_m2, 0.01);
}

TEST(RunEvaluation, MissingGroundTruthNamesTheFile) {
  Oracle t;
  const TestWorld w;
  const auto layers = t.layers(w);
  t.write(w, {layers, layers});
  std::filesystem::remove(t.seq / "gt_hazard.jdem");
  try {
    t.evaluate();
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gt_hazard.jdem"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--ground-truth"), std::string::npos) << e.what();
  }
}

TEST(RunEvaluation, HMinOfPiecewiseConstantLayersDefaultsToTheRoughnessThreshold) {
  Config c = parse_config(
      "map:\n  layers:\n    - {resolution: 0.04, size: 20, rule: omg, hazard: {kernel: 5}}\n"
      "    - {resolution: 0.08, size: 20, rule: ccm}\n",
      "test");
  std::string source;
  // (D - 1) r tan(20 deg) = 4 * 0.04 * 0.36397 = 0.058235 m.
  EXPECT_NEAR(layer_h_min(c.map.layers[0], c.hazard, &source), 4 * 0.04 * std::tan(M_PI / 9), 1e-12);
  EXPECT_EQ(source, "derived roughness threshold");
  EXPECT_NEAR(layer_h_min(c.map.layers[1], c.hazard, &source), 0.06, 1e-12);
  EXPECT_EQ(source, "0.75 r");
}

}  // namespace
}  // namespace hazmap::eval
