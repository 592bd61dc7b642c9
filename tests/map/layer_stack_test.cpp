// The layer stack: insertion modes, pooling, gating and pose uncertainty.

#include "hazmap/map/layer_stack.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <iterator>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hazmap/core/error.hpp"
#include "hazmap/core/parallel_for.hpp"
#include "hazmap/io/config.hpp"  // validate()
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/ccm.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

Measurement point(double x, double y, double z, double sigma_z, double sigma_xy = 0.002) {
  Measurement m{};
  m.p_W = Eigen::Vector3f(float(x), float(y), float(z));
  m.cov_xx = m.cov_yy = float(sigma_xy * sigma_xy);
  m.cov_zz = float(sigma_z * sigma_z);
  return m;
}

/// Rough terrain: a few planes and bumps with noise, over +-extent around the origin.
PointCloud random_cloud(std::mt19937_64& rng, int n, double extent) {
  std::uniform_real_distribution<double> u(-extent, extent), s(0.002, 0.01);
  std::normal_distribution<double> noise(0.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng), sz = s(rng);
    const double z = 0.1 * x - 0.05 * y + 0.02 * std::sin(13 * x) * std::cos(7 * y) + sz * noise(rng);
    cloud.push_back(point(x, y, z, sz));
  }
  return cloud;
}

MapConfig stack(RuleKind rule, const std::string& insertion, std::vector<std::pair<double, int>> layers) {
  MapConfig map;
  map.insertion = *enum_value<Insertion>(insertion);
  for (auto [r, n] : layers) {
    LayerConfig l;
    l.resolution_m = r;
    l.size = n;
    l.rule = rule;
    map.layers.push_back(l);
  }
  return map;
}

RulesConfig uncapped() {
  RulesConfig rules;
  rules.kalman = {0.0, 0.0};
  rules.omg.max_weight = 1e300;
  rules.ccm.max_weight = 1e300;
  return rules;
}

double rel(double a, double b, double scale) { return std::abs(a - b) / std::max(std::abs(b), scale); }

/// Largest relative difference over every cell of coarse layers between the two modes.
double pooled_vs_all_layers(RuleKind rule, const RulesConfig& rules, std::vector<std::pair<double, int>> layers) {
  LayerStack all(stack(rule, "all_layers", layers), rules);
  LayerStack pool(stack(rule, "finest_then_pool", layers), rules);
  std::mt19937_64 rng(7);
  for (int frame = 0; frame < 4; ++frame) {
    const PointCloud cloud = random_cloud(rng, 20000, 0.6);
    for (LayerStack* s : {&all, &pool}) {
      s->begin_frame(0.001, 0.002);  // no rolling
      s->insert(MapPoints(cloud));
    }
  }
  double worst = 0;
  int compared = 0;
  for (size_t i = 1; i < all.size(); ++i) {
    const RollingGrid& g = all.layer(i).grid();
    for (CellIndex iy = g.origin_y(); iy < g.origin_y() + g.size(); ++iy)
      for (CellIndex ix = g.origin_x(); ix < g.origin_x() + g.size(); ++ix) {
        const Moments a = all.layer(i).cell_moments(ix, iy), b = pool.layer(i).cell_moments(ix, iy);
        EXPECT_EQ(a.empty(), b.empty());
        if (a.empty()) continue;
        ++compared;
        const double spread = std::sqrt(a.szz / a.w) + 1e-6;
        worst = std::max({worst, rel(b.w, a.w, 0), std::abs(b.mz - a.mz) / spread,
                          rel(b.szz, a.szz, 1e-12 * a.w)});
        if (rule == RuleKind::ccm)
          worst = std::max({worst, rel(b.sxx, a.sxx, 0), rel(b.syy, a.syy, 0), rel(b.sxz, a.sxz, 1e-9 * a.w),
                            std::abs(b.mx - a.mx) / g.resolution_m(),
                            rel(b.noise_var, a.noise_var, 0)});
      }
  }
  EXPECT_GT(compared, 50);
  return worst;
}

