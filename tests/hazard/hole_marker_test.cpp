// The hole-free test (map.layers.N.hole_free_coverage, issue 34): HoleMarker's verdict on
// one cell against a disparity image computed here independently (each pixel's ray met
// with the ground plane), with holes, nearer and farther surfaces put on pixels whose
// ground point this test finds inside or just outside the cell; and the export that reads
// the marks: a partly covered CCM cell gets its plane only with a kSeenWhole mark.

#include "hazmap/hazard/hole_marker.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "hazmap/hazard/plane_classifier.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr double kBaseline = 0.05;

/// A 400 x 300 camera 0.25 m above flat ground (z = 0), pitched down by 30 deg, on a body
/// yawed 30 deg (W's cells then project as slanted quads, whose bounding boxes hold other
/// cells' pixels), with the pixels' disparities of that ground (x16; none above the horizon).
struct Scene {
  SensorView view;
  std::vector<std::int16_t> disparity;

  Scene() {
    Eigen::Matrix3d level;
    level.col(0) = Eigen::Vector3d(0, -1, 0);
    level.col(1) = Eigen::Vector3d(0, 0, -1);
    level.col(2) = Eigen::Vector3d(1, 0, 0);
    view.T_B_C.linear() = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix() * level;
    view.T_B_C.translation() = Eigen::Vector3d(0.0, 0.0, 0.25);
    view.T_W_B.linear() = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    view.focal_px = 300;
    view.cx_px = 199.5;
    view.cy_px = 149.5;
    view.width_px = 400;
    view.height_px = 300;
    view.edge_margin_px = 5;
    view.z_min_m = 0.05;
    view.z_max_m = 3.0;
    view.baseline_m = kBaseline;
    view.roi_x1 = 400;
    view.roi_y1 = 300;
    view.invalid_below_x16 = 0;
    disparity.assign(400 * 300, 0);
    for (int v = 0; v < 300; ++v)
      for (int u = 0; u < 400; ++u) {
        double depth = 0;
        if (ground_depth(u, v, &depth)) at(u, v) = static_cast<std::int16_t>(std::lround(16 * 300 * kBaseline / depth));
      }
    view.disparity_x16 = disparity.data();
    view.disparity_stride = 400;
  }

  std::int16_t& at(int u, int v) { return disparity[static_cast<size_t>(v) * 400 + u]; }

  /// Independent of the marker: pixel (u, v)'s ray in the camera, rotated into W, met with
  /// z = 0; its depth along the optical axis and the ground point.
  bool ground_depth(int u, int v, double* depth, Eigen::Vector2d* xy = nullptr) const {
    const Eigen::Vector3d ray_C((u - view.cx_px) / view.focal_px, (v - view.cy_px) / view.focal_px, 1.0);
    const Pose3d T_W_C = view.T_W_B * view.T_B_C;
    const Eigen::Vector3d ray_W = T_W_C.linear() * ray_C;
    if (ray_W.z() >= -1e-9) return false;
    *depth = -T_W_C.translation().z() / ray_W.z();
    if (xy) *xy = (T_W_C.translation() + *depth * ray_W).head<2>();
    return true;
  }

  /// The pixels whose ground point lies in [x0, x1) x [y0, y1) (inside), or within
  /// `margin` of it but outside (near).
  void pixels_of(double x0, double x1, double y0, double y1, double margin,
                 std::vector<Eigen::Vector2i>* inside, std::vector<Eigen::Vector2i>* near) const {
    for (int v = 0; v < 300; ++v)
      for (int u = 0; u < 400; ++u) {
        double depth = 0;
        Eigen::Vector2d p;
        if (!ground_depth(u, v, &depth, &p)) continue;
        const bool in = p.x() >= x0 && p.x() < x1 && p.y() >= y0 && p.y() < y1;
        const bool close = p.x() >= x0 - margin && p.x() < x1 + margin && p.y() >= y0 - margin &&
                           p.y() < y1 + margin;
        if (in) inside->push_back({u, v});
        else if (close) near->push_back({u, v});
      }
  }
};

