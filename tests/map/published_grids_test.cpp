// What layers publish (LayerGrids, SPEC 6.1, 6.4): the baseline's variance, CCM cells
// that are not evaluable (mean height, no slopes, the unmeasured tilt in the variance),
// and the CCM noise variance and lateral covariance grids, each against a batch
// computation in double.

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "hazmap/map/grid_math.hpp"
#include "hazmap/map/layer_stack.hpp"

namespace hazmap {
namespace {

Measurement point(double x, double y, double z, double sigma_z, double sigma_xy = 0.001) {
  Measurement m{};
  m.p_W = Eigen::Vector3f(float(x), float(y), float(z));
  m.cov_xx = m.cov_yy = float(sigma_xy * sigma_xy);
  m.cov_zz = float(sigma_z * sigma_z);
  return m;
}

MapConfig one_layer(RuleKind rule, double r, int n) {
  MapConfig map;
  LayerConfig l;
  l.rule = rule;
  l.resolution_m = r;
  l.size = n;
  map.layers.push_back(l);
  return map;
}

/// Grid row and column of the cell holding (x, y).
std::pair<int, int> at(const DenseGrid& g, double x, double y) {
  int row = -1, col = -1;
  EXPECT_TRUE(g.cell_at(x, y, &row, &col));
  return {row, col};
}

TEST(PublishedGrids, BananasVarianceIsTheLastPointsSensorVariance) {
  LayerStack s(one_layer(RuleKind::bananas, 0.1, 8), RulesConfig{});
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> sigma(0.001, 0.02);
  float last_var = 0, last_z = 0;
  for (int frame = 0; frame < 3; ++frame) {
    s.begin_frame(0.0, 0.0);
    PointCloud cloud;
    for (int i = 0; i < 7; ++i) cloud.push_back(point(0.05, 0.05, 0.1 * i + frame, sigma(rng)));
    // Two chunks' worth in another cell, so that the cell's last point is in a later run.
    for (int i = 0; i < 1500; ++i) cloud.push_back(point(0.15, 0.05, 0.0, 0.01));
    cloud.push_back(point(0.05, 0.05, 0.77 + frame, sigma(rng)));
    last_var = cloud.back().cov_zz;
    last_z = cloud.back().p_W.z();
    s.insert(MapPoints(cloud));
    LayerGrids g;
    s.export_layer(0, g);
    const auto [row, col] = at(g.height, 0.05, 0.05);
    EXPECT_EQ(g.height.at(row, col), last_z);
    EXPECT_EQ(g.variance.at(row, col), last_var);  // the float Sigma_zz itself
    EXPECT_TRUE(std::isnan(g.variance.at(0, 0)));   // unknown cells stay NaN
    EXPECT_EQ(g.noise_variance.rows, 0);            // plane grids only on CCM layers
    EXPECT_EQ(g.lateral_xx.rows, 0);
  }
}

/// Weighted batch moments of points in one cell, in double, x and y cell-centric.
struct Batch {
  double w = 0, mx = 0, my = 0, mz = 0, sxx = 0, syy = 0, sxy = 0, szz = 0, noise = 0;
};
Batch batch(const std::vector<Measurement>& pts, const std::vector<double>& weights, double cx,
            double cy) {
  Batch b;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double w = weights[i];
    b.w += w;
    b.mx += w * (pts[i].p_W.x() - cx);
    b.my += w * (pts[i].p_W.y() - cy);
    b.mz += w * pts[i].p_W.z();
    b.noise += w * double(pts[i].cov_zz);
  }
  b.mx /= b.w;
  b.my /= b.w;
  b.mz /= b.w;
  b.noise /= b.w;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double w = weights[i];
    const double dx = pts[i].p_W.x() - cx - b.mx, dy = pts[i].p_W.y() - cy - b.my;
    const double dz = pts[i].p_W.z() - b.mz;
    b.sxx += w * dx * dx;
    b.syy += w * dy * dy;
    b.sxy += w * dx * dy;
    b.szz += w * dz * dz;
  }
  return b;
}