/// Asserts that two layers over the same window hold bit-identical cells; returns the
/// number of observed cells.
int expect_identical_cells(const Layer& a_layer, const Layer& b_layer, const std::string& what) {
  const RollingGrid& g = a_layer.grid();
  int observed = 0;
  for (CellIndex iy = g.origin_y(); iy < g.origin_y() + g.size(); ++iy)
    for (CellIndex ix = g.origin_x(); ix < g.origin_x() + g.size(); ++ix) {
      const Moments a = a_layer.cell_moments(ix, iy), b = b_layer.cell_moments(ix, iy);
      observed += !a.empty();
      EXPECT_EQ(a.empty(), b.empty()) << what;
      EXPECT_EQ(a.w, b.w) << what;
      EXPECT_EQ(a.mz, b.mz) << what;
      EXPECT_EQ(a.szz, b.szz) << what;
      EXPECT_EQ(a.mx, b.mx) << what;
      EXPECT_EQ(a.sxz, b.sxz) << what;
      EXPECT_EQ(a.noise_var, b.noise_var) << what;
      if (::testing::Test::HasFailure()) return observed;  // one report, not one per cell
    }
  return observed;
}

TEST(LayerStack, FinestThenPoolEqualsAllLayersWithoutRollingOrCap) {
  EXPECT_LT(pooled_vs_all_layers(RuleKind::ccm, uncapped(), {{0.04, 8}, {0.08, 8}, {0.16, 8}}), 1e-5);
  EXPECT_LT(pooled_vs_all_layers(RuleKind::omg, uncapped(), {{0.02, 16}, {0.04, 16}, {0.16, 8}}), 1e-5);
  EXPECT_LT(pooled_vs_all_layers(RuleKind::kalman, uncapped(), {{0.02, 16}, {0.04, 16}, {0.16, 8}}), 1e-5);
}

TEST(LayerStack, WithTheWeightCapPoolingDiffersAndTheDifferenceIsReported) {
  RulesConfig capped = uncapped();
  capped.ccm.max_weight = 50;
  const double diff = pooled_vs_all_layers(RuleKind::ccm, capped, {{0.04, 8}, {0.08, 8}, {0.16, 8}});
  RecordProperty("ccm_capped_max_relative_difference", std::to_string(diff));
  std::printf("finest_then_pool vs all_layers with ccm.max_weight = 50: max relative difference %.3g\n", diff);
  EXPECT_GT(diff, 1e-3);  // the cap acts on different point sets in the two modes
}

// Timing each layer must not change what is inserted, and the layers' shares must add
// up to no more than the call's wall time.
TEST(LayerStack, PerLayerTimesLeaveTheMapUnchangedAndSumToTheCallsTime) {
  for (const std::string insertion : {"all_layers", "finest_then_pool"}) {
    const MapConfig map = stack(RuleKind::ccm, insertion, {{0.02, 32}, {0.04, 16}, {0.16, 8}});
    LayerStack plain(map, uncapped()), timed(map, uncapped());
    std::mt19937_64 rng(11);
    std::vector<double> layer_ms(timed.size(), -1.0);
    for (int frame = 0; frame < 3; ++frame) {
      const MapPoints points(random_cloud(rng, 5000, 0.3));
      plain.begin_frame(0.001, 0.002);
      timed.begin_frame(0.001, 0.002);
      const std::size_t expected = plain.insert(points);
      const auto start = std::chrono::steady_clock::now();
      EXPECT_EQ(timed.insert(points, layer_ms.data()), expected) << insertion;
      const double wall_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      double sum = 0;
      for (const double ms : layer_ms) {
        EXPECT_GT(ms, 0.0) << insertion;
        sum += ms;
      }
      EXPECT_LE(sum, wall_ms * (1 + 1e-9)) << insertion;
    }
    for (size_t i = 0; i < plain.size(); ++i)
      expect_identical_cells(plain.layer(i), timed.layer(i), insertion + " layer " + std::to_string(i));
  }
}