// A 4 cm cell about 0.8 m ahead, level with the ground.
constexpr double kX0 = 0.68, kX1 = 0.72, kY0 = 0.38, kY1 = 0.42, kTol = 1.0;

/// The pixels whose ground point lies in quarter q of the cell (x half + 2 y half).
std::vector<Eigen::Vector2i> quarter_pixels(const Scene& s, int q) {
  std::vector<Eigen::Vector2i> inside, near, out;
  s.pixels_of(kX0, kX1, kY0, kY1, 0.0, &inside, &near);
  for (const auto& p : inside) {
    double depth = 0;
    Eigen::Vector2d g;
    s.ground_depth(p.x(), p.y(), &depth, &g);
    if ((g.x() >= 0.5 * (kX0 + kX1)) + 2 * (g.y() >= 0.5 * (kY0 + kY1)) == q) out.push_back(p);
  }
  return out;
}

TEST(HoleMarker, ACellWhoseEveryPixelMatchedIsSeenWhole) {
  Scene s;
  std::vector<Eigen::Vector2i> inside, near;
  s.pixels_of(kX0, kX1, kY0, kY1, 0.005, &inside, &near);
  ASSERT_GT(inside.size(), 20u);  // the cell spans many pixels at 0.8 m
  ASSERT_GT(near.size(), 5u);
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), kSeenWhole);
  // Holes on pixels that looked at the neighbouring cells do not count.
  for (const auto& p : near) s.at(p.x(), p.y()) = 0;
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), kSeenWhole);
  // Without a disparity image: nothing is known.
  s.view.disparity_x16 = nullptr;
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), 0.0f);
}

TEST(HoleMarker, AQuarterWithoutADisparityIsAHoleAPixelIsNot) {
  for (int q = 0; q < 4; ++q) {
    Scene s;
    const std::vector<Eigen::Vector2i> pixels = quarter_pixels(s, q);
    ASSERT_GE(pixels.size(), 3u) << q;
    // All but one of the quarter's pixels without a match: the matcher's noise.
    for (size_t k = 1; k < pixels.size(); ++k) s.at(pixels[k].x(), pixels[k].y()) = 0;
    EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), kSeenWhole) << q;
    s.at(pixels[0].x(), pixels[0].y()) = 0;
    EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), kHoleSeen) << q;
  }
}

TEST(HoleMarker, APixelOffThePlaneWithholdsTheVerdictWithinTheToleranceIsGround) {
  std::vector<Eigen::Vector2i> inside, near;
  Scene().pixels_of(kX0, kX1, kY0, kY1, 0.0, &inside, &near);
  const Eigen::Vector2i p = inside[inside.size() / 2];
  struct Case {
    double shift_px;
    float verdict;
  };
  // Nearer (something in front) or farther (not this plane): this frame says nothing.
  for (const Case c : {Case{+0.8, kSeenWhole}, Case{-0.8, kSeenWhole}, Case{+1.5, 0.0f},
                       Case{+4.0, 0.0f}, Case{-1.5, 0.0f}}) {
    Scene s;
    s.at(p.x(), p.y()) = static_cast<std::int16_t>(s.at(p.x(), p.y()) + std::lround(16 * c.shift_px));
    EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), c.verdict) << c.shift_px;
  }
  // A cell 5 cm above the ground its pixels see: every pixel reads farther.
  Scene s;
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.05, kTol), 0.0f);
}