// SPEC 6.4: a CCM cell that is not evaluable (its points cover one corner, or too few of
// them) publishes mu_z, NaN slopes and Szz/W + (r^2/12 + |mu_xy|^2) tan^2(max_slope); an
// evaluable cell publishes its plane at the centre and Szz/W.
TEST(PublishedGrids, CcmCellThatIsNotEvaluablePublishesItsMeanAndTheTiltItMayHide) {
  const double r = 0.04, max_slope_deg = 25.0;
  HazardConfig hazard;
  hazard.max_slope_deg = max_slope_deg;
  RulesConfig rules;
  rules.ccm.min_points = 10;
  LayerStack s(one_layer(RuleKind::ccm, r, 8), rules, hazard);
  s.begin_frame(0.0, 0.0);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.0005);
  auto plane = [&](double x, double y) { return 1.0 + 0.3 * x - 0.2 * y + noise(rng); };
  // Cell [0, r)^2: the whole cell (evaluable). Cell [r, 2r) x [0, r): its lower-left
  // quarter only (kappa ~ 0.25). Cell [0, r) x [r, 2r): whole, but 5 points.
  std::vector<Measurement> full, corner, few;
  for (int i = 0; i < 400; ++i) {
    const double x = u(rng) * r, y = u(rng) * r;
    full.push_back(point(x, y, plane(x, y), 0.002));
  }
  for (int i = 0; i < 200; ++i) {
    const double x = r + 0.5 * u(rng) * r, y = 0.5 * u(rng) * r;
    corner.push_back(point(x, y, plane(x, y), 0.002));
  }
  for (int i = 0; i < 5; ++i) {
    const double x = (0.1 + 0.2 * i) * r, y = r + (0.9 - 0.2 * i) * r;
    few.push_back(point(x, y, plane(x, y), 0.002));
  }
  PointCloud cloud;
  for (const auto* set : {&full, &corner, &few}) cloud.insert(cloud.end(), set->begin(), set->end());
  s.insert(MapPoints(cloud));
  LayerGrids g;
  s.export_layer(0, g);
  const double tan2 = std::pow(std::tan(max_slope_deg * M_PI / 180.0), 2);
  struct Case {
    const std::vector<Measurement>* pts;
    double cx, cy;
    bool evaluable;
  };
  for (const Case& c : {Case{&full, 0.5 * r, 0.5 * r, true}, Case{&corner, 1.5 * r, 0.5 * r, false},
                        Case{&few, 0.5 * r, 1.5 * r, false}}) {
    const Batch b = batch(*c.pts, std::vector<double>(c.pts->size(), 1.0), c.cx, c.cy);
    const auto [row, col] = at(g.height, c.cx, c.cy);
    ASSERT_EQ(g.evaluable.at(row, col), c.evaluable ? 1.0f : 0.0f) << c.cx << " " << c.cy;
    const double szz_w = b.szz / b.w;
    if (c.evaluable) {
      // The plane at the centre (slopes 0.3, -0.2 recovered to the noise's precision).
      EXPECT_NEAR(g.slope_x.at(row, col), 0.3, 0.01);
      EXPECT_NEAR(g.slope_y.at(row, col), -0.2, 0.01);
      EXPECT_NEAR(g.height.at(row, col), 1.0 + 0.3 * c.cx - 0.2 * c.cy, 5e-4);
      EXPECT_NEAR(g.variance.at(row, col), szz_w, 1e-5 * szz_w);
    } else {
      EXPECT_NEAR(g.height.at(row, col), b.mz, 1e-6);  // mu_z, not the plane at the centre
      EXPECT_TRUE(std::isnan(g.slope_x.at(row, col)));
      EXPECT_TRUE(std::isnan(g.slope_y.at(row, col)));
      const double tilt = (r * r / 12.0 + b.mx * b.mx + b.my * b.my) * tan2;
      EXPECT_NEAR(g.variance.at(row, col), szz_w + tilt, 1e-5 * (szz_w + tilt));
      // The true plane (19.8 deg, under max_slope) at every corner of the cell lies within
      // 3 sigma of the published mu_z.
      for (double qx : {-0.5 * r, 0.5 * r})
        for (double qy : {-0.5 * r, 0.5 * r}) {
          const double truth = 1.0 + 0.3 * (c.cx + qx) - 0.2 * (c.cy + qy);
          EXPECT_LT(std::abs(truth - g.height.at(row, col)), 3.0 * std::sqrt(g.variance.at(row, col)))
              << c.cx << " " << c.cy << " corner " << qx << " " << qy;
        }
    }
  }
  // The corner cell's mean lies ~ r/4 from the centre in x and y: the plane there would
  // be 0.3 r/4 - 0.2 r/4 = 1 mm away from mu_z, more than the tolerance above.
  const Batch corner_b = batch(corner, std::vector<double>(corner.size(), 1.0), 1.5 * r, 0.5 * r);
  EXPECT_GT(std::abs(0.3 * corner_b.mx - 0.2 * corner_b.my), 5e-4);
}