/// One single-layer stack per layer of `map`: what each layer of the stack must equal.
std::vector<std::unique_ptr<LayerStack>> each_layer_alone(const MapConfig& map,
                                                          const RulesConfig& rules) {
  std::vector<std::unique_ptr<LayerStack>> alone;
  for (const LayerConfig& layer : map.layers) {
    MapConfig one = map;
    one.layers = {layer};
    alone.push_back(std::make_unique<LayerStack>(one, rules));
  }
  return alone;
}

/// A frame into each of `stacks` (begin_frame at the robot, then the points); the cell
/// updates summed, which the whole stack's insert must return.
std::size_t insert_into_each(const std::vector<std::unique_ptr<LayerStack>>& stacks,
                             const MapPoints& points, double robot_x, double robot_y) {
  std::size_t updates = 0;
  for (const auto& s : stacks) {
    s->begin_frame(robot_x, robot_y);
    updates += s->insert(points);
  }
  return updates;
}

// The stack hands each chunk to its layers coarsest first (whoever reads a chunk first
// pays for its cache misses); a layer's state must still be exactly what it would be
// alone: a mixed stack, rolling, against one single-layer stack per layer.
TEST(LayerStack, EachLayerOfAMixedStackEqualsTheSameLayerAlone) {
  MapConfig map = stack(RuleKind::kalman, "all_layers", {{0.02, 32}, {0.04, 16}, {0.16, 8}});
  map.layers[1].rule = map.layers[2].rule = RuleKind::ccm;
  const RulesConfig rules;
  LayerStack mixed(map, rules);
  const auto alone = each_layer_alone(map, rules);
  std::mt19937_64 rng(5);
  for (int frame = 0; frame < 4; ++frame) {
    const MapPoints points(random_cloud(rng, 6000, 0.4));
    const double robot_x = 0.03 * frame, robot_y = -0.05 * frame;  // rolls the finer layers
    mixed.begin_frame(robot_x, robot_y);
    EXPECT_EQ(mixed.insert(points), insert_into_each(alone, points, robot_x, robot_y));
  }
  for (size_t i = 0; i < mixed.size(); ++i)
    EXPECT_GT(expect_identical_cells(mixed.layer(i), alone[i]->layer(0), "layer " + std::to_string(i)), 30)
        << "layer " << i;
}

/// Every published grid of two layers, bit for bit (NaN where the other has NaN, and the
/// same payload), with the geometry.
void expect_same_grids(const LayerGrids& a, const LayerGrids& b, const std::string& what) {
  const DenseGrid LayerGrids::*grids[] = {
      &LayerGrids::height,     &LayerGrids::variance,   &LayerGrids::count,
      &LayerGrids::slope_x,    &LayerGrids::slope_y,    &LayerGrids::roughness,
      &LayerGrids::coverage,   &LayerGrids::evaluable,  &LayerGrids::noise_variance,
      &LayerGrids::lateral_xx, &LayerGrids::lateral_yy, &LayerGrids::lateral_xy,
      &LayerGrids::lateral_xz, &LayerGrids::lateral_yz};
  for (std::size_t k = 0; k < std::size(grids); ++k) {
    const DenseGrid &ga = a.*grids[k], &gb = b.*grids[k];
    ASSERT_EQ(ga.rows, gb.rows) << what << ", grid " << k;
    ASSERT_EQ(ga.cols, gb.cols) << what << ", grid " << k;
    EXPECT_EQ(ga.center_x_m, gb.center_x_m) << what << ", grid " << k;
    EXPECT_EQ(ga.center_y_m, gb.center_y_m) << what << ", grid " << k;
    ASSERT_EQ(ga.values.size(), gb.values.size()) << what << ", grid " << k;
    // memcmp of an empty grid's null data is undefined (UBSan): compare only a payload.
    if (!ga.values.empty()) {
      EXPECT_EQ(0, std::memcmp(ga.values.data(), gb.values.data(), ga.values.size() * sizeof(float)))
          << what << ", grid " << k;
    }
  }
}