TEST(HoleMarker, ACellPartlyOutOfViewGetsNoVerdict) {
  Scene s;
  // Along W y at x = 0.70, the first ground point past the image's right edge: a cell
  // straddling it (some corner out) gets no verdict, one inside it does.
  const Pose3d T_C_W = (s.view.T_W_B * s.view.T_B_C).inverse();
  double y_edge = 1.0;
  for (double y = 0.4; y > -2.0; y -= 0.001) {
    const Eigen::Vector3d c = T_C_W * Eigen::Vector3d(0.70, y, 0.0);
    if (s.view.cx_px + s.view.focal_px * c.x() / c.z() > s.view.width_px - 1 - s.view.edge_margin_px) {
      y_edge = y;
      break;
    }
  }
  ASSERT_LT(y_edge, 0.4);
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, y_edge - 0.02, y_edge + 0.02, 0.0, kTol), 0.0f);
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, y_edge + 0.03, y_edge + 0.07, 0.0, kTol), kSeenWhole);
  // Beyond the layer's depth limit (its lateral gate), then beyond z_max. The cell's
  // farthest corner lies this deep:
  double deepest = 0;
  const Pose3d T_C_W2 = (s.view.T_W_B * s.view.T_B_C).inverse();
  for (const double x : {kX0, kX1})
    for (const double y : {kY0, kY1}) deepest = std::max(deepest, (T_C_W2 * Eigen::Vector3d(x, y, 0.0)).z());
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol, deepest + 1e-3), kSeenWhole);
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol, deepest - 1e-3), 0.0f);
  s.view.z_max_m = deepest - 1e-3;
  EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), 0.0f);
}

// Ground at the left image's border whose match would fall off the right image (u - f B
// / Z within the right margin: bm and sgbm drop such matches) was not seen by the pair:
// its missing disparities are no hole. Cells along W y at x = 0.70, level with the
// ground, their corners projected here independently: the first cell whose corners are
// all in the left image but one of whose matches falls within 11 px of the right image's
// border, with every disparity over it removed, is a hole without the right margin and
// gets no verdict with it; the first cell clear of the margin is still a hole.
TEST(HoleMarker, GroundTheRightCameraCouldNotMatchIsNoHole) {
  constexpr double kMargin = 11;
  const Scene scene;
  const Pose3d T_C_W = (scene.view.T_W_B * scene.view.T_B_C).inverse();
  // The smallest left-image u and right-image u - f B / Z over a cell's corners.
  auto corners = [&](double y0, double* u_left, double* u_right) {
    *u_left = *u_right = 1e300;
    for (const double x : {kX0, kX1})
      for (const double y : {y0, y0 + 0.04}) {
        const Eigen::Vector3d c = T_C_W * Eigen::Vector3d(x, y, 0.0);
        const double u = scene.view.cx_px + scene.view.focal_px * c.x() / c.z();
        *u_left = std::min(*u_left, u);
        *u_right = std::min(*u_right, u - scene.view.focal_px * kBaseline / c.z());
      }
  };
  double y_cut = 0, y_clear = 0;               // the cells [y, y + 0.04]
  for (double y = 1.5; y > 0.0; y -= 0.002) {  // from the left border inwards
    double ul = 0, ur = 0;
    corners(y, &ul, &ur);
    if (ul < scene.view.edge_margin_px - 0.5) continue;  // not wholly in the left image
    if (y_cut == 0 && ur < kMargin - 0.5) y_cut = y;
    if (ur >= kMargin + 0.5) {
      y_clear = y;
      break;
    }
  }
  ASSERT_GT(y_cut, 0.0);
  ASSERT_GT(y_clear, 0.0);
  for (const double y0 : {y_cut, y_clear}) {
    for (const double margin : {0.0, kMargin}) {
      Scene s;
      s.view.right_edge_margin_px = margin;
      std::vector<Eigen::Vector2i> inside, near;
      s.pixels_of(kX0, kX1, y0, y0 + 0.04, 0.0, &inside, &near);
      ASSERT_GT(inside.size(), 20u);
      for (const auto& p : inside) s.at(p.x(), p.y()) = 0;
      const float expected = y0 == y_cut && margin > 0 ? 0.0f : kHoleSeen;
      EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, y0, y0 + 0.04, 0.0, kTol), expected)
          << (y0 == y_cut ? "cell cut by the right image's border" : "cell clear of it")
          << ", margin " << margin;
    }
  }
}

