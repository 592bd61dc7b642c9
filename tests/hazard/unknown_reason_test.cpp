// Why a cell stayed unknown (issue 34): HazardClassifier::explain's reason bits on
// analytic terrain, and that asking for them changes no class.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {
namespace {

Config one_layer(RuleKind rule, double r) {
  Config c;
  LayerConfig l;
  l.rule = rule;
  l.resolution_m = r;
  l.size = static_cast<int>(std::lround(1.6 / r));
  l.hazard.kernel = r < 0.02 ? 7 : 5;
  c.map.layers.push_back(l);
  c.rules.ccm.max_weight = 1e6;
  return c;
}

/// Flat ground z = 0 sampled every `spacing` with height noise sigma, except where
/// `hole` says so; the layer's export.
template <class Hole>
LayerGrids map_flat(const Config& config, double spacing, double sigma, Hole hole) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  PointCloud cloud;
  for (double y = -0.7; y < 0.7; y += spacing)
    for (double x = -0.7; x < 0.7; x += spacing) {
      if (hole(x, y)) continue;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), float(noise(rng)));
      m.cov_xx = m.cov_yy = 1e-6f;
      m.cov_zz = float(sigma * sigma);
      cloud.push_back(m);
    }
  LayerStack stack(config.map, config.rules);
  stack.begin_frame(0.001, 0.001);
  stack.insert(MapPoints(cloud));
  LayerGrids g;
  stack.export_layer(0, g);
  return g;
}

struct Explained {
  DenseGrid hazard, reasons;
};
Explained explain(const Config& config, const LayerGrids& g) {
  const HazardParams params = resolve_hazard_params(config);
  auto classifier = make_hazard_classifier(params.layers[0]);
  Explained e;
  HazardDiagnostics diag;
  classifier->explain(g, e.reasons);
  classifier->classify(g, e.hazard, diag);
  return e;
}

unsigned bits_at(const DenseGrid& g, double x, double y) {
  int row = 0, col = 0;
  EXPECT_TRUE(g.cell_at(x, y, &row, &col));
  return static_cast<unsigned>(g.at(row, col));
}

TEST(UnknownReason, ExplainGivesBitsExactlyAtUnknownCellsAndChangesNoClass) {
  const Config config = one_layer(RuleKind::kalman, 0.01);
  const LayerGrids g = map_flat(config, 0.003, 0.0005, [](double x, double y) {
    return std::hypot(x - 0.3, y - 0.1) < 0.03;  // a hole: unknown around it
  });
  const Explained e = explain(config, g);
  // The same classifier's whole pass, with no explain before it.
  const HazardParams params = resolve_hazard_params(config);
  DenseGrid plain;
  HazardDiagnostics diag;
  make_hazard_classifier(params.layers[0])->classify(g, plain, diag);
  ASSERT_EQ(plain.values.size(), e.hazard.values.size());
  int unknown = 0;
  for (size_t i = 0; i < plain.values.size(); ++i) {
    ASSERT_EQ(plain.values[i], e.hazard.values[i]);
    const bool is_unknown = plain.values[i] == float(HazardClass::unknown);
    unknown += is_unknown;
    if (is_unknown) EXPECT_GT(e.reasons.values[i], 0.0f) << i;
    else EXPECT_EQ(e.reasons.values[i], 0.0f) << i;
  }
  EXPECT_GT(unknown, 0);
}