/// Scan lines across +-0.35 m in x, 3 mm apart along a line (runs of consecutive points
/// per cell, as the pipeline makes them), lines 1 cm apart, over a sloped, bumpy surface
/// with noise; lateral spread and height variance vary along the line, so that the SPEC 4
/// gates drop some points.
PointCloud scan_lines(std::mt19937_64& rng, double x0, double y0) {
  std::normal_distribution<double> noise(0.0, 1.0);
  PointCloud cloud;
  for (int row = 0; row < 60; ++row)
    for (int k = 0; k < 234; ++k) {
      const double x = x0 - 0.35 + 0.003 * k, y = y0 - 0.3 + 0.01 * row;
      const double sz = 0.002 + 0.004 * (k % 7) / 6.0, sxy = 0.001 + 0.01 * ((k + row) % 11) / 10.0;
      const double z = 0.08 * x + 0.03 * std::sin(17 * x) * std::cos(11 * y) + sz * noise(rng);
      cloud.push_back(point(x, y, z, sz, sxy));
    }
  return cloud;
}

// A layer inside a stack publishes exactly what the same layer publishes alone: every
// rule in each position of an all_layers stack, every grid bit for bit, with the gates
// on, the window rolling, and the changed cells and gate counts compared too. (The stack
// shares each chunk among its layers and grows the bounding box in its chunk loop; none
// of that may reach a layer's cells.)
TEST(LayerStack, EveryRuleInAStackPublishesTheSameBitsAsAlone) {
  RulesConfig rules;  // shipped defaults (floors, caps, time inflation), plus the gates:
  rules.kalman.gate_sigma = 3.0;
  rules.omg.gate_sigma = 3.0;
  rules.ccm.max_std_ratio = 1.0;
  for (const RuleInfo& row : kRuleTable) {  // every rule in the registry
    const RuleKind rule = row.kind;
    MapConfig map = stack(RuleKind::kalman, "all_layers", {{0.02, 48}, {0.04, 24}, {0.08, 16}, {0.16, 8}});
    map.layers[0].rule = rule;
    map.layers[2].rule = RuleKind::ccm;
    map.layers[3].rule = RuleKind::omg;
    map.layers[1].max_std_ratio = 0.5;  // a layer's own lateral gate
    LayerStack mixed(map, rules);
    const auto alone = each_layer_alone(map, rules);
    std::mt19937_64 rng(23);
    MapPoints points;
    for (int frame = 0; frame < 5; ++frame) {
      const double robot_x = 0.05 * frame, robot_y = -0.03 * frame;  // rolls every layer
      points.assign(scan_lines(rng, robot_x + 0.1, robot_y), CcmWeighting::constant);
      mixed.begin_frame(robot_x, robot_y);
      EXPECT_EQ(mixed.insert(points), insert_into_each(alone, points, robot_x, robot_y));
      for (std::size_t i = 0; i < mixed.size(); ++i) {
        const std::string what = std::string(rule_name(rule)) + " stack, layer " +
                                 std::to_string(i) + ", frame " + std::to_string(frame);
        LayerGrids in_stack, by_itself;
        mixed.export_layer(i, in_stack);
        alone[i]->export_layer(0, by_itself);
        expect_same_grids(in_stack, by_itself, what);
        const CellRange a = mixed.changed_cells(i), b = alone[i]->changed_cells(0);
        EXPECT_TRUE(a.x0 == b.x0 && a.x1 == b.x1 && a.y0 == b.y0 && a.y1 == b.y1) << what;
        EXPECT_FALSE(a.empty()) << what;
        EXPECT_EQ(mixed.gate_counts(i).std_gate, alone[i]->gate_counts(0).std_gate) << what;
        EXPECT_EQ(mixed.gate_counts(i).consistency_gate,
                  alone[i]->gate_counts(0).consistency_gate) << what;
        if (frame == 4) {
          EXPECT_GT(expect_identical_cells(mixed.layer(i), alone[i]->layer(0), what), 20) << what;
          // The gates bit somewhere: otherwise this would not test them.
          if (i == 1) {
            EXPECT_GT(mixed.gate_counts(i).std_gate, 0u) << what;
          }
        }
        if (::testing::Test::HasFailure()) return;
      }
    }
  }
}

