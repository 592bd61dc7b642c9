// Hazard segmentation on analytic terrain (SPEC 8): points generated directly on a known
// surface with sensor-level noise, fused by the real layer stack, classified by the
// real hazard code.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "hazmap/map/layer_stack.hpp"
#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/hazard/plane_classifier.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {
namespace {

using Surface = std::function<double(double, double)>;

/// Layers as in the thesis tables: Kalman 1 cm (kernel 7) and CCM 4 ... 64 cm.
Config analytic_config(const std::vector<std::pair<RuleKind, double>>& layers,
                       int cells_per_side_m = 4) {
  Config c;
  for (auto [rule, r] : layers) {
    LayerConfig l;
    l.rule = rule;
    l.resolution_m = r;
    l.size = std::max(16, 2 * static_cast<int>(std::ceil(cells_per_side_m / r / 2)));
    l.hazard.kernel = r < 0.02 ? 7 : r < 0.5 ? 5 : 3;
    c.map.layers.push_back(l);
  }
  c.rules.ccm.max_weight = 1e6;
  return c;
}

/// Samples the surface on a square grid of `spacing` over +-half, with Gaussian height
/// noise sigma, and runs hazards on every layer. Returns the views.
/// Keeps a point at (x, y) when true (what the cameras see).
using Visible = std::function<bool(double, double)>;

std::vector<LayerView> map_surface(const Config& config, const Surface& h, double half_m,
                                   double spacing_m, double sigma_m, unsigned seed = 1,
                                   const Visible& visible = nullptr, double lateral_sigma_m = 0.001) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  PointCloud cloud;
  for (double y = -half_m; y < half_m; y += spacing_m)
    for (double x = -half_m; x < half_m; x += spacing_m) {
      const double px = x + jitter(rng) * spacing_m, py = y + jitter(rng) * spacing_m;
      if (visible && !visible(px, py)) continue;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(px), float(py), float(h(px, py) + noise(rng)));
      m.cov_xx = m.cov_yy = float(lateral_sigma_m * lateral_sigma_m);
      m.cov_zz = float(sigma_m * sigma_m);
      cloud.push_back(m);
    }
  LayerStack stack(config.map, config.rules);
  stack.begin_frame(0.001, 0.001);
  stack.insert(MapPoints(cloud));
  std::vector<LayerView> views(stack.size());
  const HazardParams params = resolve_hazard_params(config);
  for (size_t i = 0; i < stack.size(); ++i) {
    stack.export_layer(i, views[i].map);
    make_hazard_classifier(params.layers[i])
        ->classify(views[i].map, views[i].hazard, views[i].diagnostics);
  }
  return views;
}

struct Counts {
  int unknown = 0, traversable = 0, hazard = 0;
};
/// Class counts over cells whose centre lies within |x|, |y| < limit (the data's
/// border is left out: there a kernel sees only half a slope).
Counts count(const DenseGrid& hazard, double limit_m = 1.2) {
  Counts c;
  for (int row = 0; row < hazard.rows; ++row)
    for (int col = 0; col < hazard.cols; ++col) {
      if (std::abs(hazard.x_of_col(col)) >= limit_m || std::abs(hazard.y_of_row(row)) >= limit_m)
        continue;
      const auto k = static_cast<HazardClass>(int(hazard.at(row, col)));
      (k == HazardClass::hazard        ? c.hazard
       : k == HazardClass::traversable ? c.traversable
                                       : c.unknown)++;
    }
  return c;
}

const std::vector<std::pair<RuleKind, double>> kAllLayers = {
    {RuleKind::kalman, 0.01}, {RuleKind::ccm, 0.04}, {RuleKind::ccm, 0.08},
    {RuleKind::ccm, 0.16},    {RuleKind::ccm, 0.32}, {RuleKind::ccm, 0.64}};

TEST(AnalyticHazards, NoisyFlatPlaneHasNoHazardOnAnyLayer) {
  const Config config = analytic_config(kAllLayers);
  // 2 mm height noise: the stereo sensor model at 0.5 m with CADRE's full resolution.
  const auto views = map_surface(
      config, [](double, double) { return 0.05; }, 1.4, 0.003, 0.002);
  for (size_t i = 0; i < views.size(); ++i) {
    const Counts c = count(views[i].hazard);
    EXPECT_EQ(c.hazard, 0) << "layer " << i;
    EXPECT_GT(c.traversable, 0) << "layer " << i;
  }
}

