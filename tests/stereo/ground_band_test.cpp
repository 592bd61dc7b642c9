// The disparity intervals of ground-band matching (SPEC 3.4) against independent
// computations: the simulator's ray-cast depth of level ground, brute-force marching
// along each ray through the terrain envelope, and random terrain points projected
// through the camera.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/sim/renderer.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"
#include "hazmap/stereo/ground_band.hpp"

namespace hazmap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

StereoGeometry geometry_of(const sim::StereoRig& rig) {
  return {rig.camera.fx_px, rig.baseline_m, rig.camera.cx_px, rig.camera.cy_px};
}

// Level ground (no slope, height or depth): each row's interval is exactly the range of
// f B / Z over the row, Z the depth the simulator's ray caster finds on flat terrain
// under the body (the rig is the ideal rectified CADRE pair, so C' = C).
TEST(GroundBand, LevelGroundIsTheRenderedGroundDisparity) {
  const sim::StereoRig rig = sim::make_cadre_rig(0.2);
  sim::TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  const sim::Terrain terrain = sim::make_terrain(terrain_options);
  sim::RenderOptions far;  // rows just below the horizon see the plane kilometres away
  far.ray_cast.max_range_m = 1e5;
  const sim::Renderer renderer(terrain, far, 1);
  const cv::Mat depth = renderer.render_depth(rig.camera, rig.T_B_CL);  // body = world
  TerrainEnvelope level;
  level.max_slope_deg = level.max_height_m = level.max_depth_m = 0.0;
  const double fb = rig.camera.fx_px * rig.baseline_m;
  const GroundBand band(geometry_of(rig), rig.T_B_CL, level, 1e6);
  int ground_rows = 0, sky_rows = 0;
  for (int v = 0; v < depth.rows; ++v) {
    DisparityInterval truth;
    for (int u = 0; u < depth.cols; ++u) {
      const float z = depth.at<float>(v, u);
      if (std::isfinite(z)) truth.include({fb / z, fb / z});
    }
    const DisparityInterval got = band.row(v, depth.cols);
    if (truth.empty()) {  // above the horizon
      ++sky_rows;
      EXPECT_TRUE(got.empty()) << "row " << v;
      continue;
    }
    ++ground_rows;
    ASSERT_FALSE(got.empty()) << "row " << v;
    EXPECT_NEAR(got.lo, truth.lo, 1e-4 * truth.lo + 1e-6) << "row " << v;
    EXPECT_NEAR(got.hi, truth.hi, 1e-4 * truth.hi + 1e-6) << "row " << v;
  }
  EXPECT_GT(ground_rows, depth.rows / 2);
  EXPECT_GT(sky_rows, 0);
}

