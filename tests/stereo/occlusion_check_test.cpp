// The occlusion check of PointCloudBuilder (stereo.occlusion_*) on analytic worlds: a
// 10 cm block on level ground, the CADRE camera 15 cm up and 34 deg down right above its
// near edge, so that its top is nearer than the disparity search reaches. Each pixel's
// true depth comes from marching its ray through the analytic terrain; pixels whose true
// disparity lies beyond the search get an aliased one, a third of it, as block matching
// gives them (measured on rendered views: the rock top at 187 px matched at ~100 px).

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "hazmap/map/map_points.hpp"
#include "hazmap/stereo/point_cloud_builder.hpp"

namespace hazmap {
namespace {

// 0.1 x CADRE: 160 x 130 px, f = 67.1 px, B = 5 cm; 40 disparities reach f B / 40 =
// 8.4 cm, as 160 do at 0.4 scale.
const StereoGeometry kGeometry{67.1, 0.05, 79.5, 64.5};
constexpr int kCols = 160, kRows = 130, kDisparities = 40;
constexpr double kBlockX0 = 0.0, kBlockX1 = 0.2, kBlockHalfWidth = 0.1, kBlockHeight = 0.1;

double terrain_height(double x, double y) {
  return x >= kBlockX0 && x < kBlockX1 && std::abs(y) < kBlockHalfWidth ? kBlockHeight : 0.0;
}

// The lowest terrain within 1 cm of (x, y): a point on the block's vertical faces is not
// below the terrain.
double terrain_floor(double x, double y) {
  double h = std::numeric_limits<double>::infinity();
  for (double dx : {-0.01, 0.0, 0.01})
    for (double dy : {-0.01, 0.0, 0.01}) h = std::min(h, terrain_height(x + dx, y + dy));
  return h;
}

Pose3d camera_in_body() {
  Pose3d T_B_C = Pose3d::Identity();
  T_B_C.linear() = rotation_from_rpy(-M_PI / 2 - 34.0 * M_PI / 180.0, 0.0, -M_PI / 2);
  T_B_C.translation() = Eigen::Vector3d(0.0, 0.025, 0.15);
  return T_B_C;
}

struct Scene {
  cv::Mat disparity_x16;
  cv::Mat aliased;  ///< CV_8U: 1 where the true disparity is beyond the search
  int aliased_count = 0;
};

// True depth by marching each ray in 1 mm steps of depth to the first sample at or
// below the terrain (`height`, the block world by default); disparities in range as they
// are, beyond it a third.
Scene render(const Pose3d& T_W_C, double (*height)(double, double) = terrain_height) {
  Scene s;
  s.disparity_x16.create(kRows, kCols, CV_16S);
  s.aliased = cv::Mat::zeros(kRows, kCols, CV_8U);
  const double fb = kGeometry.focal_px * kGeometry.baseline_m;
  for (int v = 0; v < kRows; ++v)
    for (int u = 0; u < kCols; ++u) {
      const Eigen::Vector3d ray_W =
          T_W_C.linear() * Eigen::Vector3d((u - kGeometry.cx_px) / kGeometry.focal_px,
                                           (v - kGeometry.cy_px) / kGeometry.focal_px, 1.0);
      double depth = 0.0;
      for (double z = 0.001; z < 3.0; z += 0.001) {
        const Eigen::Vector3d p = T_W_C.translation() + z * ray_W;
        if (p.z() <= height(p.x(), p.y())) {
          depth = z;
          break;
        }
      }
      double d = depth > 0.0 ? fb / depth : 0.0;
      if (d >= kDisparities) {
        d /= 3.0;
        s.aliased.at<uint8_t>(v, u) = 1;
        ++s.aliased_count;
      }
      s.disparity_x16.at<int16_t>(v, u) = d > 0.0 ? static_cast<int16_t>(std::lround(16 * d)) : -16;
    }
  return s;
}

// The terrain as a map would publish it: 1 cm cells over [-0.5, 0.78) x [-0.64, 0.64),
// heights at the cell centres, variance 1 mm^2; cells with x in [unseen_x0, unseen_x1)
// unseen (NaN).
struct PublishedTerrain {
  DenseGrid height, variance, none;
  PublishedTerrain(double unseen_x0, double unseen_x1) {
    height.reset(128, 128, 0.01, 0.14, 0.0, 0.0f);
    variance.reset(128, 128, 0.01, 0.14, 0.0, 1e-6f);
    for (int r = 0; r < 128; ++r)
      for (int c = 0; c < 128; ++c) {
        const double x = height.x_of_col(c), y = height.y_of_row(r);
        height.at(r, c) = x >= unseen_x0 && x < unseen_x1
                              ? std::numeric_limits<float>::quiet_NaN()
                              : static_cast<float>(terrain_height(x, y));
      }
  }
};

StereoConfig test_stereo() {
  StereoConfig s;
  s.num_disparities = kDisparities;
  s.min_disparity = 0;
  s.z_min_m = 0.02;
  s.z_max_m = 3.0;
  return s;
}

// Deepest point of a cloud below the analytic terrain [m] (negative: none below).
double deepest_below(const PointCloud& cloud) {
  double worst = -std::numeric_limits<double>::infinity();
  for (const Measurement& m : cloud)
    worst = std::max(worst, terrain_floor(m.p_W.x(), m.p_W.y()) - m.p_W.z());
  return worst;
}

TEST(OcclusionCheck, RayBlockedByKnownTerrainAndItsUnseenContinuation) {
  // Level ground known at 0 and the block's first 10 cm known at 0.1 m; the rest of the
  // block (x in [0.1, 0.2)) unseen. Camera 15 cm above the origin; rays by their W
  // direction per metre of depth (here simply their direction: depth = distance).
  PublishedTerrain published(0.1, 0.2);
  KnownTerrain t;
  t.add_layer(published.height, published.variance, published.none, published.none);
  t.prepare_near_field(-0.1, -0.2, 0.7, 0.2, 0.03, 3.0);
  Eigen::Vector3d camera(0.0, 0.0, 0.15);
  RayCheck c;
  c.near_m = 0.084;
  c.margin_m = 0.01;
  c.sample_m = 0.01;
  c.known_level_m = t.max_top() - c.margin_m;
  c.unseen_level_m = t.max_unseen_height();
  const auto blocked = [&](const Eigen::Vector3d& to, double reach) {
    RayCheck k = c;
    const Eigen::Vector3d dir = (to - camera).normalized();
    k.depth_m = std::min(reach, (to - camera).norm());
    return ray_blocked(t, camera, dir, k);
  };
  // Ground behind the block, seen through its known part (6 cm below its top at x 0.05).
  EXPECT_TRUE(blocked({0.1, 0.0, 0.0}, 1.0));
  // ... not when the check ends before the ray enters the block.
  EXPECT_FALSE(blocked({0.1, 0.0, 0.0}, 0.02));
  // The block's top itself, and ground in front of it (x < 0 is ground).
  EXPECT_FALSE(blocked({0.05, 0.0, 0.1}, 1.0));
  EXPECT_FALSE(blocked({-0.2, 0.05, 0.0}, 1.0));
  // A ray grazing the known top by less than the margin (+ 3 sigma) passes: no evidence.
  EXPECT_FALSE(blocked({0.099, 0.0, 0.1 - 0.008 * 2}, 0.0999));
  // Ground beside the block, away from anything unseen or higher: clear.
  EXPECT_FALSE(blocked({0.3, 0.3, 0.0}, 1.0));
  // From 15 cm above x = 0.08, a ray over the known top (12 cm at its edge x = 0.1), then
  // over the unseen part: within 3 cm of the known top, below the assumed 0.1 m (at
  // x 0.12, 9 cm) within the near field, blocked; with no near field not, nor when the
  // point lies nearer than that (the stretch ends before).
  camera = Eigen::Vector3d(0.08, 0.0, 0.15);
  EXPECT_TRUE(blocked({0.16, 0.0, 0.03}, 1.0));
  EXPECT_FALSE(blocked({0.11, 0.0, 0.105}, 1.0));
  c.near_m = 0.0;
  EXPECT_FALSE(blocked({0.16, 0.0, 0.03}, 1.0));
}

// A drive's frame over a rock nearer than the search reaches, at the builder: without the
// map's terrain the aliased disparities put points far below the block's top (the
// failure); with it every such point is dropped and the kept ones follow the terrain.
TEST(OcclusionCheck, AliasedPointsOfASurfaceNearerThanTheSearchAreDropped) {
  const Pose3d T_B_C = camera_in_body();
  const Pose3d T_W_B = Pose3d::Identity();  // the camera above the block's near edge
  const Scene scene = render(T_W_B * T_B_C);
  ASSERT_GT(scene.aliased_count, 1000);
  const StereoConfig stereo = test_stereo();
  SensorConfig sensor;
  const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(), T_B_C,
                                  cv::Rect(0, 0, kCols, kRows));
  EXPECT_NEAR(builder.near_depth_m(0), 67.1 * 0.05 / 40, 1e-12);
  EXPECT_NEAR(builder.occlusion_depth_m(0), 2.0 * 67.1 * 0.05 / 40, 1e-12);