TEST(AnalyticHazards, RampsAbove20DegAreHazardsAndBelowAreNotOnEveryLayer) {
  const Config config = analytic_config(kAllLayers);
  for (const double deg : {15.0, 25.0}) {
    const double t = std::tan(deg * M_PI / 180.0);
    const auto views = map_surface(
        config, [t](double x, double) { return t * x; }, 1.4, 0.003, 0.001);
    for (size_t i = 0; i < views.size(); ++i) {
      const Counts c = count(views[i].hazard);
      if (deg < 20) {
        EXPECT_EQ(c.hazard, 0) << deg << " deg, layer " << i;
        EXPECT_GT(c.traversable, 0) << deg << " deg, layer " << i;
      } else {
        EXPECT_EQ(c.traversable, 0) << deg << " deg, layer " << i;
        EXPECT_GT(c.hazard, 0) << deg << " deg, layer " << i;
      }
    }
  }
}

TEST(AnalyticHazards, StepOfThreeQuartersOfTheCellIsAHazardAndThirtyPercentIsNot) {
  const double r = 0.04;
  const Config config = analytic_config({{RuleKind::ccm, r}});
  for (const double p : {0.25, 0.5, 0.75}) {
    for (const double height : {0.75 * r, 0.3 * r}) {
      // Cell [0, r) x [0, r): the step covers its upper fraction p in x.
      const double x0 = r * (1.0 - p);
      const auto views = map_surface(
          config, [&](double x, double) { return x >= x0 ? height : 0.0; }, 0.6, 0.002, 0.0005);
      int row = 0, col = 0;
      ASSERT_TRUE(views[0].hazard.cell_at(0.5 * r, 0.5 * r, &row, &col));
      const auto cls = static_cast<HazardClass>(int(views[0].hazard.at(row, col)));
      if (height > 0.5 * r)
        EXPECT_EQ(cls, HazardClass::hazard) << "p = " << p << ", h = " << height;
      else
        EXPECT_EQ(cls, HazardClass::traversable) << "p = " << p << ", h = " << height;
    }
  }
}

/// Hemispherical rock of radius R at (xc, yc) on flat ground.
Surface rock(double radius, double xc = 0.2, double yc = 0.1) {
  return [=](double x, double y) {
    const double d2 = (x - xc) * (x - xc) + (y - yc) * (y - yc);
    return d2 < radius * radius ? std::sqrt(radius * radius - d2) : 0.0;
  };
}

/// Distance from a cell centre of `grid` to the rock's rim (negative inside).
double rim_distance(const DenseGrid& g, int row, int col, double radius, double xc = 0.2,
                    double yc = 0.1) {
  return std::hypot(g.x_of_col(col) - xc, g.y_of_row(row) - yc) - radius;
}

TEST(AnalyticHazards, ThreeCentimetreRockIsSeenByFineLayersOnlyAndOnlyNearIt) {
  Config config = analytic_config(kAllLayers);
  config.map.layers[0].hazard.roughness_threshold_m = 0.025;  // thesis Table 7.3, 1 cm layer
  const double R = 0.03;
  const auto views = map_surface(config, rock(R), 1.4, 0.002, 0.001);
  // Kalman 1 cm: hazard cells exist, none farther than the kernel radius from the rim.
  {
    const DenseGrid& h = views[0].hazard;
    int near = 0;
    for (int row = 0; row < h.rows; ++row)
      for (int col = 0; col < h.cols; ++col)
        if (h.at(row, col) == float(HazardClass::hazard)) {
          ++near;
          EXPECT_LE(rim_distance(h, row, col, R), 3.5 * 0.01 + 0.005) << row << "," << col;
        }
    EXPECT_GT(near, 0);
  }
  // CCM 4 cm: hazard cells exist, none farther than one cell from the rim.
  {
    const DenseGrid& h = views[1].hazard;
    int near = 0;
    for (int row = 0; row < h.rows; ++row)
      for (int col = 0; col < h.cols; ++col)
        if (h.at(row, col) == float(HazardClass::hazard)) {
          ++near;
          // Cell centre within one cell (plus half a cell diagonal) of the rim.
          EXPECT_LE(rim_distance(h, row, col, R), 0.04 + 0.04 * std::sqrt(0.5))
              << row << "," << col;
        }
    EXPECT_GT(near, 0);
  }
  EXPECT_EQ(count(views[5].hazard).hazard, 0);  // 64 cm
  EXPECT_GT(count(views[5].hazard).traversable, 0);
}