TEST(HoleMarker, OnlyPixelsOnTheStrideGridCount) {
  // The grid starts at the region's corner: odd columns, even rows.
  const auto on_grid = [](const Eigen::Vector2i& p) { return (p.x() - 1) % 2 == 0 && p.y() % 2 == 0; };
  for (const bool kill_on_grid : {false, true}) {
    Scene s;
    s.view.stride = 2;
    s.view.roi_x0 = 1;
    int killed = 0;
    for (const auto& p : quarter_pixels(s, 0))
      if (on_grid(p) == kill_on_grid) {
        s.at(p.x(), p.y()) = 0;
        ++killed;
      }
    ASSERT_GT(killed, 0);
    EXPECT_EQ(HoleMarker::test_cell(s.view, kX0, kX1, kY0, kY1, 0.0, kTol), kill_on_grid ? kHoleSeen : kSeenWhole);
  }
}

TEST(HoleMarker, MarkRaisesKnownCellsAndAHoleIsFinal) {
  Scene s;
  LayerGrids g;
  const int n = 8;
  const double r = 0.04;  // cell borders at x = 0.68 + k r, y = 0.40 + k r
  for (DenseGrid* d : {&g.height, &g.coverage, &g.count, &g.evaluable})
    d->reset(n, n, r, 0.68, 0.40, std::nanf(""));
  // The cell [0.68, 0.72] x [0.40, 0.44], and three beside it.
  int row = 0, col = 0;
  ASSERT_TRUE(g.height.cell_at(0.68 + 0.5 * r, 0.40 + 0.5 * r, &row, &col));
  auto set = [&](int rr, int cc, float cov, float count, float evaluable) {
    g.height.at(rr, cc) = 0.0f;
    g.coverage.at(rr, cc) = cov;
    g.count.at(rr, cc) = count;
    g.evaluable.at(rr, cc) = evaluable;
  };
  // Known cells, whatever their coverage, points or plane (a hole seen before a cell has
  // enough points still counts later); not unknown ones.
  set(row, col, 0.6f, 50, 0);
  set(row, col + 1, 0.3f, 50, 0);
  set(row, col + 2, 0.6f, 5, 0);
  set(row + 1, col, 0.9f, 50, 1);
  DenseGrid marks;
  marks.reset(n, n, r, g.height.center_x_m, g.height.center_y_m, 0.0f);
  const GridRect changed = HoleMarker::mark(s.view, g, kTol, marks);
  int marked = 0;
  for (float m : marks.values) marked += m != 0.0f;
  EXPECT_EQ(marked, 4);
  for (const auto& [rr, cc] : {std::pair{row, col}, {row, col + 1}, {row, col + 2}, {row + 1, col}})
    EXPECT_EQ(marks.at(rr, cc), kSeenWhole) << rr << " " << cc;
  EXPECT_EQ(changed.row0, row);
  EXPECT_EQ(changed.row1, row + 2);
  EXPECT_EQ(changed.col0, col);
  EXPECT_EQ(changed.col1, col + 3);
  // A second frame sees the same: nothing changes.
  EXPECT_TRUE(HoleMarker::mark(s.view, g, kTol, marks).empty());
  // A frame with a hole over it ends it, for good.
  const double x = g.height.x_of_col(col), y = g.height.y_of_row(row);
  std::vector<Eigen::Vector2i> inside, near;
  s.pixels_of(x - 0.5 * r, x + 0.5 * r, y - 0.5 * r, y + 0.5 * r, 0.0, &inside, &near);
  ASSERT_FALSE(inside.empty());
  const std::vector<std::int16_t> kept = s.disparity;
  for (const auto& p : inside) {  // the cell's upper-right quarter: every pixel
    double depth = 0;
    Eigen::Vector2d q;
    s.ground_depth(p.x(), p.y(), &depth, &q);
    if (q.x() >= x && q.y() >= y) s.at(p.x(), p.y()) = 0;
  }
  EXPECT_FALSE(HoleMarker::mark(s.view, g, kTol, marks).empty());
  EXPECT_EQ(marks.at(row, col), kHoleSeen);
  s.disparity = kept;
  EXPECT_TRUE(HoleMarker::mark(s.view, g, kTol, marks).empty());
  EXPECT_EQ(marks.at(row, col), kHoleSeen);
}