// Layers inserted on several threads (each thread a set of layers through every chunk,
// the sets rebalanced from the frame before's times): every grid bit for bit as on one
// thread, the changed cells, gate counts and updates too, timed or not, on 2 and 3
// threads over a 5-layer mixed stack that rolls.
TEST(LayerStack, LayersOnSeveralThreadsPublishTheSameBitsAsOnOne) {
  RulesConfig rules;
  rules.kalman.gate_sigma = 3.0;
  rules.ccm.max_std_ratio = 1.0;
  MapConfig map = stack(RuleKind::kalman, "all_layers",
                        {{0.01, 64}, {0.02, 48}, {0.04, 24}, {0.08, 16}, {0.16, 8}});
  map.layers[1].rule = map.layers[3].rule = RuleKind::ccm;
  map.layers[4].rule = RuleKind::omg;
  for (const int threads : {2, 3})
    for (const bool timed : {false, true}) {
      const testing::ThreadsFor pool(threads);
      LayerStack serial(map, rules), parallel(map, rules);
      parallel.set_parallel(&pool);
      std::vector<double> layer_ms(map.layers.size(), -1.0);
      std::mt19937_64 rng(29);
      MapPoints points;
      for (int frame = 0; frame < 5; ++frame) {
        const double robot_x = 0.04 * frame, robot_y = 0.02 * frame;
        points.assign(scan_lines(rng, robot_x + 0.1, robot_y), CcmWeighting::constant);
        serial.begin_frame(robot_x, robot_y);
        parallel.begin_frame(robot_x, robot_y);
        const std::size_t expected = serial.insert(points);
        EXPECT_EQ(parallel.insert(points, timed ? layer_ms.data() : nullptr), expected);
        for (std::size_t i = 0; i < serial.size(); ++i) {
          const std::string what = std::to_string(threads) + " threads" + (timed ? ", timed" : "") +
                                   ", layer " + std::to_string(i) + ", frame " +
                                   std::to_string(frame);
          LayerGrids a, b;
          serial.export_layer(i, a);
          parallel.export_layer(i, b);
          expect_same_grids(a, b, what);
          const CellRange ca = serial.changed_cells(i), cb = parallel.changed_cells(i);
          EXPECT_TRUE(ca.x0 == cb.x0 && ca.x1 == cb.x1 && ca.y0 == cb.y0 && ca.y1 == cb.y1) << what;
          EXPECT_EQ(serial.gate_counts(i).std_gate, parallel.gate_counts(i).std_gate) << what;
          EXPECT_EQ(serial.gate_counts(i).consistency_gate,
                    parallel.gate_counts(i).consistency_gate)
              << what;
          if (timed) {
            EXPECT_GT(layer_ms[i], 0.0) << what;  // every layer ran, and was timed
          }
          if (frame == 4) {
            EXPECT_GT(expect_identical_cells(serial.layer(i), parallel.layer(i), what), 20) << what;
          }
          if (::testing::Test::HasFailure()) return;
        }
      }
    }
}

TEST(LayerStack, MixedFamiliesNeedAllLayers) {
  Config c;
  c.map = stack(RuleKind::kalman, "finest_then_pool", {{0.01, 8}, {0.04, 8}});
  c.map.layers[1].rule = RuleKind::ccm;
  try {
    validate(c);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("map.layers.1.rule"), std::string::npos) << e.what();
  }
  c.map.insertion = Insertion::all_layers;
  EXPECT_NO_THROW(validate(c));
}