TEST(AnalyticHazards, TenCentimetreRockIsAHazardOnThe4And8CentimetreLayers) {
  const Config config = analytic_config(kAllLayers);
  const auto views = map_surface(config, rock(0.10), 1.4, 0.002, 0.001);
  EXPECT_GT(count(views[1].hazard).hazard, 0);
  EXPECT_GT(count(views[2].hazard).hazard, 0);
}

TEST(AnalyticHazards, NoisyFarPlaneIsUnknownNotHazardOnEveryLayer) {
  // Far ground as stereo sees it at ~3 m: few points per cell, each with 4 cm height and
  // 6 mm lateral sigma. Layers take only points whose noise suits them (max_std_ratio 1,
  // as the shipped configs): the 1 cm layer gets none. Nothing proves a hazard there, and
  // nothing proves the ground clear of 3 cm rocks.
  Config config = analytic_config(kAllLayers);
  for (auto& l : config.map.layers) l.max_std_ratio = 1.0;
  auto flat = [](double, double) { return 0.0; };
  const auto views = map_surface(config, flat, 1.4, 0.02, 0.04, 1, nullptr, 0.006);
  for (size_t i = 0; i < views.size(); ++i) EXPECT_EQ(count(views[i].hazard).hazard, 0) << "layer " << i;
  EXPECT_EQ(count(views[0].hazard).traversable, 0);
  EXPECT_EQ(count(views[1].hazard).traversable, 0);
  // The thesis' plain comparisons (k = 0), without gating, turn the same noise into
  // hazards on the 1 cm layer.
  config.hazard.k_sigma = 0;
  for (auto& l : config.map.layers) l.max_std_ratio = 0.0;
  const auto plain = map_surface(config, flat, 1.4, 0.02, 0.04, 1, nullptr, 0.006);
  EXPECT_GT(count(plain[0].hazard).hazard, 1000);
}

TEST(AnalyticHazards, OneFaceOfARockIsAHazard) {
  // Only the near half of a 6 cm rock is seen (its far side is hidden from the cameras),
  // and nothing behind it: the visible face is evidence enough on the fine layers.
  const Config config = analytic_config(kAllLayers);
  const double R = 0.06, xc = 0.2, yc = 0.1;
  const auto views = map_surface(config, rock(R, xc, yc), 1.4, 0.002, 0.001, 1,
                                 [&](double x, double) { return x < xc; });
  for (size_t i : {0u, 1u}) {
    int on_face = 0;
    const DenseGrid& h = views[i].hazard;
    for (int row = 0; row < h.rows; ++row)
      for (int col = 0; col < h.cols; ++col)
        if (h.at(row, col) == float(HazardClass::hazard) && h.x_of_col(col) < xc &&
            rim_distance(h, row, col, R, xc, yc) < 0)
          ++on_face;
    EXPECT_GT(on_face, 0) << "layer " << i;
  }
  // Nothing behind the rock was seen, so nothing there is traversable.
  int row = 0, col = 0;
  ASSERT_TRUE(views[0].hazard.cell_at(xc + 0.1, yc, &row, &col));
  EXPECT_NE(views[0].hazard.at(row, col), float(HazardClass::traversable));
}

