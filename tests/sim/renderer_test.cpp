// Renderer: hit points on the surface, exact stereo geometry (rectified rows,
// disparity = f B / Z), shading and noise against closed forms, determinism across
// threads, and the rock grid against testing every rock.

#include "hazmap/sim/renderer.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"
#include "sim_fixtures.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSurfaceToleranceM = 1e-4;   // hit point vs height_m
constexpr double kPixelTolerancePx = 1e-6;    // reprojection, rectified rows
constexpr double kRelativeDisparityTolerance = 1e-6;
using testing::kTestScale;
using testing::small_options;

// ---------------------------------------------------------------------------------------
// Camera geometry (SPEC 11)

TEST(StereoRig, CadreGeometry) {
  const StereoRig rig = make_cadre_rig(1.0);
  EXPECT_EQ(rig.camera.width_px, 1600);
  EXPECT_EQ(rig.camera.height_px, 1300);
  EXPECT_EQ(rig.camera.fx_px, 671.0);
  EXPECT_EQ(rig.camera.cx_px, 799.5);
  EXPECT_EQ(rig.camera.cy_px, 649.5);
  EXPECT_EQ(rig.baseline_m, 0.05);

  const Eigen::Matrix3d R_B_C = rig.T_B_CL.linear();
  // Top edge of the image (v = -0.5) looks 10 deg above the horizon.
  const Eigen::Vector3d top_B = R_B_C * rig.camera.ray_C(rig.camera.cx_px, -0.5);
  EXPECT_NEAR(std::atan2(top_B.z(), std::hypot(top_B.x(), top_B.y())), 10.0 * kPi / 180.0,
              1e-9);
  // Optical axis forward and pitched down by half_vfov - 10 deg; image x = body -y.
  const double pitch_rad = std::atan(650.0 / 671.0) - 10.0 * kPi / 180.0;
  EXPECT_TRUE((R_B_C * Eigen::Vector3d::UnitZ())
                  .isApprox(Eigen::Vector3d(std::cos(pitch_rad), 0.0, -std::sin(pitch_rad)), 1e-9));
  EXPECT_TRUE((R_B_C * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-9));
  // The pair straddles the body centre, 15 cm above the ground.
  EXPECT_TRUE(rig.T_B_CL.translation().isApprox(Eigen::Vector3d(0.0, 0.025, 0.15)));
  EXPECT_TRUE(rig.T_B_CR().translation().isApprox(Eigen::Vector3d(0.0, -0.025, 0.15)));

  const StereoRig small = make_cadre_rig(0.4);
  EXPECT_EQ(small.camera.width_px, 640);
  EXPECT_EQ(small.camera.height_px, 520);
  EXPECT_DOUBLE_EQ(small.camera.fx_px, 268.4);
}

// ---------------------------------------------------------------------------------------
// Ray casting: hits on the surface and the stereo round trip

class RenderGeometry : public ::testing::Test {
 protected:
  RenderGeometry()
      : options_(small_options()),
        terrain_(make_simulation_terrain(options_)),
        rig_(make_cadre_rig(kTestScale)),
        T_W_B_(simulation_path(options_, terrain_)[0]),
        T_W_CL_(T_W_B_ * rig_.T_B_CL),
        T_W_CR_(T_W_B_ * rig_.T_B_CR()) {}

  // A grid of pixels plus the pixel over each rock's top, so rocks are always tested.
  std::vector<Eigen::Vector2d> test_pixels() const {
    std::vector<Eigen::Vector2d> pixels;
    for (double u : {5.0, 40.0, 79.5, 120.25, 155.0}) {
      for (double v : {22.0, 30.0, 45.5, 70.0, 100.0, 129.0}) pixels.emplace_back(u, v);
    }
    for (std::size_t i = 0; i < terrain_.rocks().size(); ++i) {
      const Rock& rock = terrain_.rocks()[i];
      const Eigen::Vector3d top_W(rock.x_m, rock.y_m, terrain_.height_m(rock.x_m, rock.y_m));
      const Eigen::Vector2d uv = rig_.camera.project(T_W_CL_.inverse() * top_W);
      if (uv.x() > 0 && uv.x() < rig_.camera.width_px - 1 && uv.y() > 0 &&
          uv.y() < rig_.camera.height_px - 1) {
        pixels.push_back(uv);
      }
    }
    return pixels;
  }

  SimulationOptions options_;
  Terrain terrain_;
  StereoRig rig_;
  Pose3d T_W_B_;
  Pose3d T_W_CL_;
  Pose3d T_W_CR_;
};

TEST_F(RenderGeometry, HitPointsLieOnTheSurface) {
  int rock_hits = 0;
  for (const Eigen::Vector2d& uv : test_pixels()) {
    const Eigen::Vector3d d_W = T_W_CL_.linear() * rig_.camera.ray_C(uv.x(), uv.y());
    const auto hit = cast_ray(terrain_, T_W_CL_.translation(), d_W);
    ASSERT_TRUE(hit) << "pixel " << uv.transpose() << " sees the sky";
    const Eigen::Vector3d& p = hit->p_W;
    EXPECT_LT(std::abs(p.z() - terrain_.height_m(p.x(), p.y())), kSurfaceToleranceM)
        << "pixel " << uv.transpose();
    EXPECT_NEAR(hit->normal_W.norm(), 1.0, 1e-12);
    rock_hits += hit->rock_index >= 0;
  }
  EXPECT_GE(rock_hits, 1);
}

