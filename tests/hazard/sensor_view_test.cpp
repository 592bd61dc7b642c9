// hazard.partial_ring_proof: view_edge (issue 34). SensorView's column test against an
// independent pinhole projection of densely sampled points; the view mask's levels; and
// the rule itself on a real layer stack and hazard stage: a ring cut by the edge of the
// view proves from its seen part, a ring with a hole inside the view does not.

#include "hazmap/hazard/sensor_view.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {
namespace {

/// A 400 x 300 camera 0.25 m above the wheel plane, pitched down by `pitch_deg` from
/// looking along body x, with the body at `T_W_B`.
SensorView forward_camera(double pitch_deg, const Pose3d& T_W_B = Pose3d::Identity()) {
  SensorView v;
  v.T_W_B = T_W_B;
  // Camera axes in the body: x_C = -y_B, y_C = -z_B, z_C = x_B when level; then pitched.
  Eigen::Matrix3d level;
  level.col(0) = Eigen::Vector3d(0, -1, 0);
  level.col(1) = Eigen::Vector3d(0, 0, -1);
  level.col(2) = Eigen::Vector3d(1, 0, 0);
  const Eigen::Matrix3d pitch =
      Eigen::AngleAxisd(pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  v.T_B_C.linear() = pitch * level;
  v.T_B_C.translation() = Eigen::Vector3d(0.05, 0.0, 0.25);
  v.focal_px = 300;
  v.cx_px = 199.5;
  v.cy_px = 149.5;
  v.width_px = 400;
  v.height_px = 300;
  v.edge_margin_px = 5;
  v.z_min_m = 0.05;
  v.z_max_m = 3.0;
  v.band_below_m = 0.2;
  v.band_above_m = 0.1;
  return v;
}

/// Independent: does W point p project into the matchable image within the depth range?
bool point_in_view(const SensorView& v, const Eigen::Vector3d& p_W) {
  const Eigen::Matrix3d R_W_C = v.T_W_B.linear() * v.T_B_C.linear();
  const Eigen::Vector3d c_W = v.T_W_B * v.T_B_C.translation();
  const Eigen::Vector3d p = R_W_C.transpose() * (p_W - c_W);
  if (p.z() < v.z_min_m || p.z() > v.z_max_m) return false;
  Eigen::Matrix3d K;
  K << v.focal_px, 0, v.cx_px, 0, v.focal_px, v.cy_px, 0, 0, 1;
  const Eigen::Vector3d uvw = K * p;
  const double u = uvw.x() / uvw.z(), vv = uvw.y() / uvw.z();
  const double m = v.edge_margin_px;
  // Its match in the right image, when the view checks it.
  const bool right = v.right_edge_margin_px <= 0 ||
                     u - v.focal_px * v.baseline_m / p.z() >= v.right_edge_margin_px - 0.5;
  return right && u >= m - 0.5 && u <= v.width_px - 0.5 - m && vv >= m - 0.5 &&
         vv <= v.height_px - 0.5 - m;
}

TEST(SensorView, ColumnTestMatchesDenselySampledPointsOfTheBand) {
  // The exact segment test must say "seen" wherever one of 2001 points along the band's
  // column projects into the view (a superset: never narrower), and differ from the
  // samples only where the segment's visible part falls between two of them. Without
  // and with the right image's border (a 5 cm baseline, its matches 11 px in from it).
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()))
                       .toRotationMatrix();  // yawed, on a 6 deg slope
  T_W_B.translation() = Eigen::Vector3d(1.0, -2.0, 0.3);
  std::vector<int> seen_by_case;
  for (const double right_margin : {0.0, 11.0}) {
    SensorView view = forward_camera(35.0, T_W_B);
    view.baseline_m = 0.05;
    view.right_edge_margin_px = right_margin;
    const Eigen::Vector3d n = T_W_B.linear().col(2), o = T_W_B.translation();
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    int seen = 0, differ = 0;
    const int cases = 4000;
    for (int i = 0; i < cases; ++i) {
      const double x = o.x() + u(rng), y = o.y() + u(rng);
      bool sampled = false;
      for (int k = 0; k <= 2000 && !sampled; ++k) {
        const double h = -view.band_below_m + (view.band_below_m + view.band_above_m) * k / 2000.0;
        // The point of the vertical line over (x, y) that lies h above the wheel plane.
        const double z = o.z() + (h - n.x() * (x - o.x()) - n.y() * (y - o.y())) / n.z();
        sampled = point_in_view(view, {x, y, z});
      }
      const bool exact = view.sees_column(x, y);
      ASSERT_TRUE(exact || !sampled) << "narrower than its own samples at " << x << ", " << y
                                     << ", right margin " << right_margin;
      seen += exact;
      differ += exact != sampled;
    }
    EXPECT_GT(seen, cases / 20) << right_margin;  // the test covers the view, not only its outside
    EXPECT_LE(differ, cases / 1000) << right_margin;  // only slivers between samples
    seen_by_case.push_back(seen);
  }
  // The right image's border takes a band off the view's left side: the cases can differ.
  EXPECT_LT(seen_by_case[1], seen_by_case[0]);
}