TEST(AnalyticHazards, FlatRockTopWiderThanTheKernelIsAHazardOnEveryLayerThatVouchesForIt) {
  // A 6 cm high block with a flat 24 cm x 24 cm top: its centre looks smooth to the 7-cell
  // kernel and to a 4 cm plane, but stands 6 cm above the wheel ring (radius 15 cm).
  const Config config = analytic_config(kAllLayers);
  const double xc = 0.3, yc = 0.1, half = 0.12;
  const auto views = map_surface(
      config,
      [&](double x, double y) { return std::abs(x - xc) < half && std::abs(y - yc) < half ? 0.06 : 0.0; },
      1.4, 0.002, 0.001);
  const HazardParams params = resolve_hazard_params(config);
  for (size_t i = 0; i < views.size(); ++i) {
    // Layers that vouch for 6 cm obstacles (h_min well below the block): 1 and 4 cm.
    if (params.layers[i].h_min_m > 0.04) continue;
    int row = 0, col = 0;
    ASSERT_TRUE(views[i].hazard.cell_at(xc + 0.001, yc + 0.001, &row, &col));
    EXPECT_EQ(views[i].hazard.at(row, col), float(HazardClass::hazard)) << "layer " << i;
  }
  // The roughness kernel alone calls the top's centre traversable: the ring is what sees it.
  int row = 0, col = 0;
  ASSERT_TRUE(views[0].diagnostics.kernel_range.cell_at(xc + 0.001, yc + 0.001, &row, &col));
  EXPECT_LT(views[0].diagnostics.kernel_range.at(row, col), 0.005);
}

TEST(AnalyticHazards, RockTopIsAHazardWhenTheGroundAroundIsOnlyPartlySeen) {
  // A 6 cm block with an 18 cm top (the wheel ring, radius 15 cm, lies on the ground
  // around it), but the ground is seen in 1.2 cm strips only (every 4 cm cell's points
  // cover a third of it: no ground cell of the 4 cm layer is evaluable), as next to a
  // real rock. The ring's samples on those cells are evidence (mu_z with its honest
  // variance), so the top is a hazard; they never prove anything.
  const Config config = analytic_config({{RuleKind::ccm, 0.04}});
  const double xc = 0.3, yc = 0.1, half = 0.09;
  const auto on_top = [&](double x, double y) {
    return std::abs(x - xc) < half && std::abs(y - yc) < half;
  };
  const Visible strips = [&](double x, double y) {
    return on_top(x, y) || std::fmod(x + 10.0, 0.04) < 0.012;
  };
  const auto views = map_surface(
      config, [&](double x, double y) { return on_top(x, y) ? 0.06 : 0.0; }, 1.4, 0.002, 0.001, 3,
      strips);
  const DenseGrid& h = views[0].hazard;
  const LayerGrids& g = views[0].map;
  int row = 0, col = 0;
  ASSERT_TRUE(h.cell_at(xc + 0.001, yc + 0.001, &row, &col));
  EXPECT_EQ(h.at(row, col), float(HazardClass::hazard));
  int ground_cells = 0;
  for (int r = 0; r < h.rows; ++r)
    for (int c = 0; c < h.cols; ++c) {
      const double x = h.x_of_col(c), y = h.y_of_row(r);
      if (std::abs(x) > 1.2 || std::abs(y) > 1.2 || std::hypot(x - xc, y - yc) < 0.4) continue;
      if (std::isnan(g.height.at(r, c))) continue;
      ++ground_cells;
      EXPECT_EQ(g.evaluable.at(r, c), 0.0f);
      // Flat ground seen in strips: neither proven traversable nor (noise) a hazard.
      EXPECT_EQ(h.at(r, c), float(HazardClass::unknown)) << x << " " << y;
    }
  EXPECT_GT(ground_cells, 1000);
}

