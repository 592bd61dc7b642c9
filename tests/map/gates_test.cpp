// SPEC 4 gates in the layers: the lateral-spread gate (max_std_ratio, every rule) and the
// consistency gate of the piecewise-constant fusing rules (gate_sigma, Kalman and OMG),
// each against the formula computed here, with the layers' per-insertion counts.

#include <cmath>
#include <optional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "hazmap/map/grid_math.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/rules/rule_registry.hpp"

namespace hazmap {
namespace {

Measurement point(double x, double y, double z, double sigma_z, double sigma_xy) {
  Measurement m{};
  m.p_W = Eigen::Vector3f(float(x), float(y), float(z));
  m.cov_xx = m.cov_yy = float(sigma_xy * sigma_xy);
  m.cov_zz = float(sigma_z * sigma_z);
  return m;
}

MapConfig one_layer(RuleKind rule, double r, int n, std::optional<double> max_std_ratio = std::nullopt) {
  MapConfig map;
  LayerConfig l;
  l.rule = rule;
  l.resolution_m = r;
  l.size = n;
  l.max_std_ratio = max_std_ratio;
  map.layers.push_back(l);
  return map;
}

// Every rule: the gate drops exactly the points inside the window whose lateral variance
// max(Sigma_xx, Sigma_yy) exceeds (ratio r / sqrt(12))^2, counts them, and leaves the
// layer as if only the other points had come.
TEST(Gates, LateralGateDropsExactlyThePointsTheFormulaSaysForEveryRule) {
  const double r = 0.04, ratio = 1.5;
  const int n = 16;  // window [-0.32, 0.32)^2 around the origin
  const double gate_var = std::pow(ratio * r / std::sqrt(12.0), 2);
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> cell(-10, 9);  // some cells outside the window
  std::uniform_real_distribution<double> inside(0.05, 0.95), lateral(0.0, 2.0 * std::sqrt(gate_var));
  std::normal_distribution<double> noise(0.0, 0.003);
  // 3003 points: three chunks, the last one not a whole number of vectors.
  PointCloud all, kept;
  std::size_t in_window = 0, wide_in_window = 0;
  for (int i = 0; i < 3003; ++i) {
    const int ix = cell(rng), iy = cell(rng);
    const double x = (ix + inside(rng)) * r, y = (iy + inside(rng)) * r;
    const Measurement m = point(x, y, 0.1 * x + noise(rng), 0.003, lateral(rng));
    all.push_back(m);
    const bool in = ix >= -8 && ix < 8 && iy >= -8 && iy < 8;
    const bool wide = double(std::max(m.cov_xx, m.cov_yy)) > gate_var;
    in_window += in;
    wide_in_window += in && wide;
    if (!wide) kept.push_back(m);
  }
  ASSERT_GT(wide_in_window, 500u);
  ASSERT_LT(wide_in_window, in_window - 500u);
  for (const RuleInfo& row : kRuleTable) {  // every rule in the registry
    const RuleKind rule = row.kind;
    const std::string name = rule_name(rule);
    RulesConfig rules;
    // The layer's own ratio, and the fallback to rules.ccm.max_std_ratio.
    LayerStack own(one_layer(rule, r, n, ratio), rules);
    RulesConfig fallback_rules;
    fallback_rules.ccm.max_std_ratio = ratio;
    LayerStack fallback(one_layer(rule, r, n, std::nullopt), fallback_rules);  // auto
    // 0 turns the gate off whatever rules.ccm says; the reference gets only the kept points.
    LayerStack off(one_layer(rule, r, n, 0.0), fallback_rules);
    LayerStack reference(one_layer(rule, r, n), rules);
    for (LayerStack* s : {&own, &fallback, &off, &reference}) s->begin_frame(0.0, 0.0);
    EXPECT_EQ(own.insert(MapPoints(all)), in_window - wide_in_window) << name;
    EXPECT_EQ(own.gate_counts(0).std_gate, wide_in_window) << name;
    EXPECT_EQ(own.gate_counts(0).consistency_gate, 0u) << name;
    EXPECT_EQ(fallback.insert(MapPoints(all)), in_window - wide_in_window) << name;
    EXPECT_EQ(fallback.gate_counts(0).std_gate, wide_in_window) << name;
    EXPECT_EQ(off.insert(MapPoints(all)), in_window) << name;
    EXPECT_EQ(off.gate_counts(0).std_gate, 0u) << name;
    reference.insert(MapPoints(kept));
    const RollingGrid& g = own.layer(0).grid();
    for (CellIndex iy = g.origin_y(); iy < g.origin_y() + g.size(); ++iy)
      for (CellIndex ix = g.origin_x(); ix < g.origin_x() + g.size(); ++ix) {
        const Moments a = own.layer(0).cell_moments(ix, iy);
        const Moments b = reference.layer(0).cell_moments(ix, iy);
        ASSERT_EQ(a.w, b.w) << name;
        ASSERT_EQ(a.mz, b.mz) << name;
        ASSERT_EQ(a.szz, b.szz) << name;
      }
    // The next insertion starts its count afresh.
    own.insert(MapPoints(kept));
    EXPECT_EQ(own.gate_counts(0).std_gate, 0u) << name;
  }
}

/// A layer whose cell (0, 0) [0, 0.1)^2 has converged on z = 0.2 over ten frames of
/// 20 points each (sigma_z = 5 mm).
LayerStack converged_cell(RuleKind rule, double gate_sigma) {
  RulesConfig rules;
  rules.kalman.gate_sigma = gate_sigma;
  rules.omg.gate_sigma = gate_sigma;
  LayerStack s(one_layer(rule, 0.1, 8), rules);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.005);
  for (int frame = 0; frame < 10; ++frame) {
    s.begin_frame(0.0, 0.0);
    PointCloud cloud;
    for (int i = 0; i < 20; ++i) cloud.push_back(point(0.05, 0.05, 0.2 + noise(rng), 0.005, 0.001));
    s.insert(MapPoints(cloud));
  }
  return s;
}

/// Height and variance of cell (0, 0) as the layer exports them now.
std::pair<double, double> cell_state(const LayerStack& s) {
  LayerGrids g;
  s.export_layer(0, g);
  int row = 0, col = 0;
  EXPECT_TRUE(g.height.cell_at(0.05, 0.05, &row, &col));
  return {g.height.at(row, col), g.variance.at(row, col)};
}

// SPEC 4: one wild point must not move a well-known cell. A point 1 m off a converged
// cell moves it with the gate off (gate_sigma 0) and leaves it exactly as it was, counted,
// with gate_sigma 3; points just inside the gate, |z - mu| = 0.99 * 3 sqrt(var + vm), are
// taken, and just outside (1.01) are not.
TEST(Gates, WildPointDoesNotMoveAConvergedCell) {
  for (RuleKind rule : {RuleKind::kalman, RuleKind::omg}) {
    const std::string name = rule_name(rule);
    const double sigma = 0.005, vm = sigma * sigma;
    for (double gate : {0.0, 3.0}) {
      LayerStack s = converged_cell(rule, gate);
      s.begin_frame(0.0, 0.0);
      const auto [mu, var] = cell_state(s);  // this frame's state: Kalman's inflation included
      ASSERT_NEAR(mu, 0.2, 0.003) << name;
      ASSERT_LT(var, 4 * vm) << name;
      s.insert(MapPoints(PointCloud{point(0.05, 0.05, mu + 1.0, sigma, 0.001)}));
      const auto [mu_after, var_after] = cell_state(s);
      if (gate == 0.0) {
        // Ungated the point moves the cell by the rule's gain on the 1 m innovation:
        // Kalman var / (var + vm) (~ 4 cm), OMG w / (S + w) = 1/201 (200 equal points).
        const double gain = rule == RuleKind::kalman ? var / (var + vm) : 1.0 / 201.0;
        EXPECT_NEAR(mu_after - mu, gain, 1e-3 * gain) << name;
        EXPECT_EQ(s.gate_counts(0).consistency_gate, 0u) << name;
        continue;
      }
      EXPECT_EQ(mu_after, mu) << name;
      EXPECT_EQ(var_after, var) << name;
      EXPECT_EQ(s.gate_counts(0).consistency_gate, 1u) << name;
      // At the edge of the gate, above and below the cell, in one frame: the state the
      // gate tests against is this frame's (the rejected point changed nothing).
      const double edge = gate * std::sqrt(var + vm);
      s.begin_frame(0.0, 0.0);
      const auto [mu2, var2] = cell_state(s);
      const double edge2 = gate * std::sqrt(var2 + vm);
      ASSERT_NEAR(edge2, edge, 0.1 * edge);
      const PointCloud edges{point(0.05, 0.05, mu2 + 1.01 * edge2, sigma, 0.001),
                             point(0.05, 0.05, mu2 - 1.01 * edge2, sigma, 0.001),
                             point(0.05, 0.05, mu2 + 0.99 * edge2, sigma, 0.001),
                             point(0.05, 0.05, mu2 - 0.99 * edge2, sigma, 0.001)};
      EXPECT_EQ(s.insert(MapPoints(edges)), 2u) << name;
      EXPECT_EQ(s.gate_counts(0).consistency_gate, 2u) << name;
      // A new cell takes its first points whatever they are: nothing to be consistent with.
      s.begin_frame(0.0, 0.0);
      EXPECT_EQ(s.insert(MapPoints(PointCloud{point(0.15, 0.05, 5.0, sigma, 0.001),
                                              point(0.15, 0.05, -5.0, sigma, 0.001)})),
                2u)
          << name;
    }
  }
}

}  // namespace
}  // namespace hazmap
