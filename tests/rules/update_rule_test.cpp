// The update-rule interface (rules/update_rule.hpp) from the outside: every rule, the four
// of the map and a minimal rule written outside the library (MinHeightRule,
// examples/custom_rule/min_height_rule.hpp), passes the compile-time
// checks and a suite of properties that hold for any rule, each driven through the real
// RollingLayer<Rule> (insert, export_grids) as the map uses it.
//
// MinHeightRule is the proof that a new rule needs nothing but one struct: it is not in
// the RuleKind enum, the config parser or make_layer, and RollingLayer<MinHeightRule>
// works.

#include "hazmap/rules/update_rule.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "hazmap/map/map_points.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/bananas.hpp"
#include "hazmap/rules/ccm.hpp"
#include "hazmap/rules/kalman.hpp"
#include "hazmap/rules/omg.hpp"
#include "custom_rule/min_height_rule.hpp"

namespace hazmap {
namespace {

/// The custom rule of examples/custom_rule (min_height_rule.hpp).
using custom_rule::MinHeightRule;

static_assert(check_update_rule<BananasRule>());
static_assert(check_update_rule<KalmanRule>());
static_assert(check_update_rule<OmgRule>());
static_assert(check_update_rule<CcmRule>());
static_assert(check_update_rule<MinHeightRule>());

// The merge policy each rule declares (rules/merge_policy.hpp).
static_assert(BananasRule::kMerge == MergePolicy::per_run);
static_assert(KalmanRule::kMerge == MergePolicy::per_chunk);
static_assert(OmgRule::kMerge == MergePolicy::per_frame);
static_assert(CcmRule::kMerge == MergePolicy::per_frame);
static_assert(MinHeightRule::kMerge == MergePolicy::per_run);

constexpr int kSize = 16;       // cells per side
constexpr double kCell = 0.1;   // m
constexpr float kVarZ = 1e-4f;  // every point's Sigma_zz [m^2] (above Kalman's 1e-6 floor)

/// A point at fraction (fx, fy) of global cell (ix, iy), height z, Sigma_zz kVarZ.
Measurement point_in(CellIndex ix, CellIndex iy, double fx, double fy, double z) {
  Measurement m{};
  m.p_W =
      Eigen::Vector3f(float((double(ix) + fx) * kCell), float((double(iy) + fy) * kCell), float(z));
  m.cov_xx = m.cov_yy = 1e-6f;
  m.cov_zz = kVarZ;
  return m;
}

/// Distance from float x to the next float away from zero: the float rounding of x.
double ulp(float x) {
  const float a = std::abs(x);
  return double(std::nextafter(a, std::numeric_limits<float>::infinity())) - double(a);
}

template <class Rule>
class UpdateRule : public ::testing::Test {
 protected:
  UpdateRule() : layer(kSize, kCell, typename Rule::Config{}) { layer.begin_frame(0.0, 0.0, 0); }

  CellIndex x0() const { return layer.grid().origin_x(); }
  CellIndex y0() const { return layer.grid().origin_y(); }
  /// Image position of global cell (ix, iy) in the exported grids (row 0 = largest y).
  int row(CellIndex iy) const { return int(kSize - 1 - (iy - y0())); }
  int col(CellIndex ix) const { return int(ix - x0()); }
  LayerGrids exported() const {
    LayerGrids out;
    layer.export_grids(out, nullptr, 0.0, 0.0);
    return out;
  }
  /// Every grid the layer exports: height and variance, and the plane grids of kHasPlane.
  static std::vector<const DenseGrid*> grids(const LayerGrids& g) {
    std::vector<const DenseGrid*> all{&g.height, &g.variance};
    if (Rule::kHasPlane)
      for (const DenseGrid* p : {&g.count, &g.slope_x, &g.slope_y, &g.roughness, &g.coverage,
                                 &g.evaluable, &g.noise_variance, &g.lateral_xx, &g.lateral_yy,
                                 &g.lateral_xy, &g.lateral_xz, &g.lateral_yz})
        all.push_back(p);
    return all;
  }