  PointCloud without, with;
  std::vector<cv::Point> pixels;
  const std::size_t below = builder.build(scene.disparity_x16, 0, T_W_B, without);
  const double deepest_without = deepest_below(without);
  EXPECT_GT(deepest_without, 0.08);  // the failure: measured 10.4 cm below the terrain

  PublishedTerrain published(1.0, 1.0);  // all known
  KnownTerrain terrain;
  terrain.add_layer(published.height, published.variance, published.none, published.none);
  builder.prepare_terrain(terrain, T_W_B);
  const PointDrops drops = builder.build(scene.disparity_x16, 0, T_W_B, terrain, with, &pixels);
  EXPECT_EQ(drops.below_ground, below);
  EXPECT_EQ(with.size() + drops.occluded, without.size());
  EXPECT_LT(deepest_below(with), 0.01);
  int aliased_kept = 0, true_dropped = 0, true_total = 0;
  for (const cv::Point& px : pixels) aliased_kept += scene.aliased.at<uint8_t>(px);
  for (int v = 0; v < kRows; ++v)
    for (int u = 0; u < kCols; ++u) true_total += scene.aliased.at<uint8_t>(v, u) == 0;
  true_dropped = static_cast<int>(drops.occluded) - (scene.aliased_count - aliased_kept);
  // Aliased points kept are those whose alias lands on or above the terrain (within the
  // margin): none is below it by more than 1 cm (above); in-range points are not dropped.
  EXPECT_LT(aliased_kept, scene.aliased_count / 10);  // measured: 475 of 9752
  EXPECT_EQ(true_dropped, 0);
  EXPECT_GT(true_total, 10000);