TEST(AnalyticHazards, FewPointsOnARockTopAreStepEvidenceAndFewOnGroundProveNothing) {
  // A 6 cm block with an 18 cm top, the ground around it fully seen, the top seen by a
  // few points per 4 cm cell only (fewer than min_points: no plane test runs there), as
  // a rock's top from a low camera. The cells' mean heights stand 6 cm above the ring:
  // hazard. The same sparse sampling on flat ground far away is neither hazard nor
  // traversable.
  const Config config = analytic_config({{RuleKind::ccm, 0.04}});
  const double xc = 0.3, yc = 0.1, half = 0.09;
  const auto on_top = [&](double x, double y) {
    return std::abs(x - xc) < half && std::abs(y - yc) < half;
  };
  const auto sparse_patch = [](double x, double y) {
    return x > -0.8 && x < -0.4 && y > -0.8 && y < -0.4;
  };
  // About 4 of a cell's 400 grid points (2 mm spacing, jittered), near its centre.
  const auto few = [](double x, double y) {
    return std::abs(std::fmod(x + 10.0, 0.04) - 0.02) < 0.002 &&
           std::abs(std::fmod(y + 10.0, 0.04) - 0.02) < 0.002;
  };
  const Visible visible = [&](double x, double y) {
    return (on_top(x, y) || sparse_patch(x, y)) ? few(x, y) : true;
  };
  const auto views = map_surface(
      config, [&](double x, double y) { return on_top(x, y) ? 0.06 : 0.0; }, 1.4, 0.002, 0.001, 7,
      visible);
  const DenseGrid& h = views[0].hazard;
  const LayerGrids& g = views[0].map;
  const int min_points = resolve_hazard_params(config).layers[0].min_points;
  int top_cells = 0, sparse_ground = 0;
  for (int r = 0; r < h.rows; ++r)
    for (int c = 0; c < h.cols; ++c) {
      const double x = h.x_of_col(c), y = h.y_of_row(r);
      if (std::isnan(g.height.at(r, c)) || double(g.count.at(r, c)) >= min_points) continue;
      // Cells wholly on the top or in the patch (their edges hold other points).
      if (std::abs(x - xc) < half - 0.02 && std::abs(y - yc) < half - 0.02) {
        ++top_cells;
        EXPECT_EQ(h.at(r, c), float(HazardClass::hazard)) << x << " " << y;
      } else if (x > -0.78 && x < -0.42 && y > -0.78 && y < -0.42) {
        ++sparse_ground;
        EXPECT_EQ(h.at(r, c), float(HazardClass::unknown)) << x << " " << y;
      }
    }
  EXPECT_GE(top_cells, 4);
  EXPECT_GE(sparse_ground, 60);
}

TEST(AnalyticHazards, RingSampleOnACellThatIsNotEvaluableComesFromItsNeighboursPlane) {
  // A tilted plane on the 4 cm layer; the cell [0.12, 0.16) x [0.04, 0.08) is seen in one
  // corner only (not evaluable): a sample at its centre is its evaluable neighbour's
  // plane extrapolated there (exact, within noise of the truth, with a larger variance
  // than the neighbour's own centre). Where no neighbour is evaluable the cell's mu_z is
  // evidence only.
  const Config config = analytic_config({{RuleKind::ccm, 0.04}});
  const auto plane = [](double x, double y) { return 0.1 * x + 0.05 * y; };
  const auto in_cell = [](double x, double y, double x0, double y0) {
    return x >= x0 && x < x0 + 0.04 && y >= y0 && y < y0 + 0.04;
  };
  const Visible visible = [&](double x, double y) {
    if (in_cell(x, y, 0.12, 0.04)) return x < 0.13 && y < 0.05;  // a corner
    // An island: one corner-seen cell with nothing around it.
    if (x >= 0.56 && x < 0.72 && y >= 0.48 && y < 0.64) return x < 0.61 && x >= 0.60 && y < 0.53 && y >= 0.52;
    return true;
  };
  const auto views = map_surface(config, plane, 1.0, 0.002, 0.0005, 5, visible);
  const LayerGrids& g = views[0].map;
  const PlaneClassifier classifier(resolve_hazard_params(config).layers[0]);
  int row = 0, col = 0;
  ASSERT_TRUE(g.height.cell_at(0.14, 0.06, &row, &col));
  ASSERT_EQ(g.evaluable.at(row, col), 0.0f);
  ASSERT_FALSE(std::isnan(g.height.at(row, col)));
  const RingSample s = classifier.surface_at(g, 0.14, 0.06);
  EXPECT_TRUE(s.known && s.exact);
  EXPECT_NEAR(s.z_m, plane(0.14, 0.06), 0.001);
  const RingSample own = classifier.surface_at(g, 0.10, 0.06);  // the neighbour's centre
  EXPECT_TRUE(own.exact);
  EXPECT_GT(s.var_m2, own.var_m2);
  ASSERT_TRUE(g.height.cell_at(0.62, 0.54, &row, &col));
  ASSERT_EQ(g.evaluable.at(row, col), 0.0f);
  const RingSample island = classifier.surface_at(g, 0.62, 0.54);
  EXPECT_TRUE(island.known);
  EXPECT_FALSE(island.exact);
  EXPECT_EQ(island.z_m, g.height.at(row, col));
}