// A general mount (rolled, pitched, yawed, offset, above max_height) and an envelope with
// every term non-zero: march each sampled ray in fine geometric steps, test every sample
// against the envelope directly, and compare the disparities of the first and last
// samples inside with the closed form.
TEST(GroundBand, IntervalsMatchBruteForceMarchingAlongTheRays) {
  const StereoGeometry g{300.0, 0.07, 159.5, 119.5};
  const cv::Size size(320, 240);
  Pose3d T_B_C = Pose3d::Identity();
  Eigen::Matrix3d R_B_C0;  // camera z -> body x, x -> -y, y -> -z
  R_B_C0 << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  // Pitched down 7 deg: the view spans 15 deg above to 29 deg below the horizon.
  T_B_C.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                   Eigen::AngleAxisd(0.12, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                   Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix() * R_B_C0;
  T_B_C.translation() = Eigen::Vector3d(0.12, -0.04, 0.32);
  TerrainEnvelope env;
  env.max_slope_deg = 8.0;
  env.max_height_m = 0.08;
  env.max_depth_m = 0.3;
  const double cap = 1e6;  // no cap: the camera is above max_height
  const GroundBand band(g, T_B_C, env, cap);
  const double fb = g.focal_px * g.baseline_m, tan_slope = std::tan(env.max_slope_deg * kDegToRad);
  const Eigen::Vector3d c = T_B_C.translation();
  auto inside = [&](const Eigen::Vector3d& p) {
    const double rho = std::hypot(p.x() - c.x(), p.y() - c.y());
    return p.z() <= env.max_height_m + tan_slope * rho &&
           p.z() >= -env.max_depth_m - tan_slope * rho;
  };
  constexpr double kZMin = 1e-3, kZMax = 1e3;
  constexpr int kSteps = 40000;
  const double ratio = std::pow(kZMax / kZMin, 1.0 / kSteps);  // 1.00035
  int bounded = 0, unbounded = 0, empty = 0;
  for (int v = 0; v < size.height; v += 17) {
    for (int u = 0; u < size.width; u += 29) {
      const Eigen::Vector3d r = T_B_C.linear() * Eigen::Vector3d((u - g.cx_px) / g.focal_px,
                                                                 (v - g.cy_px) / g.focal_px, 1);
      double z_first = 0, z_last = 0;
      bool any = false;
      for (double z = kZMin; z <= kZMax; z *= ratio) {
        if (!inside(c + z * r)) continue;
        if (!any) z_first = z;
        z_last = z;
        any = true;
      }
      const DisparityInterval got = band.pixel(u, v);
      if (!any) {
        EXPECT_TRUE(got.empty()) << u << " " << v;
        ++empty;
        continue;
      }
      ASSERT_FALSE(got.empty()) << u << " " << v;
      // One step of the march is a relative error of ratio - 1 in Z and so in d.
      EXPECT_NEAR(got.hi, fb / z_first, 2 * (ratio - 1) * fb / z_first) << u << " " << v;
      if (z_last * ratio > kZMax) {
        ++unbounded;  // inside up to the march's end: no far limit, d reaches 0
        EXPECT_EQ(got.lo, 0.0) << u << " " << v;
      } else {
        ++bounded;
        EXPECT_NEAR(got.lo, fb / z_last, 2 * (ratio - 1) * fb / z_last) << u << " " << v;
      }
    }
  }
  // The sample reaches every case: rays that leave the envelope, that stay in it to the
  // horizon, and (upwards) that never meet it.
  EXPECT_GT(bounded, 20);
  EXPECT_GT(unbounded, 5);
  EXPECT_GT(empty, 0);
}

// Soundness from the other side: random terrain points of the envelope (ahead of the
// camera), projected through the camera, have a disparity inside the interval of the
// ray they lie on.
TEST(GroundBand, SampledTerrainPointsLieInsideTheirRaysInterval) {
  const sim::StereoRig rig = sim::make_cadre_rig(0.4);
  const StereoGeometry g = geometry_of(rig);
  TerrainEnvelope env;
  env.max_slope_deg = 15.0;
  env.max_height_m = 0.1;  // below the camera (0.15 m)
  env.max_depth_m = 0.4;
  const GroundBand band(g, rig.T_B_CL, env, 1e6);
  const Pose3d T_C_B = rig.T_B_CL.inverse();
  const Eigen::Vector3d c = rig.T_B_CL.translation();
  const double fb = g.focal_px * g.baseline_m, tan_slope = std::tan(env.max_slope_deg * kDegToRad);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(0.0, 4.0), y(-3.0, 3.0), unit(0.0, 1.0);
  int projected = 0;
  for (int i = 0; i < 200000; ++i) {
    const Eigen::Vector3d xy(c.x() + x(rng), c.y() + y(rng), 0.0);
    const double rho = std::hypot(xy.x() - c.x(), xy.y() - c.y());
    const double lo = -env.max_depth_m - tan_slope * rho, hi = env.max_height_m + tan_slope * rho;
    const Eigen::Vector3d p_B(xy.x(), xy.y(), lo + (hi - lo) * unit(rng));
    const Eigen::Vector3d p_C = T_C_B * p_B;
    if (p_C.z() <= 0) continue;
    const double u = g.focal_px * p_C.x() / p_C.z() + g.cx_px;
    const double v = g.focal_px * p_C.y() / p_C.z() + g.cy_px;
    if (u < 0 || v < 0 || u > rig.camera.width_px - 1 || v > rig.camera.height_px - 1) continue;
    ++projected;
    const double d = fb / p_C.z();
    const DisparityInterval got = band.pixel(u, v);
    ASSERT_FALSE(got.empty());
    EXPECT_GE(d, got.lo * (1 - 1e-9)) << u << " " << v;
    EXPECT_LE(d, got.hi * (1 + 1e-9)) << u << " " << v;
  }
  EXPECT_GT(projected, 20000);
}

// SPEC 3.4 on the CADRE mount with the default envelope: rows above the horizon reach
// disparity 0; with obstacles allowed taller than the camera is high (0.5 m > 0.15 m)
// every ray starts inside the envelope, so every interval runs up to the cap.
TEST(GroundBand, HorizonAndCapOnTheCadreMount) {
  const sim::StereoRig rig = sim::make_cadre_rig(0.4);
  const StereoGeometry g = geometry_of(rig);
  const GroundBand band(g, rig.T_B_CL, TerrainEnvelope(), 272.0);
  const std::vector<DisparityInterval> rows =
      band.rows({rig.camera.width_px, rig.camera.height_px});
  // The top edge looks 10 deg above the horizon: row 0 sees only far terrain and near
  // obstacles.
  EXPECT_EQ(rows.front().lo, 0.0);
  for (const DisparityInterval& r : rows) {
    ASSERT_FALSE(r.empty());
    EXPECT_EQ(r.hi, 272.0);
  }
  // Obstacles lower than the camera: the top rows no longer reach the cap.
  TerrainEnvelope low;
  low.max_slope_deg = 10.0;
  low.max_height_m = 0.05;
  low.max_depth_m = 0.2;
  const GroundBand tight(g, rig.T_B_CL, low, 272.0);
  EXPECT_EQ(tight.row(0, rig.camera.width_px).lo, 0.0);
  EXPECT_LT(tight.row(0, rig.camera.width_px).hi, 100.0);
  // The bottom row sees level ground at d = 122 px (cadre_flight.yaml): inside its band.
  const DisparityInterval bottom = tight.row(rig.camera.height_px - 1, rig.camera.width_px);
  EXPECT_LT(bottom.lo, 120.0);
  EXPECT_GT(bottom.hi, 125.0);
}

TEST(GroundBand, RejectsUnusableGeometry) {
  const StereoGeometry g{300.0, 0.07, 159.5, 119.5};
  TerrainEnvelope steep;
  steep.max_slope_deg = 90.0;
  EXPECT_THROW(GroundBand(g, Pose3d::Identity(), steep, 100.0), Error);
  EXPECT_THROW(GroundBand(g, Pose3d::Identity(), TerrainEnvelope(), 0.0), Error);
  EXPECT_THROW(
      GroundBand(StereoGeometry{300.0, 0.0, 0, 0}, Pose3d::Identity(), TerrainEnvelope(), 64.0),
      Error);
}

}  // namespace
}  // namespace hazmap