TEST(LayerStack, GateDropsPointsWithLargeLateralSpreadForCcmLayers) {
  RulesConfig rules = uncapped();
  rules.ccm.max_std_ratio = 1.0;  // gate: std <= r / sqrt(12) = 1.15 cm at r = 4 cm
  LayerStack s(stack(RuleKind::ccm, "all_layers", {{0.04, 8}}), rules);
  s.begin_frame(0, 0);
  PointCloud cloud{point(0.01, 0.01, 0, 0.01, 0.005), point(0.01, 0.01, 0, 0.01, 0.02)};
  EXPECT_EQ(s.insert(MapPoints(cloud)), 1u);
  rules.ccm.max_std_ratio = 0.0;
  LayerStack open(stack(RuleKind::ccm, "all_layers", {{0.04, 8}}), rules);
  open.begin_frame(0, 0);
  EXPECT_EQ(open.insert(MapPoints(cloud)), 2u);
}

TEST(LayerStack, PoseUncertaintyInflatesVarianceBySpec7) {
  // Kalman layer on a plane z = 0.5 x; then two frames of pose noise without points.
  RulesConfig rules = uncapped();
  LayerStack s(stack(RuleKind::kalman, "all_layers", {{0.1, 16}}), rules, /*pose_uncertainty=*/true);
  s.begin_frame(0.05, 0.05);
  PointCloud cloud;
  for (int iy = -8; iy < 8; ++iy)
    for (int ix = -8; ix < 8; ++ix) {
      const double x = (ix + 0.5) * 0.1, y = (iy + 0.5) * 0.1;
      cloud.push_back(point(x, y, 0.5 * x, 0.01));
    }
  s.insert(MapPoints(cloud));
  const PoseNoise noise{0.01, 0.02, 0.005, 0.01};
  s.begin_frame(0.05, 0.05, noise);
  s.begin_frame(0.05, 0.05, noise);
  LayerGrids g;
  s.export_layer(0, g);
  // Cell at x = 0.35, y = -0.25 (interior): o = cell - robot = (0.3, -0.3), g = (0.5, 0).
  int row = 0, col = 0;
  ASSERT_TRUE(g.variance.cell_at(0.35, -0.25, &row, &col));
  const double ox = 0.3, oy = -0.3, gx = 0.5, gy = 0.0, k = 2.0;  // two frames of noise
  const double lat = gx * (-oy) + gy * ox;                          // g . [-o_y, o_x]
  const double expected = 1e-4 + k * (gx * gx * 1e-4 + gy * gy * 4e-4 + 1e-4 * lat * lat + 2.5e-5);
  EXPECT_NEAR(g.variance.at(row, col), expected, 1e-6 * expected);
}

/// Each fusing rule's layer, fed scan lines (runs of consecutive points per cell, as the
/// pipeline produces them) over three frames, equals a batch computation in double per
/// cell: Kalman and OMG the inverse-variance mean and weight, CCM the weighted moments.
TEST(LayerStack, ScanLineInsertionEqualsBatchPerCell) {
  const double r = 0.04;
  const int n = 16;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4), sigma(0.002, 0.01);
  PointCloud cloud;
  for (int frame = 0; frame < 3; ++frame)
    for (int line = 0; line < 90; ++line)  // scan lines across y, ~9 points per cell
      for (int k = 0; k < 140; ++k) {
        const double x = -0.3 + (line + jitter(rng)) * 0.0066, y = -0.3 + (k + jitter(rng)) * 0.0043;
        const double sz = sigma(rng);
        cloud.push_back(point(x, y, 0.4 + 0.1 * x - 0.05 * y + sz * noise(rng), sz));
      }
  const std::size_t per_frame = cloud.size() / 3;
  // Batch moments per global cell index, in double.
  std::map<std::pair<CellIndex, CellIndex>, std::vector<const Measurement*>> cells;
  for (const Measurement& m : cloud) cells[{cell_index(m.p_W.x(), r), cell_index(m.p_W.y(), r)}].push_back(&m);
  for (RuleKind rule : {RuleKind::kalman, RuleKind::omg, RuleKind::ccm}) {
    LayerStack s(stack(rule, "all_layers", {{r, n}}), uncapped());
    for (int frame = 0; frame < 3; ++frame) {
      s.begin_frame(0.0, 0.0);
      const PointCloud part(cloud.begin() + frame * per_frame, cloud.begin() + (frame + 1) * per_frame);
      s.insert(MapPoints(part));
    }
    int compared = 0;
    for (const auto& [key, pts] : cells) {
      const Moments got = s.layer(0).cell_moments(key.first, key.second);
      ASSERT_FALSE(got.empty());
      Moments ref;
      for (const Measurement* m : pts) {
        const double w = rule == RuleKind::ccm ? 1.0 : 1.0 / double(m->cov_zz);
        ref.w += w;
        ref.mz += w * m->p_W.z();
        ref.mx += w * (m->p_W.x() - cell_center(key.first, r));
      }
      ref.mz /= ref.w;
      ref.mx /= ref.w;
      double szz = 0;
      for (const Measurement* m : pts) {
        const double w = rule == RuleKind::ccm ? 1.0 : 1.0 / double(m->cov_zz);
        szz += w * (m->p_W.z() - ref.mz) * (m->p_W.z() - ref.mz);
      }
      const double spread = std::sqrt(szz / ref.w);
      ASSERT_NEAR(got.w, ref.w, 1e-6 * ref.w) << rule_name(rule);
      ASSERT_NEAR(got.mz, ref.mz, 1e-5 * spread) << rule_name(rule);
      if (rule == RuleKind::ccm) {
        ASSERT_NEAR(got.mx, ref.mx, 1e-5 * r);
        ASSERT_NEAR(got.szz, szz, 1e-5 * szz);
      }
      if (rule == RuleKind::omg) {
        const double expected = szz + double(pts.size());  // spread + one per point
        ASSERT_NEAR(got.szz, expected, 1e-5 * expected);
      }
      ++compared;
    }
    EXPECT_GT(compared, 100);
  }
}