TEST_F(RenderGeometry, StereoRoundTripGivesDisparityFBOverZ) {
  const double f_px = rig_.camera.fx_px;
  int same_point_from_right = 0;
  int tested = 0;
  for (const Eigen::Vector2d& uv : test_pixels()) {
    const Eigen::Vector3d d_W = T_W_CL_.linear() * rig_.camera.ray_C(uv.x(), uv.y());
    const auto hit = cast_ray(terrain_, T_W_CL_.translation(), d_W);
    ASSERT_TRUE(hit);
    const Eigen::Vector3d p_CL = T_W_CL_.inverse() * hit->p_W;
    const Eigen::Vector3d p_CR = T_W_CR_.inverse() * hit->p_W;
    const Eigen::Vector2d uv_left = rig_.camera.project(p_CL);
    const Eigen::Vector2d uv_right = rig_.camera.project(p_CR);
    EXPECT_NEAR(uv_left.x(), uv.x(), kPixelTolerancePx);
    EXPECT_NEAR(uv_left.y(), uv.y(), kPixelTolerancePx);
    EXPECT_NEAR(uv_right.y(), uv.y(), kPixelTolerancePx) << "rows must match (rectified)";
    const double disparity_px = uv_left.x() - uv_right.x();
    const double expected_px = f_px * rig_.baseline_m / p_CL.z();
    EXPECT_NEAR(disparity_px / expected_px, 1.0, kRelativeDisparityTolerance);

    // The right camera sees the same point through its pixel, unless something occludes it.
    const Eigen::Vector3d d_right_W =
        T_W_CR_.linear() * rig_.camera.ray_C(uv_right.x(), uv_right.y());
    const auto hit_right = cast_ray(terrain_, T_W_CR_.translation(), d_right_W);
    ++tested;
    if (hit_right && (hit_right->p_W - hit->p_W).norm() < 1e-3) ++same_point_from_right;
  }
  EXPECT_GE(same_point_from_right, tested * 9 / 10);
}