TEST(SensorView, MaskCountsCellsWhollyOrPartlyViewedAndReportsWhatChanged) {
  const SensorView view = forward_camera(30.0);
  DenseGrid mask;
  mask.reset(128, 128, 0.02, 0.0, 0.0, 0.0f);
  ViewMarker marker;
  const GridRect changed = marker.mark(view, mask);
  int wholly = 0, partly = 0;
  GridRect bounds;
  for (int row = 0; row < mask.rows; ++row)
    for (int col = 0; col < mask.cols; ++col) {
      const double x = mask.x_of_col(col), y = mask.y_of_row(row), h = 0.01;
      int corners = view.sees_column(x, y);
      for (double dx : {-h, h})
        for (double dy : {-h, h}) corners += view.sees_column(x + dx, y + dy);
      const float want = corners == 5 ? kWhollyViewed : corners > 0 ? kPartlyViewed : 0.0f;
      ASSERT_EQ(mask.at(row, col), want) << row << ", " << col;
      wholly += want == kWhollyViewed;
      partly += want == kPartlyViewed;
      if (want > 0) bounds = bounds.hull({row, row + 1, col, col + 1});
    }
  EXPECT_GT(wholly, 500);
  EXPECT_GT(partly, 20);
  EXPECT_EQ(changed, bounds);
  // Nothing behind the camera: the rover's rear half is never looked at.
  for (int row = 0; row < mask.rows; ++row)
    for (int col = 0; col < mask.cols; ++col)
      if (mask.x_of_col(col) < 0.0) {
        ASSERT_EQ(mask.at(row, col), 0.0f);
      }
  // The same view again changes nothing.
  const std::vector<float> before = mask.values;
  EXPECT_TRUE(marker.mark(view, mask).empty());
  EXPECT_EQ(mask.values, before);
}

TEST(SensorView, TerrainBandReadsTheFirstLayerThatKnowsTheHeight) {
  DenseGrid h16, v16, h64, v64;
  h16.reset(4, 4, 0.16, 0.0, 0.0, std::nanf(""));
  v16.reset(4, 4, 0.16, 0.0, 0.0, 0.0f);
  h64.reset(4, 4, 0.64, 0.0, 0.0, 0.3f);
  v64.reset(4, 4, 0.64, 0.0, 0.0, 0.01f);
  h16.at(1, 2) = 0.1f;  // the cell holding (0.08, 0.08)
  v16.at(1, 2) = 0.0004f;
  TerrainBand band;
  band.add(&h16, &v16, 3.0, 0.05);
  band.add(&h64, &v64, 3.0, 0.2);
  double lo = 0, hi = 0;
  ASSERT_TRUE(band.at(0.08, 0.08, &lo, &hi));
  EXPECT_NEAR(lo, 0.1 - 3 * 0.02 - 0.05, 1e-6);
  EXPECT_NEAR(hi, 0.1 + 3 * 0.02 + 0.05, 1e-6);
  ASSERT_TRUE(band.at(-0.2, 0.2, &lo, &hi));  // unknown at 16 cm: the 64 cm layer's
  EXPECT_NEAR(lo, 0.3 - 0.3 - 0.2, 1e-6);
  EXPECT_FALSE(band.at(5.0, 0.0, &lo, &hi));  // outside every grid
}