  // occlusion_reach 0 turns the check off.
  StereoConfig off = stereo;
  off.occlusion_reach = 0.0;
  const PointCloudBuilder open(off, sensor, kGeometry, Eigen::Matrix3d::Identity(), T_B_C,
                               cv::Rect(0, 0, kCols, kRows));
  open.prepare_terrain(terrain, T_W_B);
  PointCloud all;
  EXPECT_EQ(open.build(scene.disparity_x16, 0, T_W_B, terrain, all).occluded, 0u);
  EXPECT_EQ(all.size(), without.size());
}

// The block's far part never seen (the cameras only see it from right above, nearer than
// the search reaches): the aliased points over it are dropped only through the assumed
// continuation of its seen part (stereo.occlusion_fill).
TEST(OcclusionCheck, UnseenContinuationOfASeenSurfaceBlocksNearRays) {
  const Pose3d T_B_C = camera_in_body();
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.translation().x() = 0.08;  // the camera 2 cm short of the last seen cells
  const Scene scene = render(T_W_B * T_B_C);
  PublishedTerrain published(0.1, 0.2);
  KnownTerrain terrain;
  terrain.add_layer(published.height, published.variance, published.none, published.none);
  SensorConfig sensor;
  double deepest[2] = {0, 0};
  std::size_t occluded[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    StereoConfig stereo = test_stereo();
    stereo.occlusion_fill_m = k == 0 ? 0.0 : 0.03;
    const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(), T_B_C,
                                    cv::Rect(0, 0, kCols, kRows));
    builder.prepare_terrain(terrain, T_W_B);
    PointCloud cloud;
    occluded[k] = builder.build(scene.disparity_x16, 0, T_W_B, terrain, cloud).occluded;
    deepest[k] = deepest_below(cloud);
  }
  EXPECT_GT(deepest[0], 0.08);  // without the fill the unseen part takes aliased points
  EXPECT_LT(deepest[1], 0.01);
  EXPECT_GT(occluded[1], occluded[0]);
}