TEST(LayerStack, CcmLayerExportsPlaneGrids) {
  LayerStack s(stack(RuleKind::ccm, "all_layers", {{0.04, 8}}), uncapped());
  s.begin_frame(0.0, 0.0);
  PointCloud cloud;
  for (int j = 0; j < 160; ++j)
    for (int i = 0; i < 160; ++i) {
      const double x = -0.16 + (i + 0.5) * 0.002, y = -0.16 + (j + 0.5) * 0.002;
      cloud.push_back(point(x, y, 0.2 * x - 0.1 * y + 1.0, 0.001));
    }
  s.insert(MapPoints(cloud));
  LayerGrids g;
  s.export_layer(0, g);
  ASSERT_EQ(g.slope_x.rows, 8);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) {
      EXPECT_NEAR(g.slope_x.at(r, c), 0.2, 1e-4);
      EXPECT_NEAR(g.slope_y.at(r, c), -0.1, 1e-4);
      const double x = g.height.x_of_col(c), y = g.height.y_of_row(r);
      EXPECT_NEAR(g.height.at(r, c), 0.2 * x - 0.1 * y + 1.0, 1e-5);  // plane at the centre
      EXPECT_EQ(g.evaluable.at(r, c), 1.0f);
    }
}

// Issue 24: the pose enters the map in begin_frame; a position beyond 2^30 cells of any
// layer is refused there, naming the layer, before any layer has moved.
TEST(LayerStack, PositionBeyondTheCellLimitIsRefusedBeforeAnyLayerMoves) {
  LayerStack s(stack(RuleKind::kalman, "all_layers", {{0.01, 8}, {0.04, 8}}), uncapped());
  s.begin_frame(0.5, 0.5);
  const double x0 = s.layer(0).grid().center_x_m(), x1 = s.layer(1).grid().center_x_m();
  // 2e7 m: within 2^30 cells of the 4 cm layer (5e8), not of the 1 cm one (2e9).
  try {
    s.begin_frame(2e7, 0.5);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "map: robot position x = 2e+07 m is 2e+09 cells of a 0.01 m layer: |x / "
              "resolution| must stay below 2^30 cells (a pose far outside any traverse, or a "
              "bad pose file) (layer 0)");
  }
  EXPECT_EQ(s.layer(0).grid().center_x_m(), x0);
  EXPECT_EQ(s.layer(1).grid().center_x_m(), x1);
}

}  // namespace
}  // namespace hazmap