TEST(AnalyticHazards, OneCentimetreRingSampleInAHoleComesFromANeighbourAndAHalfRingStillProves) {
  // Flat ground on the 1 cm Kalman layer with unobserved 1 cm cells exactly where the
  // wheel ring of the cell at (0.305, 0.105) samples: each sample then comes from an
  // observed neighbour and the cell is proven traversable. 3 x 3 holes lose samples: with
  // samples 0-2 lost, 3-7 (a pair and more) still prove the cell with
  // hazard.partial_ring_proof (issue 34); with 0-3 lost, 4-7 hold no opposite pair:
  // unknown. Without partial-ring proof (the default) any lost sample leaves it unknown.
  Config config = analytic_config({{RuleKind::kalman, 0.01}});
  const double xc = 0.305, yc = 0.105, R = 0.15;
  const auto holes = [&](double half_width, int wide) {
    return [=](double x, double y) {
      for (int k = 0; k < 8; ++k) {
        const double sx = xc + R * std::cos(k * M_PI / 4), sy = yc + R * std::sin(k * M_PI / 4);
        const double cx = std::floor(sx / 0.01) * 0.01 + 0.005, cy = std::floor(sy / 0.01) * 0.01 + 0.005;
        const double w = k < wide ? half_width : 0.005;  // samples below `wide`: wider holes
        if (std::abs(x - cx) < w && std::abs(y - cy) < w) return false;
      }
      return true;
    };
  };
  struct Case {
    double half_width;
    int wide;
    HazardClass want;           ///< with partial-ring proof
    HazardClass want_full_only;  ///< without
  };
  constexpr HazardClass T = HazardClass::traversable, U = HazardClass::unknown;
  for (const Case& c : {Case{0.005, 1, T, T}, Case{0.015, 1, T, U}, Case{0.015, 3, T, U},
                        Case{0.015, 4, U, U}})
  for (const bool partial : {true, false}) {
    config.hazard.partial_ring_proof = partial ? PartialRingProof::any : PartialRingProof::off;
    const auto views = map_surface(config, [](double, double) { return 0.0; }, 0.6, 0.002, 0.0005,
                                   7, Visible(holes(c.half_width, c.wide)));
    int row = 0, col = 0;
    ASSERT_TRUE(views[0].hazard.cell_at(xc, yc, &row, &col));
    EXPECT_EQ(views[0].hazard.at(row, col), float(partial ? c.want : c.want_full_only))
        << "hole half-width " << c.half_width << " around samples < " << c.wide
        << (partial ? ", partial-ring proof" : ", full rings only");
  }
}