/// Random points over a 4 x 4-cell patch of a 4 cm CCM layer, sigma_z and the lateral
/// std varying so that trace weights and noise variances vary from point to point.
PointCloud varied_cloud(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-0.08, 0.08), sz(0.001, 0.02), sxy(0.0005, 0.004);
  std::normal_distribution<double> noise(0.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < count; ++i) {
    const double x = u(rng), y = u(rng), s = sz(rng);
    Measurement m = point(x, y, 0.5 + 0.2 * x + 0.05 * std::sin(40 * y) + s * noise(rng), s, sxy(rng));
    m.cov_xy = float(0.3 * m.cov_xx);
    cloud.push_back(m);
  }
  return cloud;
}

// noise_variance is the weighted mean (the CCM weights, here trace weights) of the
// points' Sigma_zz, and lateral_xx/yy/xy the weighted lateral covariance S/W, against a
// batch in double over three frames; and with the weight cap, noise_variance follows the
// per-frame capped merge (the cap leaves means unchanged) computed here in double.
TEST(PublishedGrids, CcmNoiseVarianceAndLateralCovarianceEqualBatch) {
  const double r = 0.04;
  for (const double cap : {1e300, 3e4}) {
    RulesConfig rules;
    rules.ccm.weighting = CcmWeighting::trace;
    rules.ccm.max_weight = cap;
    LayerStack s(one_layer(RuleKind::ccm, r, 8), rules);
    std::mt19937_64 rng(6);
    std::map<std::pair<CellIndex, CellIndex>, std::vector<Measurement>> cells;
    struct Capped {
      double w = 0, noise = 0;
    };
    std::map<std::pair<CellIndex, CellIndex>, Capped> capped;  // the capped recursion
    for (int frame = 0; frame < 3; ++frame) {
      const PointCloud cloud = varied_cloud(rng, 3000);
      s.begin_frame(0.0, 0.0);
      s.insert(MapPoints(cloud, CcmWeighting::trace));
      std::map<std::pair<CellIndex, CellIndex>, Capped> frame_sums;
      for (const Measurement& m : cloud) {
        const std::pair<CellIndex, CellIndex> key{cell_index(m.p_W.x(), r), cell_index(m.p_W.y(), r)};
        cells[key].push_back(m);
        const double w = 1.0 / (double(m.cov_xx) + double(m.cov_yy) + double(m.cov_zz));
        frame_sums[key].w += w;
        frame_sums[key].noise += w * double(m.cov_zz);
      }
      for (const auto& [key, f] : frame_sums) {
        Capped& c = capped[key];
        const double w = c.w + f.w;
        c.noise = (c.w * c.noise + f.noise) / w;
        c.w = std::min(w, cap);
      }
    }
    LayerGrids g;
    s.export_layer(0, g);
    ASSERT_EQ(g.noise_variance.rows, 8);
    int compared = 0;
    for (const auto& [key, pts] : cells) {
      const double cx = cell_center(key.first, r), cy = cell_center(key.second, r);
      const auto [row, col] = at(g.height, cx, cy);
      const double noise = g.noise_variance.at(row, col);
      if (cap < 1e300) {
        EXPECT_NEAR(noise, capped[key].noise, 1e-5 * capped[key].noise);
        ++compared;
        continue;
      }
      std::vector<double> w;
      for (const Measurement& m : pts)
        w.push_back(1.0 / (double(m.cov_xx) + double(m.cov_yy) + double(m.cov_zz)));
      const Batch b = batch(pts, w, cx, cy);
      EXPECT_NEAR(noise, b.noise, 1e-5 * b.noise);
      EXPECT_NEAR(g.lateral_xx.at(row, col), b.sxx / b.w, 1e-5 * b.sxx / b.w);
      EXPECT_NEAR(g.lateral_yy.at(row, col), b.syy / b.w, 1e-5 * b.syy / b.w);
      EXPECT_NEAR(g.lateral_xy.at(row, col), b.sxy / b.w, 1e-5 * std::sqrt(b.sxx * b.syy) / b.w);
      ++compared;
    }
    EXPECT_EQ(compared, 16);
    if (cap < 1e300) {
      // The cap acted (else this case tests nothing new): the capped mean differs from
      // the plain weighted mean somewhere.
      double worst = 0;
      for (const auto& [key, pts] : cells) {
        std::vector<double> w;
        for (const Measurement& m : pts)
          w.push_back(1.0 / (double(m.cov_xx) + double(m.cov_yy) + double(m.cov_zz)));
        const Batch b = batch(pts, w, 0, 0);
        worst = std::max(worst, std::abs(capped[key].noise - b.noise) / b.noise);
      }
      EXPECT_GT(worst, 1e-3);
    }
  }
}