Measurement point(double x, double y, double z) {
  Measurement m{};
  m.p_W = Eigen::Vector3f(float(x), float(y), float(z));
  m.cov_xx = m.cov_yy = 1e-6f;
  m.cov_zz = 4e-6f;
  return m;
}

/// An 8 x 8 CCM layer of r-metre cells that took `cloud` in one frame (with
/// `hole_free_coverage` > 0 it keeps the cells' occupancy masks), and its export without
/// marks in `plain`.
std::unique_ptr<LayerStack> one_ccm_layer(double r, double hole_free_coverage,
                                          const PointCloud& cloud, LayerGrids& plain) {
  MapConfig map;
  LayerConfig l;
  l.rule = RuleKind::ccm;
  l.resolution_m = r;
  l.size = 8;
  l.hole_free_coverage = hole_free_coverage;
  map.layers.push_back(l);
  auto s = std::make_unique<LayerStack>(map, RulesConfig{}, HazardConfig{});
  s->begin_frame(0.0, 0.0);
  s->insert(MapPoints(cloud));
  s->export_layer(0, plain);
  return s;
}

// mark() in bands of rows on threads against one thread: the same marks and the same
// changed rectangle, over a field of known cells with holes punched in the disparities
// and some cells off the ground plane, frame after frame.
TEST(HoleMarker, BandsOnThreadsMarkAsOneThread) {
  Scene s;
  std::mt19937 rng(41);
  std::uniform_int_distribution<int> pixel_u(0, 399), pixel_v(0, 299);
  for (int k = 0; k < 150; ++k) {  // holes of 12 x 12 pixels
    const int u0 = pixel_u(rng), v0 = pixel_v(rng);
    for (int v = v0; v < std::min(300, v0 + 12); ++v)
      for (int u = u0; u < std::min(400, u0 + 12); ++u) s.at(u, v) = 0;
  }
  LayerGrids g;
  const int n = 24;
  const double r = 0.04;
  for (DenseGrid* d : {&g.height, &g.coverage, &g.count, &g.evaluable})
    d->reset(n, n, r, 0.9, 0.45, 0.0f);
  std::uniform_real_distribution<float> u01(0.f, 1.f);
  for (int i = 0; i < n * n; ++i) {
    const float p = u01(rng);
    g.height.values[static_cast<size_t>(i)] = p < 0.1f ? std::nanf("") : p < 0.2f ? 0.05f : 0.0f;
  }
  for (const int threads : {2, 3}) {
    const testing::ThreadsFor pool(threads);
    DenseGrid one, many;
    one.reset(n, n, r, 0.9, 0.45, 0.0f);
    many.reset(n, n, r, 0.9, 0.45, 0.0f);
    for (int frame = 0; frame < 2; ++frame) {
      const GridRect a = HoleMarker::mark(s.view, g, kTol, one);
      const GridRect b = HoleMarker::mark(s.view, g, kTol, many, 1e300, &pool);
      EXPECT_TRUE(a == b) << threads << " threads, frame " << frame;
      EXPECT_EQ(one.values, many.values) << threads << " threads, frame " << frame;
    }
    int whole = 0, holes = 0;
    for (const float m : one.values) whole += m == kSeenWhole, holes += m == kHoleSeen;
    EXPECT_GT(whole, 40);  // both verdicts occur, on many cells
    EXPECT_GT(holes, 20);
  }
}