  RollingLayer<Rule> layer;
};

using Rules = ::testing::Types<BananasRule, KalmanRule, OmgRule, CcmRule, MinHeightRule>;
TYPED_TEST_SUITE(UpdateRule, Rules);

// A cleared cell is not known: the default cell, a cell Rule::clear was applied to after
// it held data, and the layer's cells that left the window and came back (the layer
// clears them).
TYPED_TEST(UpdateRule, ClearedCellIsNotKnown) {
  using Rule = TypeParam;
  typename Rule::Cell fresh;
  Rule::clear(fresh);
  EXPECT_FALSE(Rule::known(fresh));

  const CellIndex ix = this->x0() + 3, iy = this->y0() + 5;
  for (CellIndex y = this->y0(); y < this->y0() + kSize; ++y)
    for (CellIndex x = this->x0(); x < this->x0() + kSize; ++x)
      ASSERT_FALSE(Rule::known(this->layer.cell(x, y))) << x << "," << y;
  this->layer.insert(MapPoints(PointCloud{point_in(ix, iy, 0.5, 0.5, 0.25)}));
  typename Rule::Cell held = this->layer.cell(ix, iy);
  ASSERT_TRUE(Rule::known(held));
  Rule::clear(held);
  EXPECT_FALSE(Rule::known(held));

  this->layer.begin_frame(1000.0, 0.0, 1);  // a jump larger than the window clears it
  this->layer.begin_frame(0.0, 0.0, 2);     // and back: the cells entered again, cleared
  ASSERT_TRUE(this->layer.grid().contains(ix, iy));
  EXPECT_FALSE(Rule::known(this->layer.cell(ix, iy)));
}

// One point into an empty layer makes its cell known, and the exported height there is
// the point's height (the float z MapPoints holds) to within one float ulp; the exported
// variance is finite. Every rule publishes the point's z exactly in fact: Bananas and
// MinHeight the point itself; Kalman, OMG and CCM a mean of one point taken relative to
// that point's own height (offset 0), stored as a SplitHeight. CCM publishes mu_z: one
// point is not evaluable (count 1 < min_points), so its published height is mean_z, not
// the plane at the centre (which would also be mu_z: one point has no slopes).
TYPED_TEST(UpdateRule, OnePointMakesItsCellKnownWithThePointsHeight) {
  using Rule = TypeParam;
  for (const double z : {0.1234567, -3.21701, 101.37, 0.0}) {
    RollingLayer<Rule> fresh(kSize, kCell, typename Rule::Config{});
    fresh.begin_frame(0.0, 0.0, 0);
    const CellIndex ix = this->x0() + 6, iy = this->y0() + 9;
    const Measurement m = point_in(ix, iy, 0.3, 0.7, z);
    EXPECT_EQ(fresh.insert(MapPoints(PointCloud{m})), 1u);
    ASSERT_TRUE(Rule::known(fresh.cell(ix, iy))) << z;
    LayerGrids out;
    fresh.export_grids(out, nullptr, 0.0, 0.0);
    const int row = this->row(iy), col = this->col(ix);
    const float zf = m.p_W.z();
    EXPECT_LE(std::abs(double(out.height.at(row, col)) - double(zf)), ulp(zf)) << z;
    EXPECT_TRUE(std::isfinite(out.variance.at(row, col))) << z;
    EXPECT_GE(out.variance.at(row, col), 0.0f) << z;
    if constexpr (Rule::kHasPlane) {
      EXPECT_EQ(out.evaluable.at(row, col), 0.0f) << z;
    }
  }
}

// Many points of one height h (the float MapPoints holds), all with Sigma_zz kVarZ, over
// several frames and spread over their cells, give height h to within 1e-6 m in every
// cell they fell in. For CCM the cells become evaluable (320 points covering the cell)
// and publish their plane at the centre: points of one height have no slopes, so that
// is mu_z = h.
TYPED_TEST(UpdateRule, ManyPointsOfOneHeightGiveThatHeight) {
  using Rule = TypeParam;
  for (const double h : {0.4321, -12.345, 98.7654}) {
    RollingLayer<Rule> fresh(kSize, kCell, typename Rule::Config{});
    const std::vector<std::pair<CellIndex, CellIndex>> cells = {{this->x0() + 1, this->y0() + 1},
                                                                {this->x0() + 8, this->y0() + 4},
                                                                {this->x0() + 15, this->y0() + 15}};
    for (std::uint32_t frame = 0; frame < 5; ++frame) {
      fresh.begin_frame(0.0, 0.0, frame);
      PointCloud cloud;
      for (const auto& [ix, iy] : cells)
        for (int k = 0; k < 64; ++k)  // an 8 x 8 grid of positions inside the cell
          cloud.push_back(point_in(ix, iy, (k % 8 + 0.5) / 8.0, (k / 8 + 0.5) / 8.0, h));
      ASSERT_EQ(fresh.insert(MapPoints(cloud)), cloud.size());
    }
    LayerGrids out;
    fresh.export_grids(out, nullptr, 0.0, 0.0);
    const float hf = static_cast<float>(h);
    for (const auto& [ix, iy] : cells) {
      EXPECT_NEAR(out.height.at(this->row(iy), this->col(ix)), hf, 1e-6) << h;
      if constexpr (Rule::kHasPlane) {
        EXPECT_EQ(out.evaluable.at(this->row(iy), this->col(ix)), 1.0f) << h;
      }
    }
  }
}

// Points whose cells are outside the window change nothing: the insert uses none of them,
// the std gate counts none (it counts points inside the window only), and every exported
// grid and every cell's moments are bit for bit what they were (same frame, so no ageing
// in between).
TYPED_TEST(UpdateRule, PointsOutsideTheWindowChangeNothing) {
  PointCloud inside;
  for (int k = 0; k < 40; ++k)
    inside.push_back(point_in(this->x0() + k % kSize, this->y0() + (7 * k) % kSize, 0.2 + 0.015 * k,
                              0.8 - 0.015 * k, 0.05 * k - 0.7));
  ASSERT_EQ(this->layer.insert(MapPoints(inside)), inside.size());
  const LayerGrids before = this->exported();
  std::vector<Moments> moments_before;
  for (CellIndex y = this->y0(); y < this->y0() + kSize; ++y)
    for (CellIndex x = this->x0(); x < this->x0() + kSize; ++x)
      moments_before.push_back(this->layer.cell_moments(x, y));

  // Centres of the cells just past each edge, past the corners, and far away; heights
  // that would show.
  const CellIndex x0 = this->x0(), y0 = this->y0(), x1 = x0 + kSize, y1 = y0 + kSize;
  PointCloud outside;
  for (CellIndex t = x0; t < x1; ++t) {
    outside.push_back(point_in(t, y0 - 1, 0.5, 0.5, 5.0));
    outside.push_back(point_in(t, y1, 0.5, 0.5, -5.0));
    outside.push_back(point_in(x0 - 1, t - x0 + y0, 0.5, 0.5, 3.0));
    outside.push_back(point_in(x1, t - x0 + y0, 0.5, 0.5, -3.0));
  }
  outside.push_back(point_in(x0 - 1, y0 - 1, 0.5, 0.5, 1.0));
  outside.push_back(point_in(x1, y1, 0.5, 0.5, 1.0));
  outside.push_back(point_in(x0 + 1000, y0 - 500, 0.5, 0.5, 1.0));
  EXPECT_EQ(this->layer.insert(MapPoints(outside)), 0u);
  EXPECT_EQ(this->layer.gate_counts().std_gate, 0u);
  EXPECT_EQ(this->layer.gate_counts().consistency_gate, 0u);

  const LayerGrids after = this->exported();
  const auto b = this->grids(before), a = this->grids(after);
  for (std::size_t g = 0; g < b.size(); ++g) {
    ASSERT_EQ(a[g]->rows, b[g]->rows);
    ASSERT_EQ(a[g]->cols, b[g]->cols);
    ASSERT_EQ(a[g]->values.size(), b[g]->values.size());
    EXPECT_EQ(
        std::memcmp(a[g]->values.data(), b[g]->values.data(), b[g]->values.size() * sizeof(float)),
        0)
        << "grid " << g;
  }
  std::size_t k = 0;
  for (CellIndex y = y0; y < y1; ++y)
    for (CellIndex x = x0; x < x1; ++x, ++k) {
      const Moments m = this->layer.cell_moments(x, y);
      const Moments& o = moments_before[k];
      EXPECT_TRUE(m.w == o.w && m.mz == o.mz && m.szz == o.szz && m.count == o.count &&
                  m.mx == o.mx && m.my == o.my && m.sxz == o.sxz && m.syz == o.syz)
          << x << "," << y;
    }
}

// The exported grids are NaN exactly where nothing was inserted: height and variance
// (and, for a rule with a plane, every plane grid) are NaN in every cell no point fell
// in, and height and variance are numbers in every cell one did. Rules without a plane
// export empty plane grids.
TYPED_TEST(UpdateRule, ExportedGridsAreNanWhereNothingWasInserted) {
  using Rule = TypeParam;
  std::set<std::pair<int, int>> hit;  // (row, col)
  PointCloud cloud;
  for (int k = 0; k < 23; ++k) {
    const CellIndex ix = this->x0() + (5 * k) % kSize, iy = this->y0() + (3 * k + k / 4) % kSize;
    for (int p = 0; p <= k % 3; ++p)
      cloud.push_back(point_in(ix, iy, 0.25 + 0.2 * p, 0.5, 0.01 * k));
    hit.insert({this->row(iy), this->col(ix)});
  }
  ASSERT_GT(hit.size(), 15u);
  ASSERT_LT(hit.size(), std::size_t(kSize * kSize - 100));
  ASSERT_EQ(this->layer.insert(MapPoints(cloud)), cloud.size());
  const LayerGrids out = this->exported();
  for (const DenseGrid* g : this->grids(out)) {
    ASSERT_EQ(g->rows, kSize);
    ASSERT_EQ(g->cols, kSize);
  }
  if constexpr (!Rule::kHasPlane) {
    EXPECT_EQ(out.slope_x.rows, 0);
    EXPECT_EQ(out.count.rows, 0);
  }
  for (int row = 0; row < kSize; ++row)
    for (int col = 0; col < kSize; ++col) {
      if (hit.count({row, col})) {
        EXPECT_FALSE(std::isnan(out.height.at(row, col))) << row << "," << col;
        EXPECT_FALSE(std::isnan(out.variance.at(row, col))) << row << "," << col;
      } else {
        const auto grids = this->grids(out);
        for (std::size_t g = 0; g < grids.size(); ++g)
          EXPECT_TRUE(std::isnan(grids[g]->at(row, col)))
              << "grid " << g << " " << row << "," << col;
      }
    }
}

// The merge policy says when inserted points reach the cells: per_run and per_chunk rules
// merge each chunk's runs while the chunk goes in, so a cell is known as soon as
// insert_chunk returns; per_frame rules only add to the frame's sums then, and merge once
// in end_insert. Either way every point inside the window is taken, and after end_insert
// the cells hold the same heights as after Layer::insert.
TYPED_TEST(UpdateRule, PointsReachTheCellsWhenTheMergePolicySays) {
  using Rule = TypeParam;
  const CellIndex ix = this->x0() + 4, iy = this->y0() + 11;
  PointCloud cloud;
  for (int k = 0; k < 12; ++k) cloud.push_back(point_in(ix, iy, 0.1 + 0.07 * k, 0.5, 0.3 + 0.01 * k));
  const MapPoints points(cloud);

  RollingLayer<Rule> whole(kSize, kCell, typename Rule::Config{});
  whole.begin_frame(0.0, 0.0, 0);
  ASSERT_EQ(whole.insert(points), cloud.size());

  this->layer.begin_insert();
  std::size_t used = 0;
  points.for_each_chunk([&](const PointChunk& chunk) { used += this->layer.insert_chunk(chunk); });
  EXPECT_EQ(used, cloud.size());
  EXPECT_EQ(Rule::known(this->layer.cell(ix, iy)), merges_runs(Rule::kMerge));
  this->layer.end_insert();
  ASSERT_TRUE(Rule::known(this->layer.cell(ix, iy)));
  const LayerGrids a = this->exported();
  LayerGrids b;
  whole.export_grids(b, nullptr, 0.0, 0.0);
  const int row = this->row(iy), col = this->col(ix);
  EXPECT_EQ(a.height.at(row, col), b.height.at(row, col));
  EXPECT_EQ(a.variance.at(row, col), b.variance.at(row, col));
}

}  // namespace
}  // namespace hazmap