// SPEC 7 on a CCM layer whose cells are not evaluable (no slopes): the pose inflation
// takes its gradient from the neighbours' heights, so the variance stays a number, and
// it only grows.
TEST(PublishedGrids, PoseInflationOfCcmCellsWithoutSlopesStaysFinite) {
  const MapConfig map = one_layer(RuleKind::ccm, 0.04, 8);
  LayerStack plain(map, RulesConfig{}), posed(map, RulesConfig{}, /*pose_uncertainty=*/true);
  PointCloud cloud;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)  // 3 points per cell along a line: never evaluable
      for (int k = 0; k < 3; ++k) {
        const double x = -0.16 + 0.04 * i + 0.01 * (k + 1), y = -0.16 + 0.04 * j + 0.02;
        cloud.push_back(point(x, y, 0.3 * x, 0.002));
      }
  for (LayerStack* s : {&plain, &posed}) {
    s->begin_frame(0.0, 0.0);
    s->insert(MapPoints(cloud));
    s->begin_frame(0.0, 0.0, PoseNoise{0.01, 0.01, 0.001, 0.01});
  }
  LayerGrids a, b;
  plain.export_layer(0, a);
  posed.export_layer(0, b);
  int known = 0;
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) {
      ASSERT_EQ(a.evaluable.at(r, c), 0.0f);
      ASSERT_TRUE(std::isnan(b.slope_x.at(r, c)));
      ASSERT_TRUE(std::isfinite(b.variance.at(r, c)));
      // Sigma_r,zz = 1e-6 at least, plus the slope 0.3 times the lateral noise.
      EXPECT_GT(b.variance.at(r, c), a.variance.at(r, c) + 1e-6 + 0.5 * 0.09 * 1e-4);
      ++known;
    }
  EXPECT_EQ(known, 64);
}

}  // namespace
}  // namespace hazmap
