#include "hazmap/rules/kalman.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "hazmap/rules/bananas.hpp"

namespace hazmap {
namespace {

TEST(KalmanRule, FirstPointInitialisesTheCell) {
  KalmanRule::Cell c;
  EXPECT_FALSE(KalmanRule::known(c));
  KalmanRule::update({0.0, 0.0}, c, 0.25, 4e-6);
  EXPECT_TRUE(KalmanRule::known(c));
  EXPECT_DOUBLE_EQ(KalmanRule::mean(c), 0.25);
  EXPECT_FLOAT_EQ(KalmanRule::variance(c), 4e-6f);
}

TEST(KalmanRule, EqualsBatchInverseVarianceEstimate) {
  // Batch: mu = sum(z/vm) / sum(1/vm), var = 1 / sum(1/vm), in double.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> sigma(0.001, 0.03);
  for (int trial = 0; trial < 50; ++trial) {
    const double truth = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
    KalmanRule::Cell c;
    double sum_w = 0, sum_wz = 0;
    for (int i = 0; i < 200; ++i) {
      const double s = sigma(rng);
      const double z = truth + std::normal_distribution<double>(0.0, s)(rng);
      KalmanRule::update({0.0, 0.0}, c, z, s * s);
      sum_w += 1.0 / (s * s);
      sum_wz += z / (s * s);
    }
    EXPECT_NEAR(KalmanRule::mean(c), sum_wz / sum_w,
                1e-5 * std::max(1.0, std::abs(sum_wz / sum_w)));
    EXPECT_NEAR(KalmanRule::variance(c), 1.0 / sum_w, 1e-5 / sum_w);
  }
}

TEST(KalmanRule, VarianceFloorStopsConvergence) {
  const KalmanRule::Config cfg{0.0, 1e-6};
  KalmanRule::Cell c;
  for (int i = 0; i < 1000; ++i) KalmanRule::update(cfg, c, 0.0, 1e-5);
  EXPECT_FLOAT_EQ(KalmanRule::variance(c), 1e-6f);
  // At the floor each new measurement keeps a fixed weight vm_floor / (floor + vm).
  KalmanRule::update(cfg, c, 1.0, 1e-5);
  EXPECT_NEAR(KalmanRule::mean(c), 1e-6 / (1e-6 + 1e-5), 1e-6);
}

TEST(KalmanRule, TimeInflationAddsQPerFrameToKnownCellsOnly) {
  const KalmanRule::Config cfg{2e-6, 0.0};
  KalmanRule::Cell known, unknown;
  KalmanRule::update(cfg, known, 0.1, 1e-5);
  for (int i = 0; i < 3; ++i) {
    KalmanRule::age(cfg, known, 1);
    KalmanRule::age(cfg, unknown, 1);
  }
  EXPECT_NEAR(KalmanRule::variance(known), 1e-5 + 3 * 2e-6, 1e-11);
  EXPECT_FALSE(KalmanRule::known(unknown));
}

TEST(KalmanRule, MergeRunEqualsAgeingThenMerge) {
  // merge_run's fused single-division form against age() followed by the textbook
  // information-form merge in double, on cleared and known cells, with and without owed
  // frames, below and at the floor.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const KalmanRule::Config cfg :
       {KalmanRule::Config{1e-6, 1e-6}, KalmanRule::Config{3e-5, 0.0}}) {
    for (int trial = 0; trial < 200; ++trial) {
      KalmanRule::Cell cell;
      if (trial % 4 != 0) KalmanRule::update(cfg, cell, 12.3 + 0.1 * u(rng), 1e-6 + 1e-4 * u(rng));
      const std::uint32_t owed = static_cast<std::uint32_t>(trial % 3) * 2;
      KalmanRule::Sums s;
      s.w = 1e3 + 2e6 * u(rng);
      s.wz = s.w * (0.05 * u(rng) - 0.025);  // run mean within 2.5 cm of its first height
      const double z_ref = 12.3 + 0.1 * u(rng);
      KalmanRule::Cell fused = cell, aged = cell;
      KalmanRule::merge_run(cfg, fused, s, z_ref, owed, KalmanRule::max_precision(cfg));
      KalmanRule::age(cfg, aged, owed);
      const double p = KalmanRule::known(aged) ? double(aged.precision) : 0.0;
      const double off = KalmanRule::known(aged) ? KalmanRule::mean(aged) - z_ref : 0.0;
      const double precision = p + s.w, mean = z_ref + (p * off + s.wz) / precision;
      const double floored =
          cfg.min_variance_m2 > 0 ? std::min(precision, 1.0 / cfg.min_variance_m2) : precision;
      ASSERT_NEAR(KalmanRule::mean(fused), mean, 1e-9) << trial;
      ASSERT_NEAR(fused.precision, floored, 1e-6 * floored) << trial;
    }
  }
  // A run of weight zero leaves a cleared cell cleared, and only ages a known one (its
  // cell is stamped with the frame, so the owed ageing must not be lost).
  const KalmanRule::Config cfg{1e-4, 0.0};
  KalmanRule::Cell c;
  KalmanRule::merge_run(cfg, c, KalmanRule::Sums{}, 1.0, 3, 1e6);
  EXPECT_FALSE(KalmanRule::known(c));
  KalmanRule::update(cfg, c, 0.25, 1e-4);
  KalmanRule::merge_run(cfg, c, KalmanRule::Sums{}, 1.0, 3, 1e6);
  EXPECT_NEAR(KalmanRule::mean(c), 0.25, 1e-12);
  EXPECT_NEAR(KalmanRule::variance(c), 1e-4 + 3 * 1e-4, 1e-10);
}

TEST(BananasRule, KeepsTheLastHeight) {
  BananasRule::Cell c;
  EXPECT_FALSE(BananasRule::known(c));
  for (double z : {0.3, -0.1, 0.7}) BananasRule::update({}, c, z, 1.0);
  EXPECT_FLOAT_EQ(BananasRule::height(c), 0.7f);
}

}  // namespace
}  // namespace hazmap