TEST(UnknownReason, NamesTheRingTheKernelTheHeightAndTheMargin) {
  Config config = one_layer(RuleKind::kalman, 0.01);
  config.hazard.partial_ring_proof = PartialRingProof::any;
  const double R = 0.15;  // the wheel ring's radius (default wheelbase 0.3 m)
  // 5 cm holes at ring samples 0-3 of cell (0.305, 0.105): samples 4-7 hold no opposite
  // pair, so the partial ring cannot prove the cell (wheel_ring.hpp).
  const auto in_hole = [&](double x, double y, int samples) {
    for (int k = 0; k < samples; ++k)
      if (std::abs(x - 0.305 - R * std::cos(k * M_PI / 4)) < 0.025 &&
          std::abs(y - 0.105 - R * std::sin(k * M_PI / 4)) < 0.025)
        return true;
    return false;
  };
  const LayerGrids g = map_flat(config, 0.003, 0.0005, [&](double x, double y) { return in_hole(x, y, 4); });
  const Explained e = explain(config, g);
  EXPECT_EQ(bits_at(e.reasons, 0.305, 0.105), unsigned(kReasonRingIncomplete));
  EXPECT_EQ(bits_at(e.hazard, 0.305, 0.105), unsigned(HazardClass::unknown));
  // Inside a hole: no height.
  EXPECT_TRUE(bits_at(e.reasons, 0.305 + R, 0.105) & kReasonNoHeight);
  // One hole only (sample 0): seven samples, three opposite pairs: proven, no bits.
  const Explained one = explain(config, map_flat(config, 0.003, 0.0005, [&](double x, double y) {
                                  return in_hole(x, y, 1);
                                }));
  EXPECT_EQ(bits_at(one.hazard, 0.305, 0.105), unsigned(HazardClass::traversable));
  EXPECT_EQ(bits_at(one.reasons, 0.305, 0.105), 0u);
  // Without partial-ring proof (the default) the same ring is incomplete.
  Config full_rings = config;
  full_rings.hazard.partial_ring_proof = PartialRingProof::off;
  const Explained off = explain(full_rings, map_flat(full_rings, 0.003, 0.0005, [&](double x, double y) {
                                  return in_hole(x, y, 1);
                                }));
  EXPECT_EQ(bits_at(off.hazard, 0.305, 0.105), unsigned(HazardClass::unknown));
  EXPECT_EQ(bits_at(off.reasons, 0.305, 0.105), unsigned(kReasonRingIncomplete));
  // Ground seen in one 1 cm column of three: every observed cell's kernel is a third
  // full, below min_kernel_fill (0.5): kernel incomplete, and no margin of the kernel's.
  const LayerGrids striped = map_flat(config, 0.003, 0.0005, [](double x, double) {
    return static_cast<long>(std::floor(x / 0.01 + 1000)) % 3 != 0;
  });
  const Explained st = explain(config, striped);
  const unsigned edge = bits_at(st.reasons, -0.005, 0.105);  // an observed column
  EXPECT_TRUE(edge & kReasonKernelIncomplete) << edge;
  EXPECT_FALSE(edge & kReasonRoughnessMargin) << edge;
  EXPECT_EQ(bits_at(st.hazard, -0.005, 0.105), unsigned(HazardClass::unknown));
  // Far from the hole: proven, no bits.
  EXPECT_EQ(bits_at(e.hazard, -0.3, -0.3), unsigned(HazardClass::traversable));
  EXPECT_EQ(bits_at(e.reasons, -0.3, -0.3), 0u);

  // Noisy ground (1 cm sigma against a 2.2 cm roughness threshold): the roughness test
  // cannot prove it (within k sigma), whatever else happens.
  const LayerGrids noisy = map_flat(config, 0.01, 0.01, [](double, double) { return false; });
  const Explained n = explain(config, noisy);
  EXPECT_TRUE(bits_at(n.reasons, 0.0, 0.0) & kReasonRoughnessMargin);
}

TEST(UnknownReason, CcmCellsNameTooFewPointsAndNoHeight) {
  const Config config = one_layer(RuleKind::ccm, 0.04);
  // Every point is 4 cm apart: one point per cell, fewer than min_points.
  const LayerGrids g = map_flat(config, 0.04, 0.001, [](double x, double) { return x > 0.3; });
  const Explained e = explain(config, g);
  EXPECT_EQ(bits_at(e.reasons, 0.02, 0.02) & kReasonFewPoints, unsigned(kReasonFewPoints));
  EXPECT_EQ(bits_at(e.reasons, 0.5, 0.02), unsigned(kReasonNoHeight));
}

}  // namespace
}  // namespace hazmap