// The pipeline's direct float path applies the same check: on both scenes it drops the
// same pixels as the cloud path (the ray in float decides no case differently here), keeps
// the same points, and the marked disparity image gives those points without the terrain.
TEST(OcclusionCheck, MapPointsPathDropsWhatTheCloudPathDrops) {
  const Pose3d T_B_C = camera_in_body();
  for (double x : {0.0, 0.08}) {
    SCOPED_TRACE(x);
    Pose3d T_W_B = Pose3d::Identity();
    T_W_B.translation().x() = x;
    const Scene scene = render(T_W_B * T_B_C);
    PublishedTerrain published(x == 0.0 ? 1.0 : 0.1, x == 0.0 ? 1.0 : 0.2);
    KnownTerrain terrain;
    terrain.add_layer(published.height, published.variance, published.none, published.none);
    const StereoConfig stereo = test_stereo();
    SensorConfig sensor;  // the axis model
    const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(),
                                    T_B_C, cv::Rect(0, 0, kCols, kRows));
    builder.prepare_terrain(terrain, T_W_B);

    PointCloud cloud;
    cv::Mat marked_cloud = scene.disparity_x16.clone();
    const PointDrops by_cloud =
        builder.build(scene.disparity_x16, 0, T_W_B, terrain, cloud, nullptr, &marked_cloud);
    MapPoints points;
    cv::Mat marked = scene.disparity_x16.clone();
    const PointDrops direct = builder.build_map_points(scene.disparity_x16, 0, T_W_B, terrain,
                                                       CcmWeighting::constant, points, &marked);
    ASSERT_GT(by_cloud.occluded, 500u);
    EXPECT_EQ(direct.occluded, by_cloud.occluded);
    EXPECT_EQ(direct.below_ground, by_cloud.below_ground);
    ASSERT_EQ(static_cast<std::size_t>(points.size()), cloud.size());
    for (int i = 0; i < points.size(); ++i) {
      const PointChunk c = points.chunk(i, 1);
      ASSERT_NEAR(c.x[0], cloud[i].p_W.x(), 1e-5);  // float rounding
      ASSERT_NEAR(c.z[0], cloud[i].p_W.z(), 1e-5);
    }
    EXPECT_EQ(cv::countNonZero(marked != marked_cloud), 0);
    EXPECT_EQ(cv::countNonZero(marked != scene.disparity_x16),
              static_cast<int>(by_cloud.occluded));
    PointCloud again;
    builder.build(marked, 0, T_W_B, again);
    EXPECT_EQ(again.size(), cloud.size());
  }
}