TEST(HoleMarker, ExportGivesAMarkedPartlyCoveredCellItsPlane) {
  // Cell [0, r)^2 holds points on z = 1 + 0.3 x - 0.2 y over x in [0, 0.74 r): coverage
  // 0.548 (kappa of a uniform strip 0.74 wide), short of rules.ccm.min_coverage 0.8, and
  // no point in its last column of 4 x 4 sub-cells (from 0.75 r), so only a mark gives it
  // a plane.
  const double r = 0.04;
  PointCloud cloud;
  const int k = 40;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const double x = 0.74 * r * (i + 0.5) / k, y = r * (j + 0.5) / k;
      cloud.push_back(point(x, y, 1.0 + 0.3 * x - 0.2 * y));
      // Cell [r, 2r) x [0, r): covered whole, evaluable by the rule itself.
      const double xf = r + r * (i + 0.5) / k;
      cloud.push_back(point(xf, y, 1.0 + 0.3 * xf - 0.2 * y));
    }
  LayerGrids plain;
  const std::unique_ptr<LayerStack> s = one_ccm_layer(r, 0.0, cloud, plain);
  int row = 0, col = 0;
  ASSERT_TRUE(plain.height.cell_at(0.5 * r, 0.5 * r, &row, &col));
  ASSERT_NEAR(plain.coverage.at(row, col), 0.74 * 0.74, 0.01);
  ASSERT_EQ(plain.evaluable.at(row, col), 0.0f);
  EXPECT_NEAR(plain.height.at(row, col), 1.0 + 0.3 * 0.37 * r - 0.2 * 0.5 * r, 1e-5);  // mu_z

  DenseGrid marks;
  marks.reset(8, 8, r, plain.height.center_x_m, plain.height.center_y_m, 0.0f);
  struct Case {
    float mark;
    double min_coverage;
    int min_points;
    bool evaluable;
  };
  for (const Case c : {Case{kSeenWhole, 0.5, 10, true}, Case{0.0f, 0.5, 10, false},
                       Case{kHoleSeen, 0.5, 10, false}, Case{kSeenWhole, 0.7, 10, false},
                       Case{kSeenWhole, 0.5, k * k + 1, false}}) {
    marks.at(row, col) = c.mark;
    const SeenWhole rule{&marks, c.min_coverage, c.min_points};
    LayerGrids g;
    s->export_layer(0, g, &rule);
    // A plane by the mark is for the cell's own tests only (kEvaluableOwnCell).
    ASSERT_EQ(g.evaluable.at(row, col), c.evaluable ? kEvaluableOwnCell : 0.0f) << c.mark << " " << c.min_coverage;
    if (c.evaluable) {
      // The plane at the centre, its slopes, and the points' own height spread (no tilt
      // added for a plane nobody measured).
      EXPECT_NEAR(g.height.at(row, col), 1.0 + 0.3 * 0.5 * r - 0.2 * 0.5 * r, 1e-5);
      EXPECT_NEAR(g.slope_x.at(row, col), 0.3, 1e-3);
      EXPECT_NEAR(g.slope_y.at(row, col), -0.2, 1e-3);
      EXPECT_LT(g.variance.at(row, col), plain.variance.at(row, col));
      // No wheel-ring sample for another cell: to the rings its plane is as absent as
      // before the mark (with no plane next door, its mean: evidence, not exact).
      LayerGrids alone = g;
      int nrow = 0, ncol = 0;
      ASSERT_TRUE(alone.height.cell_at(1.5 * r, 0.5 * r, &nrow, &ncol));
      alone.evaluable.at(nrow, ncol) = 0.0f;
      const PlaneSurface surface(LayerHazardParams{});
      const RingSample own = surface.at(alone, 0.25 * r, 0.5 * r);
      EXPECT_TRUE(own.known);
      EXPECT_FALSE(own.exact);
      alone.evaluable.at(row, col) = 1.0f;  // the rule's plane would be one
      EXPECT_TRUE(surface.at(alone, 0.25 * r, 0.5 * r).exact);
    } else {
      EXPECT_EQ(g.height.at(row, col), plain.height.at(row, col));
      EXPECT_EQ(g.variance.at(row, col), plain.variance.at(row, col));
    }
  }
  // A cell the rule itself gives a plane keeps it whatever its mark (a veto by holes made
  // the map blind: docs/hazards.md).
  int frow = 0, fcol = 0;
  ASSERT_TRUE(plain.height.cell_at(1.5 * r, 0.5 * r, &frow, &fcol));
  ASSERT_EQ(plain.evaluable.at(frow, fcol), 1.0f);
  for (const float mark : {0.0f, kSeenWhole, kHoleSeen}) {
    marks.at(frow, fcol) = mark;
    const SeenWhole rule{&marks, 0.5, 10};
    LayerGrids g;
    s->export_layer(0, g, &rule);
    EXPECT_EQ(g.evaluable.at(frow, fcol), 1.0f) << mark;
    EXPECT_NEAR(g.slope_x.at(frow, fcol), 0.3, 1e-3) << mark;
  }
}