// The rule on a real layer stack and hazard stage. A camera 0.5 m up looks straight down:
// flat ground, measured every 3 mm wherever the camera sees it (with a 4 cm hole inside
// the view), on a 1 cm Kalman layer.
struct DownView {
  SensorView view;
  DownView() {
    view.T_B_C.linear().col(0) = Eigen::Vector3d(0, -1, 0);
    view.T_B_C.linear().col(1) = Eigen::Vector3d(-1, 0, 0);
    view.T_B_C.linear().col(2) = Eigen::Vector3d(0, 0, -1);
    view.T_B_C.translation() = Eigen::Vector3d(0, 0, 0.5);
    view.focal_px = 500;
    view.cx_px = view.cy_px = 199.5;
    view.width_px = view.height_px = 400;
    view.z_min_m = 0.05;
    view.z_max_m = 3.0;
    view.band_below_m = view.band_above_m = 0.02;
  }
};

float class_at(const HazardStage& stage, double x, double y) {
  int row = 0, col = 0;
  const DenseGrid& h = stage.layers()[0].hazard;
  EXPECT_TRUE(h.cell_at(x, y, &row, &col));
  return h.at(row, col);
}

TEST(SensorView, ViewEdgeProvesARingCutByTheViewAndNotOneWithAHoleInside) {
  const DownView down;
  // At the camera's 0.5 m the matchable footprint is |x|, |y| < (200 - 0.5) / 500 x 0.5,
  // about 0.2 m; the hole is a 4 cm square around (0, -0.15).
  const auto in_hole = [](double x, double y) { return std::abs(x) < 0.02 && std::abs(y + 0.15) < 0.02; };
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.0005);
  PointCloud cloud;
  for (double y = -0.6; y < 0.6; y += 0.003)
    for (double x = -0.6; x < 0.6; x += 0.003) {
      if (!down.view.sees_column(x, y) || in_hole(x, y)) continue;
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x), float(y), float(noise(rng)));
      m.cov_xx = m.cov_yy = 1e-6f;
      m.cov_zz = float(0.0005 * 0.0005);
      cloud.push_back(m);
    }
  for (const PartialRingProof mode :
       {PartialRingProof::off, PartialRingProof::view_edge, PartialRingProof::any}) {
    Config config;
    LayerConfig layer;
    layer.rule = RuleKind::kalman;
    layer.resolution_m = 0.01;
    layer.size = 128;
    layer.hazard.kernel = 7;
    config.map.layers = {layer};
    config.hazard.partial_ring_proof = mode;
    LayerStack stack(config.map, config.rules);
    HazardStage stage(resolve_hazard_params(config), false);
    stack.begin_frame(0.001, 0.001);
    stack.insert(MapPoints(cloud));
    stage.run(stack, &down.view);
    // (0.105, 0.005): ring samples 0, 1 and 7 (x >= 0.21) lie outside the view; 2-6
    // hold the pair 2-6 and are measured. (0.005, 0.005): its whole ring lies in the
    // view, and sample 6 in the hole.
    const float edge = class_at(stage, 0.105, 0.005), hole = class_at(stage, 0.005, 0.005);
    const float T = float(HazardClass::traversable), U = float(HazardClass::unknown);
    switch (mode) {
      case PartialRingProof::off:
        EXPECT_EQ(edge, U);
        EXPECT_EQ(hole, U);
        break;
      case PartialRingProof::view_edge:
        EXPECT_EQ(edge, T);
        EXPECT_EQ(hole, U);
        break;
      case PartialRingProof::any:
        EXPECT_EQ(edge, T);
        EXPECT_EQ(hole, T);
        break;
    }
    // Without a view nothing is known to lie outside it: only full rings prove.
    HazardStage blind(resolve_hazard_params(config), false);
    blind.run(stack);
    if (mode != PartialRingProof::any) {
      EXPECT_EQ(class_at(blind, 0.105, 0.005), U);
    }
  }
}

}  // namespace
}  // namespace hazmap