// The builder's bounds before a ray's walk (the region's levels, then its row segment's
// box) only skip rays the walk would let through: on a rocky world seen by a yawed and
// rolled camera (row segments' boxes skewed), with unseen cells next to seen ones, the
// pixels the builder drops are exactly those whose rays ray_blocked, asked alone with the
// region's levels, finds blocked.
TEST(OcclusionCheck, TheBuilderDropsExactlyTheRaysTheWalkFindsBlocked) {
  const auto height = +[](double x, double y) {
    // Blocks 4-12 cm high on level ground, some nearer than the search reaches.
    const double rocks[][4] = {{0.02, -0.05, 0.06, 0.12},
                               {0.12, 0.06, 0.05, 0.08},
                               {0.25, -0.12, 0.07, 0.10},
                               {0.05, 0.15, 0.04, 0.04},
                               {0.40, 0.02, 0.10, 0.12}};
    for (const auto& r : rocks)
      if (std::abs(x - r[0]) < r[2] && std::abs(y - r[1]) < r[2]) return r[3];
    return 0.0;
  };
  Pose3d T_B_C = Pose3d::Identity();
  T_B_C.linear() = rotation_from_rpy(-M_PI / 2 - 30.0 * M_PI / 180.0, 0.08, -M_PI / 2 + 0.35);
  T_B_C.translation() = Eigen::Vector3d(0.0, 0.025, 0.15);
  const Pose3d T_W_B = Pose3d::Identity();
  const Pose3d T_W_C = T_W_B * T_B_C;
  const cv::Mat disparity = render(T_W_C, height).disparity_x16;
  // The published terrain: every cell but a band the cameras never saw.
  DenseGrid h, var, none;
  h.reset(128, 128, 0.01, 0.14, 0.0, 0.0f);
  var.reset(128, 128, 0.01, 0.14, 0.0, 1e-6f);
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 128; ++c) {
      const double x = h.x_of_col(c), y = h.y_of_row(r);
      h.at(r, c) = x > 0.08 && x < 0.11 && y > 0.0 ? std::numeric_limits<float>::quiet_NaN()
                                                   : static_cast<float>(height(x, y));
    }
  KnownTerrain terrain;
  terrain.add_layer(h, var, none, none);
  StereoConfig stereo = test_stereo();
  stereo.max_below_ground_m = 0.0;  // no other drop: every pixel in range reaches the check
  SensorConfig sensor;
  const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(), T_B_C,
                                  cv::Rect(0, 0, kCols, kRows));
  builder.prepare_terrain(terrain, T_W_B);
  ASSERT_GT(terrain.max_unseen_height(), 0.0);
  PointCloud cloud;
  cv::Mat marked = disparity.clone();
  const PointDrops drops = builder.build(disparity, 0, T_W_B, terrain, cloud, nullptr, &marked);
  MapPoints points;
  cv::Mat marked_direct = disparity.clone();
  builder.build_map_points(disparity, 0, T_W_B, terrain, CcmWeighting::constant, points,
                           &marked_direct);

  int blocked = 0, agree = 0, checked = 0;
  for (int v = 0; v < kRows; ++v)
    for (int u = 0; u < kCols; ++u) {
      const int d16 = disparity.at<int16_t>(v, u);
      if (d16 <= 0) continue;
      const Eigen::Vector3d p_C = triangulate(kGeometry, u, v, d16 / 16.0);
      if (!(p_C.z() >= stereo.z_min_m && p_C.z() <= stereo.z_max_m)) continue;
      const Eigen::Vector3d ray = T_W_C.linear() * p_C / p_C.z();
      const RayCheck c{builder.near_depth_m(v),
                       std::min(builder.occlusion_depth_m(v), p_C.z()),
                       stereo.occlusion_margin_m,
                       terrain.finest_resolution_m(),
                       terrain.max_top() - stereo.occlusion_margin_m,
                       terrain.max_unseen_height()};
      const bool want = ray_blocked(terrain, T_W_C.translation(), ray, c);
      const bool got = marked.at<int16_t>(v, u) != d16;
      blocked += want;
      agree += want == got;
      ++checked;
      EXPECT_EQ(got, want) << u << "," << v;
      EXPECT_EQ(marked_direct.at<int16_t>(v, u) != d16, want) << u << "," << v;
    }
  EXPECT_EQ(agree, checked);
  EXPECT_EQ(static_cast<int>(drops.occluded), blocked);
  EXPECT_GT(blocked, 200);             // the check has work to do here
  EXPECT_GT(checked - blocked, 5000);  // and rays it lets through
}

}  // namespace
}  // namespace hazmap