// A cell sampled unevenly but everywhere: z = 1 + 0.3 x - 0.2 y on 34 columns of points
// over its left half and 6 over its right half (three per sub-cell column), 40 rows. Its
// spread, computed here from the columns (0.63), is short of rules.ccm.min_coverage 0.8; its
// points fill all 16 sub-cells, so with hole_free_coverage it gets its plane for its own
// tests without any mark. Without the right half's first row of sub-cells (a corner left
// unmeasured: 14 of 16 filled; spread 0.56) it does not.
TEST(HoleMarker, ExportGivesAnUnevenlySampledCellWithEverySubCellFilledItsPlane) {
  const double r = 0.04;
  std::vector<double> columns;
  for (int i = 0; i < 34; ++i) columns.push_back(0.5 * r * (i + 0.5) / 34);
  for (int i = 0; i < 6; ++i) columns.push_back(0.5 * r + 0.5 * r * (i + 0.5) / 6);
  double mean = 0, square = 0;
  const double count = static_cast<double>(columns.size());
  for (const double x : columns) mean += x / count;
  for (const double x : columns) square += (x - mean) * (x - mean) / count;
  const double kappa = square / (r * r / 12.0);
  ASSERT_GT(kappa, 0.5);
  ASSERT_LT(kappa, 0.8);
  for (const bool corner_missing : {false, true}) {
    PointCloud cloud;
    for (const double x : columns)
      for (int j = 0; j < 40; ++j) {
        const double y = r * (j + 0.5) / 40;
        if (corner_missing && x >= 0.5 * r && y < 0.25 * r) continue;
        cloud.push_back(point(x, y, 1.0 + 0.3 * x - 0.2 * y));
      }
    LayerGrids plain;
    // hole_free_coverage 0.5: the layer keeps the occupancy mask.
    const std::unique_ptr<LayerStack> s = one_ccm_layer(r, 0.5, cloud, plain);
    int row = 0, col = 0;
    ASSERT_TRUE(plain.height.cell_at(0.5 * r, 0.5 * r, &row, &col));
    if (!corner_missing) {
      ASSERT_NEAR(plain.coverage.at(row, col), kappa, 1e-3);
    }
    ASSERT_GT(plain.coverage.at(row, col), 0.5);
    ASSERT_EQ(plain.evaluable.at(row, col), 0.0f);
    DenseGrid marks;
    marks.reset(8, 8, r, plain.height.center_x_m, plain.height.center_y_m, 0.0f);
    // No mark, and a hole mark (points have since landed in every sub-cell).
    for (const float mark : {0.0f, kHoleSeen}) {
      marks.at(row, col) = mark;
      for (const double min_coverage : {0.5, 0.8}) {
        const SeenWhole rule{&marks, min_coverage, 10};
        LayerGrids g;
        s->export_layer(0, g, &rule);
        const bool evaluable = !corner_missing && min_coverage == 0.5;
        ASSERT_EQ(g.evaluable.at(row, col), evaluable ? kEvaluableOwnCell : 0.0f)
            << "corner missing " << corner_missing << ", mark " << mark << ", min coverage "
            << min_coverage;
        if (evaluable) {
          EXPECT_NEAR(g.height.at(row, col), 1.0 + 0.3 * 0.5 * r - 0.2 * 0.5 * r, 1e-5);
          EXPECT_NEAR(g.slope_x.at(row, col), 0.3, 1e-3);
          EXPECT_NEAR(g.slope_y.at(row, col), -0.2, 1e-3);
        }
      }
    }
  }
}

}  // namespace
}  // namespace hazmap
