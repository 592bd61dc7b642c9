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
  RunEvaluation evaluate(double near_radius_m = -1.0) const {
    EvaluationOptions o;
    o.run_dir = run;
    o.sequence_dir = seq;
    o.near_radius_m = near_radius_m;
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
  const RunEvaluation drifted = t.evaluate(0.9);
  EXPECT_TRUE(drifted.used_true_poses);

  Oracle reference;
  const auto straight = reference.layers(w);
  reference.write(w, {straight, straight});
  const RunEvaluation truth = reference.evaluate(0.9);

  for (size_t l = 0; l < 2; ++l) {
    const LayerMetrics a = derive_metrics(drifted.pooled[l]), b = derive_metrics(truth.pooled[l]);
    EXPECT_NEAR(a.height_rms_m, b.height_rms_m, kFloatHeightTol) << l;
    EXPECT_NEAR(a.missed_area_m2, 0.0, kAreaTolerance) << l;
    EXPECT_NEAR(a.false_alarm_area_m2, b.false_alarm_area_m2, kAreaTolerance) << l;
    EXPECT_NEAR(a.gt_hazard_known_area_m2, b.gt_hazard_known_area_m2, kAreaTolerance) << l;
    // --near is centred on the true position: the same disc of ground truth as undrifted
    // (centred on the drifted position it would hold other pixels).
    EXPECT_EQ(drifted.near_pooled[l].extent_px, truth.near_pooled[l].extent_px) << l;
    EXPECT_EQ(drifted.near_pooled[l].gt_hazard_px, truth.near_pooled[l].gt_hazard_px) << l;
    EXPECT_EQ(drifted.near_pooled[l].false_alarm_px, truth.near_pooled[l].false_alarm_px) << l;
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
  // No footprint_hazard.jdem: L0, L1, fused.
  const std::vector<EvaluatedLayer> layers = evaluated_layers(c, false);
  ASSERT_EQ(layers.size(), 3u);
  // (D - 1) r tan(20 deg) = 4 * 0.04 * 0.36397 = 0.058235 m.
  EXPECT_NEAR(layers[0].h_min_m, 4 * 0.04 * std::tan(M_PI / 9), 1e-12);
  EXPECT_EQ(layers[0].h_min_source, "derived roughness threshold");
  EXPECT_NEAR(layers[1].h_min_m, 0.06, 1e-12);
  EXPECT_EQ(layers[1].h_min_source, "0.75 r");
  // The fused map: SPEC 8.4's default critical height, the finest layer's h_min.
  EXPECT_EQ(layers[2].name, "fused");
  EXPECT_EQ(layers[2].rule, "fused");
  EXPECT_EQ(layers[2].index, -1);
  EXPECT_EQ(layers[2].hazard_file, "fused_hazard.jdem");
  EXPECT_DOUBLE_EQ(layers[2].resolution_m, 0.04);
  EXPECT_NEAR(layers[2].h_min_m, 4 * 0.04 * std::tan(M_PI / 9), 1e-12);
}

TEST(RunEvaluation, FusedAndFootprintUseTheCriticalHeight) {
  const Config c = parse_config(
      "map:\n  layers:\n    - {resolution: 0.04, size: 20, rule: ccm}\n"
      "    - {resolution: 0.08, size: 20, rule: ccm}\n"
      "hazard: {critical_height: 0.045, wheelbase: 0.3}\n",
      "test");
  const std::vector<EvaluatedLayer> layers = evaluated_layers(c, true);
  ASSERT_EQ(layers.size(), 4u);
  // Only the footprint map is scored against dilated obstacles, by wheelbase / 2.
  EXPECT_EQ(layers[2].gt_dilation_m, 0.0);
  EXPECT_DOUBLE_EQ(layers[3].gt_dilation_m, 0.15);
  EXPECT_NEAR(layers[0].h_min_m, 0.03, 1e-12);
  EXPECT_NEAR(layers[1].h_min_m, 0.06, 1e-12);
  for (size_t i : {2u, 3u}) {
    EXPECT_DOUBLE_EQ(layers[i].h_min_m, 0.045) << i;
    EXPECT_EQ(layers[i].h_min_source, "hazard.critical_height") << i;
    EXPECT_DOUBLE_EQ(layers[i].resolution_m, 0.04) << i;
  }
  EXPECT_EQ(layers[3].name, "footprint");
  EXPECT_EQ(layers[3].hazard_file, "footprint_hazard.jdem");
}

TEST(RunEvaluation, FootprintMapIsScoredWhenWrittenAndSkippedWhenNot) {
  // Critical height 5 cm while L0's h_min is 3 cm: the footprint (here: the L0 hazard
  // grid with rock 1 deleted in frame 2) misses exactly rock 1's pixels >= 5 cm. A zero
  // footprint radius makes the footprint's truth the rocks themselves (no dilation).
  Oracle t;
  t.config.hazard.critical_height_m = 0.05;
  t.config.hazard.footprint_radius_m = 0.0;
  const TestWorld w = rocky_world();
  const auto layers = t.layers(w);
  t.write(w, {layers, layers});
  {
    const RunEvaluation ev = t.evaluate();  // no footprint_hazard.jdem yet
    ASSERT_EQ(ev.layers.size(), 3u);
    EXPECT_EQ(ev.layers[2].name, "fused");
    EXPECT_DOUBLE_EQ(ev.layers[2].h_min_m, 0.05);
    EXPECT_EQ(testing::read_text(t.run / "eval" / "metrics.csv").find("footprint"),
              std::string::npos);
  }
  auto without_rock = layers[0];
  hazmap::testing::delete_rock(without_rock, w.rocks[1].x_m, w.rocks[1].y_m,
                               w.rocks[1].radius_m + 0.08);
  hazmap::testing::write_hazard_map(t.run, t.frames[0], "footprint_hazard.jdem", layers[0].hazard);
  // Only one frame has it: skipped, with a warning, not an error.
  EXPECT_EQ(t.evaluate().layers.size(), 3u);
  hazmap::testing::write_hazard_map(t.run, t.frames[1], "footprint_hazard.jdem",
                                    without_rock.hazard);
  const RunEvaluation ev = t.evaluate();
  ASSERT_EQ(ev.layers.size(), 4u);
  EXPECT_EQ(ev.layers[3].name, "footprint");
  EXPECT_DOUBLE_EQ(ev.layers[3].h_min_m, 0.05);
  EXPECT_EQ(ev.layers[3].gt_dilation_m, 0.0);
  const LayerMetrics first = derive_metrics(ev.sums[0][3]);
  const LayerMetrics second = derive_metrics(ev.sums[1][3]);
  EXPECT_EQ(first.missed_area_m2, 0.0);
  EXPECT_NEAR(first.hazard_recall, 1.0, 1e-15);
  const double rock1 = w.rock_pixels_at_least(1, 0.05) * kPixelArea;
  double all = 0;
  for (size_t k = 0; k < w.rocks.size(); ++k) all += w.rock_pixels_at_least(k, 0.05) * kPixelArea;
  ASSERT_LT(rock1, w.rock_pixels_at_least(1, 0.03) * kPixelArea);  // h_min matters here
  EXPECT_NEAR(second.missed_area_m2, rock1, kAreaTolerance);
  EXPECT_NEAR(second.gt_hazard_area_m2, all, kAreaTolerance);
  EXPECT_NEAR(second.hazard_recall, 1.0 - rock1 / all, 1e-12);
  EXPECT_EQ(second.hazard_unknown, 0.0);
  const std::string csv = testing::read_text(t.run / "eval" / "metrics.csv");
  EXPECT_NE(csv.find("\n000001,1,footprint,0.04,footprint,0.05,"), std::string::npos) << csv;
  const std::string json = testing::read_text(t.run / "eval" / "metrics.json");
  EXPECT_NE(json.find("\"footprint\""), std::string::npos);
  EXPECT_NE(testing::read_text(t.run / "eval" / "report.html").find("footprint"),
            std::string::npos);
}

TEST(RunEvaluation, NearMetricsCountTheGroundTruthAroundTheRover) {
  // Poses (0, 0) and (0.04, 0), windows x in [0.16, 1.76), |y| < 0.8. Within 0.9 m of
  // the rover lies all of rock 0 (centre 0.67 m away, radius 0.10 m) and none of rocks 1
  // and 2 (their nearest points >= 1.19 m away). Frame 2 deletes rock 1 from L0: missed
  // overall, not near.
  Oracle t;
  const TestWorld w = rocky_world();
  const auto good = t.layers(w);
  auto bad = good;
  hazmap::testing::delete_rock(bad[0], w.rocks[1].x_m, w.rocks[1].y_m, w.rocks[1].radius_m + 0.08);
  t.write(w, {good, bad});
  const double R = 0.9;
  const RunEvaluation ev = t.evaluate(R);
  ASSERT_EQ(ev.near_sums.size(), 2u);
  // Independent count of the GT pixels in each frame's disc and window.
  const DenseGrid g = w.grid();
  const double rover_x[] = {0.0, 0.04};
  for (size_t f = 0; f < 2; ++f) {
    std::size_t in_disc = 0;
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        const double x = g.x_of_col(c), y = g.y_of_row(r);
        if (x >= 0.16 && x < 1.76 && std::abs(y) < 0.8 &&
            std::hypot(x - rover_x[f], y) <= R)
          ++in_disc;
      }
    for (size_t l = 0; l < 3; ++l) EXPECT_EQ(ev.near_sums[f][l].extent_px, in_disc) << f << l;
  }
  const MetricSums& near_bad = ev.near_sums[1][0];
  EXPECT_EQ(near_bad.gt_hazard_px, static_cast<std::size_t>(w.rock_pixels_at_least(0, 0.03)));
  EXPECT_EQ(near_bad.missed_px, 0u);
  EXPECT_EQ(derive_metrics(near_bad).hazard_recall, 1.0);
  EXPECT_GT(ev.sums[1][0].missed_px, 0u);  // rock 1 is missed, outside the disc
  // Pooled near sums are the frames' sums.
  EXPECT_EQ(ev.near_pooled[0].extent_px, ev.near_sums[0][0].extent_px + near_bad.extent_px);

  const std::string csv = testing::read_text(t.run / "eval" / "metrics.csv");
  for (const char* k : {"near_hazard_recall", "near_hazard_unknown", "near_missed_m2",
                        "near_false_alarm_fraction", "hazard_recall", "variance_violation_all",
                        "height_rms_all_m", "max_below_m"})
    EXPECT_NE(csv.find(k), std::string::npos) << k;
  EXPECT_NE(testing::read_text(t.run / "eval" / "summary.csv").find("near_hazard_recall"),
            std::string::npos);
  const std::string json = testing::read_text(t.run / "eval" / "metrics.json");
  EXPECT_NE(json.find("\"near_radius_m\""), std::string::npos);
  EXPECT_NE(json.find("\"near_missed_m2\""), std::string::npos);
  EXPECT_NE(json.find("\"max_below_m\""), std::string::npos);
  // Without --near nothing near_ is computed or written.
  const RunEvaluation plain = t.evaluate();
  EXPECT_TRUE(plain.near_sums.empty());
  EXPECT_EQ(testing::read_text(t.run / "eval" / "metrics.csv").find("near_"), std::string::npos);
  EXPECT_EQ(testing::read_text(t.run / "eval" / "metrics.json").find("near_"), std::string::npos);
}

}  // namespace
}  // namespace hazmap::eval