TEST_F(RenderGeometry, DepthImageMatchesRayCasts) {
  const Renderer renderer(terrain_, options_.render, 1);
  const cv::Mat depth = renderer.render_depth(rig_.camera, T_W_CL_);
  ASSERT_EQ(depth.type(), CV_32FC1);
  EXPECT_TRUE(std::isnan(depth.at<float>(0, 80)));  // sky above the horizon
  for (int v : {40, 80, 129}) {
    for (int u : {0, 80, 159}) {
      const auto hit = cast_ray(terrain_, T_W_CL_.translation(),
                                T_W_CL_.linear() * rig_.camera.ray_C(u, v));
      ASSERT_TRUE(hit);
      const double z_m = (T_W_CL_.inverse() * hit->p_W).z();
      EXPECT_NEAR(depth.at<float>(v, u), z_m, 1e-6 * z_m);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Radiance: closed forms

TEST(Renderer, LambertShadingAndRockShadow) {
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  terrain_options.extra_rocks = {{1.0, 0.0, 0.1, 0.0}};
  const Terrain terrain = make_terrain(terrain_options);
  RenderOptions options;
  options.texture_contrast = 0.0;  // albedo = its mean everywhere
  const Renderer renderer(terrain, options, 1);

  const double el = options.sun_elevation_deg * kPi / 180.0;
  const double az = options.sun_azimuth_deg * kPi / 180.0;
  const Eigen::Vector3d sun_W(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
  const double flat = options.ambient + (1.0 - options.ambient) * std::sin(el);

  RayHit ground;  // open ground in full sun: exposure * albedo
  ground.p_W = Eigen::Vector3d(3.0, 2.0, 0.0);
  ground.normal_W = Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(renderer.radiance(ground, 1e-3), options.exposure_dn * options.ground_albedo, 1e-9);

  RayHit lit;  // rock point facing the sun
  lit.rock_index = 0;
  lit.normal_W = sun_W;
  lit.p_W = terrain.rock_center_W(0) + 0.1 * sun_W;
  EXPECT_NEAR(renderer.radiance(lit, 1e-3), options.exposure_dn * options.rock_albedo / flat,
              1e-9);

  RayHit shadowed = ground;  // ground just down-sun of the rock: ambient only
  shadowed.p_W = Eigen::Vector3d(1.0 - 0.12 * std::cos(az), -0.12 * std::sin(az), 0.0);
  EXPECT_NEAR(renderer.radiance(shadowed, 1e-3),
              options.exposure_dn * options.ground_albedo * options.ambient / flat, 1e-9);
}

TEST(Renderer, ImageNoiseHasTheRequestedSigma) {
  const testing::UniformFlatScene scene(2.0, 1);
  const RenderOptions& options = scene.options;
  const StereoRig rig = make_cadre_rig(0.2);
  const Pose3d T_W_C = rig.T_B_CL;  // body at the origin
  const cv::Mat image = scene.renderer.render(rig.camera, T_W_C, 42);
  ASSERT_EQ(image.type(), CV_8UC1);
  // Rows well below the horizon see flat ground of radiance exposure * albedo = 100 DN.
  cv::Scalar mean, stddev;
  cv::meanStdDev(image.rowRange(100, image.rows), mean, stddev);
  EXPECT_NEAR(mean[0], options.exposure_dn * options.ground_albedo, 0.05);
  EXPECT_NEAR(stddev[0], 2.0, 0.05);
  EXPECT_LT(cv::mean(image.row(0))[0], 2.0);  // sky is black (plus clipped noise)
}

TEST(Renderer, ImageIsIndependentOfThreadCount) {
  const SimulationOptions options = small_options();
  const Terrain terrain = make_simulation_terrain(options);
  const StereoRig rig = make_cadre_rig(kTestScale);
  const Renderer renderer(terrain, options.render, 5);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const cv::Mat one = renderer.render(rig.camera, rig.T_B_CL, 9);
  cv::setNumThreads(4);
  const cv::Mat four = renderer.render(rig.camera, rig.T_B_CL, 9);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::norm(one, four, cv::NORM_INF), 0.0);
  // Textured ground below the horizon (block matching needs contrast).
  cv::Scalar mean, stddev;
  cv::meanStdDev(one.rowRange(40, one.rows), mean, stddev);
  EXPECT_GT(stddev[0], 20.0);
}

// ---------------------------------------------------------------------------------------
// Many rocks: the rock grid finds the same hits as testing every rock

// Nearest hit of a ray from above flat ground z = 0 among rocks (spheres whose visible
// part is above z = 0) and the ground, by brute force. Returns t, and the rock or -1.
std::pair<double, int> brute_force_hit(const Terrain& terrain, const Eigen::Vector3d& o,
                                       const Eigen::Vector3d& d) {
  double t_best = d.z() < 0.0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
  int best = -1;
  for (std::size_t i = 0; i < terrain.rocks().size(); ++i) {
    const Eigen::Vector3d oc = o - terrain.rock_center_W(i);
    const double r = terrain.rocks()[i].radius_m;
    const double b = oc.dot(d);
    const double disc = b * b - (oc.squaredNorm() - r * r);
    if (disc < 0.0) continue;
    const double t = -b - std::sqrt(disc);
    if (t <= 0.0 || t >= t_best || (o + t * d).z() < 0.0) continue;
    t_best = t;
    best = static_cast<int>(i);
  }
  return {t_best, best};
}

TEST(Renderer, RockGridGivesTheHitsOfTestingEveryRock) {
  TerrainOptions options;
  options.scenario = "flat";
  options.scatter_rocks = true;
  options.rock_field.density_per_m2 = 20.0;  // 320 rocks in 4 m x 4 m
  options.rock_field.min_x_m = -1.0;
  options.rock_field.max_x_m = 3.0;
  options.rock_field.max_abs_y_m = 2.0;
  options.rock_field.min_gap_m = 0.0;
  const Terrain terrain = make_terrain(options);
  ASSERT_EQ(terrain.rocks().size(), 320u);
  std::mt19937_64 rng(3);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit_double(rng()); };
  int rock_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d o(uniform(-1.5, 3.5), uniform(-2.5, 2.5), uniform(0.1, 0.3));
    const Eigen::Vector3d d =
        Eigen::Vector3d(uniform(-1, 1), uniform(-1, 1), uniform(-0.5, 0.05)).normalized();
    const auto [t_expected, rock_expected] = brute_force_hit(terrain, o, d);
    const auto hit = cast_ray(terrain, o, d);
    if (!std::isfinite(t_expected) || t_expected > RayCastOptions().max_range_m) {
      EXPECT_FALSE(hit);
      continue;
    }
    ASSERT_TRUE(hit) << "ray " << i;
    const Eigen::Vector3d p_expected = o + t_expected * d;
    if (hit->rock_index != rock_expected) {
      // Only where a rock meets the ground can the march's tolerance decide the other way.
      EXPECT_LT(p_expected.z(), kSurfaceToleranceM) << "ray " << i;
      continue;
    }
    // Rocks are exact; the ground is found to |z| < 1e-5 m, i.e. t to 1e-5 / |d_z|.
    const double tolerance_m = rock_expected >= 0 ? 1e-9 : 1e-5 / std::abs(d.z()) + 1e-9;
    ASSERT_NEAR(hit->range_m, t_expected, tolerance_m) << "ray " << i;
    rock_hits += rock_expected >= 0;
  }
  EXPECT_GT(rock_hits, 2000);
}

}  // namespace
}  // namespace hazmap::sim