TEST(AnalyticHazards, DetrendedKernelProvesAnAlmost20DegRampTheRangeCannotAndKeepsEveryHazard) {
  // 18 deg: the 7-cell range is 6 x 1 cm x tan 18 = 1.95 cm, so its proof (+ 3 sigma of
  // two 1 mm cells, 0.4 cm) fails the 2.18 cm threshold; the residuals about the kernel's
  // plane are noise, and the ring's 30 cm baseline tells 18 deg from 20.
  Config config = analytic_config({{RuleKind::kalman, 0.01}});
  const double t18 = std::tan(18 * M_PI / 180);
  const auto ramp = [](double t) { return [t](double x, double) { return t * x; }; };
  const Counts range_mode = count(map_surface(config, ramp(t18), 1.4, 0.003, 0.003)[0].hazard);
  config.hazard.roughness = RoughnessStatistic::detrended;
  const Counts detrended = count(map_surface(config, ramp(t18), 1.4, 0.003, 0.003)[0].hazard);
  EXPECT_EQ(range_mode.hazard, 0);
  EXPECT_EQ(detrended.hazard, 0);
  EXPECT_LT(range_mode.traversable, detrended.traversable / 10);
  EXPECT_GT(detrended.traversable, 0.9 * (detrended.traversable + detrended.unknown));
  // 22 deg, just over the limit: no kernel residual, but the ring's plane is too steep.
  const Counts steep = count(map_surface(config, ramp(std::tan(22 * M_PI / 180)), 1.4, 0.003, 0.001)[0].hazard);
  EXPECT_EQ(steep.traversable, 0);
  EXPECT_GT(steep.hazard, 0.9 * (steep.hazard + steep.unknown));
  // Obstacles stay hazards: a 3 cm rock, one face of a 6 cm rock, a flat 6 cm block top.
  const auto hazard_at = [&](const Surface& s, double x, double y, const Visible& v = nullptr) {
    const auto views = map_surface(config, s, 1.4, 0.002, 0.001, 1, v);
    int row = 0, col = 0;
    EXPECT_TRUE(views[0].hazard.cell_at(x, y, &row, &col));
    return views[0].hazard.at(row, col) == float(HazardClass::hazard);
  };
  EXPECT_TRUE(hazard_at(rock(0.03), 0.2 - 0.02, 0.1));
  EXPECT_TRUE(hazard_at(rock(0.06), 0.2 - 0.04, 0.1, [](double x, double) { return x < 0.2; }));
  const auto block = [](double x, double y) {
    return std::abs(x - 0.3) < 0.12 && std::abs(y - 0.1) < 0.12 ? 0.06 : 0.0;
  };
  EXPECT_TRUE(hazard_at(block, 0.301, 0.101));
}


TEST(AnalyticHazards, ThinStripOfRayCorrelatedPointsGivesNoFaceEvidenceButAHalfSeenCellStill) {
  // A 4 cm cell on a 15 deg ramp seen as a strip 1 mm wide across x, whose points carry a
  // depth error along a ray 60 deg down (x and z move together, 3 mm sigma): regressing
  // z on x across the strip reads the ray's tan 60 = 1.7, past the 3 cm face limit
  // (tan 37 deg), though the strip says nothing about the ground's slope.
  const double r = 0.04, t15 = std::tan(15 * M_PI / 180);
  auto run = [&](double min_axis_coverage, double strip_m, double slope) {
    Config config = analytic_config({{RuleKind::ccm, r}});
    config.hazard.min_axis_coverage = min_axis_coverage;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> ray(0.0, 0.003);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    PointCloud cloud;
    for (int i = 0; i < 400; ++i) {
      const double e = ray(rng);
      const double x = 0.01 + strip_m * u(rng) + e * std::cos(M_PI / 3);
      const double y = 0.002 + 0.036 * u(rng);
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), float(slope * (x - e * std::cos(M_PI / 3)) + e * std::sin(M_PI / 3)));
      m.cov_xx = m.cov_yy = 1e-6f;
      m.cov_zz = 9e-6f;
      cloud.push_back(m);
    }
    LayerStack stack(config.map, config.rules);
    stack.begin_frame(0.001, 0.001);
    stack.insert(MapPoints(cloud));
    LayerView v;
    stack.export_layer(0, v.map);
    make_hazard_classifier(resolve_hazard_params(config).layers[0])->classify(v.map, v.hazard, v.diagnostics);
    int row = 0, col = 0;
    EXPECT_TRUE(v.hazard.cell_at(0.02, 0.02, &row, &col));
    return static_cast<HazardClass>(int(v.hazard.at(row, col)));
  };
  EXPECT_EQ(run(0.0, 0.001, t15), HazardClass::hazard);   // the thesis' reading: any axis
  EXPECT_NE(run(0.1, 0.001, t15), HazardClass::hazard);  // default: the axis spans < 1/3 cell
  // A half-seen cell (a strip 2 cm of 4 wide) keeps its evidence: the ray error is a
  // small part of that spread, so the slope across reads the ground: a 15 deg ramp is no
  // face, a 60 deg face is.
  EXPECT_NE(run(0.1, 0.02, t15), HazardClass::hazard);
  EXPECT_EQ(run(0.1, 0.02, std::tan(60 * M_PI / 180)), HazardClass::hazard);
}

}  // namespace
}  // namespace hazmap
