// Time inflation (Kalman) and decay (OMG) as layers apply them: lazily, when a cell is
// next merged or read. Checked against the rule's per-point recursion with one
// Rule::age(1) per frame, over frames with and without points in the cell.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hazmap/map/map_points.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/kalman.hpp"
#include "hazmap/rules/omg.hpp"

namespace hazmap {
namespace {

constexpr double kCell = 0.1;
constexpr int kSize = 8;

/// Points at the centre of global cell (ix, 0), height z +- 2 mm, var_z 1e-4 m^2.
PointCloud cell_points(CellIndex ix, int n, double z, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, 0.002);
  PointCloud cloud;
  for (int k = 0; k < n; ++k) {
    Measurement m{};
    m.p_W = Eigen::Vector3f(float((double(ix) + 0.5) * kCell), float(0.5 * kCell),
                            float(z + noise(rng)));
    m.cov_xx = m.cov_yy = 1e-6f;
    m.cov_zz = 1e-4f;
    cloud.push_back(m);
  }
  return cloud;
}

/// Frames 0..11; the cell gets points in frames 0, 4, 5 and 11 and is read every frame.
template <class Rule, class Check>
void run_frames(const typename Rule::Config& cfg, Check check) {
  RollingLayer<Rule> layer(kSize, kCell, cfg);
  typename Rule::Cell reference;  // per point, one age(1) per frame
  std::mt19937_64 rng(3);
  for (std::uint32_t frame = 0; frame < 12; ++frame) {
    layer.begin_frame(0.0, 0.0, frame);
    if (frame > 0) Rule::age(cfg, reference, 1);
    if (frame == 0 || frame == 4 || frame == 5 || frame == 11) {
      const PointCloud cloud = cell_points(1, 6, 0.3 + 0.01 * frame, rng);
      layer.insert(MapPoints(cloud));
      for (const Measurement& m : cloud) Rule::update(cfg, reference, m.p_W.z(), m.cov_zz);
    }
    check(layer.cell(1, 0), reference, frame);
  }
}

TEST(LayerAgeing, KalmanInflationOfSkippedFramesEqualsOnePassPerFrame) {
  KalmanRule::Config cfg;
  cfg.time_inflation_m2 = 2e-5;  // a fifth of a point's variance per frame: visible
  cfg.min_variance_m2 = 1e-9;    // below anything reached: the floor stays out of the way
  run_frames<KalmanRule>(
      cfg, [](const KalmanRule::Cell& got, const KalmanRule::Cell& want, std::uint32_t frame) {
        ASSERT_TRUE(KalmanRule::known(got));
        // Float rounding of one division per frame (eager) vs one per gap (lazy): ~1e-7.
        EXPECT_NEAR(KalmanRule::variance(got), KalmanRule::variance(want),
                    1e-6 * KalmanRule::variance(want))
            << "frame " << frame;
        EXPECT_NEAR(KalmanRule::mean(got), KalmanRule::mean(want), 1e-7) << "frame " << frame;
      });
}

TEST(LayerAgeing, KalmanVarianceGrowsByQPerFrameWithoutPoints) {
  KalmanRule::Config cfg;
  cfg.time_inflation_m2 = 1e-5;
  RollingLayer<KalmanRule> layer(kSize, kCell, cfg);
  std::mt19937_64 rng(4);
  layer.begin_frame(0.0, 0.0, 0);
  layer.insert(MapPoints(cell_points(2, 4, 0.1, rng)));
  const double v0 = KalmanRule::variance(layer.cell(2, 0));
  ASSERT_NEAR(v0, 1e-4 / 4, 1e-9);  // four points of var 1e-4
  for (std::uint32_t frame = 1; frame <= 30; ++frame) {
    layer.begin_frame(0.0, 0.0, frame);
    ASSERT_NEAR(KalmanRule::variance(layer.cell(2, 0)), v0 + frame * 1e-5, 1e-6 * v0) << frame;
  }
}

TEST(LayerAgeing, OmgDecayOfSkippedFramesEqualsOnePassPerFrame) {
  OmgRule::Config cfg;
  cfg.decay = 0.8;
  cfg.max_weight = 1e9;
  run_frames<OmgRule>(
      cfg, [](const OmgRule::Cell& got, const OmgRule::Cell& want, std::uint32_t frame) {
        ASSERT_TRUE(OmgRule::known(got));
        EXPECT_NEAR(got.weight, want.weight, 1e-6 * want.weight) << "frame " << frame;
        EXPECT_NEAR(OmgRule::mean(got), OmgRule::mean(want), 1e-7) << "frame " << frame;
        EXPECT_NEAR(OmgRule::variance(got), OmgRule::variance(want), 1e-5 * OmgRule::variance(want))
            << "frame " << frame;
      });
}

}  // namespace
}  // namespace hazmap
