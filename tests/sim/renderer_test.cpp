// Renderer and sequence simulator: hit points on the surface, exact stereo geometry
// (rectified rows, disparity = f B / Z), shading and noise against closed forms,
// determinism (threads, seeds) and the files of a simulated sequence (SPEC 2).

#include "hazmap/sim/renderer.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"
#include "test_support.hpp"

namespace hazmap::sim {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
constexpr double kSurfaceToleranceM = 1e-4;   // hit point vs height_m
constexpr double kPixelTolerancePx = 1e-6;    // reprojection, rectified rows
constexpr double kRelativeDisparityTolerance = 1e-6;
constexpr double kTestScale = 0.1;            // 160 x 130 px: fast

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

// Relative path -> content of every regular file below `root`.
std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) {
      files[fs::relative(entry.path(), root).string()] = read_file(entry.path());
    }
  }
  return files;
}

SimulationOptions small_options() {
  SimulationOptions options;
  options.scale = kTestScale;
  options.frames = 2;
  options.terrain_size_m = 6.0;
  return options;
}

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
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  const Terrain terrain = make_terrain(terrain_options);
  RenderOptions options;
  options.texture_contrast = 0.0;
  options.sun_shading = false;
  options.noise_sigma_dn = 2.0;
  options.samples_per_axis = 1;
  const Renderer renderer(terrain, options, 1);
  const StereoRig rig = make_cadre_rig(0.2);
  const Pose3d T_W_C = rig.T_B_CL;  // body at the origin
  const cv::Mat image = renderer.render(rig.camera, T_W_C, 42);
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
// Sequence files (SPEC 2)

TEST(SimulateSequence, SameSeedSameBytesOtherSeedOtherImages) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.write_ground_truth = true;
  options.ground_truth_margin_m = 0.3;
  simulate_sequence(options, tmp.path() / "a");
  simulate_sequence(options, tmp.path() / "b");
  const auto a = read_tree(tmp.path() / "a");
  const auto b = read_tree(tmp.path() / "b");
  for (const char* name : {"left/000000.png", "left/000001.png", "right/000001.png",
                           "poses.txt", "calibration.yaml", "gt_height.jdem",
                           "gt_hazard.jdem"}) {
    EXPECT_EQ(a.count(name), 1u) << name;
  }
  EXPECT_TRUE(a == b);

  options.seed = 2;
  simulate_sequence(options, tmp.path() / "c");
  const auto c = read_tree(tmp.path() / "c");
  EXPECT_NE(a.at("left/000000.png"), c.at("left/000000.png"));
  EXPECT_NE(a.at("right/000001.png"), c.at("right/000001.png"));
}

TEST(SimulateSequence, WritesCalibrationPosesAndGroundTruth) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.frames = 3;
  options.write_ground_truth = true;
  options.ground_truth_margin_m = 0.3;
  simulate_sequence(options, tmp.path());

  // calibration.yaml: rectified CADRE pair at scale 0.1.
  const YAML::Node calib = YAML::LoadFile((tmp.path() / "calibration.yaml").string());
  EXPECT_EQ(calib["image_width"].as<int>(), 160);
  EXPECT_EQ(calib["image_height"].as<int>(), 130);
  const std::vector<double> K_expected = {67.1, 0, 79.5, 0, 67.1, 64.5, 0, 0, 1};
  for (const char* side : {"left", "right"}) {
    EXPECT_EQ(calib[side]["K"].as<std::vector<double>>(), K_expected) << side;
    EXPECT_EQ(calib[side]["D"].as<std::vector<double>>(), std::vector<double>(5, 0.0));
  }
  EXPECT_EQ(calib["R"].as<std::vector<double>>(),
            (std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(calib["T"].as<std::vector<double>>(), (std::vector<double>{-0.05, 0, 0}));
  EXPECT_EQ(calib["T_body_left"]["translation"].as<std::vector<double>>(),
            (std::vector<double>{0, 0.025, 0.15}));
  const auto q = calib["T_body_left"]["quaternion"].as<std::vector<double>>();
  ASSERT_EQ(q.size(), 4u);
  const Eigen::Quaterniond q_B_C(q[3], q[0], q[1], q[2]);  // file: qx qy qz qw
  const StereoRig rig = make_cadre_rig(kTestScale);
  EXPECT_TRUE(q_B_C.normalized().toRotationMatrix().isApprox(rig.T_B_CL.linear(), 1e-12));

  // poses.txt: comments, then `name t x y z qx qy qz qw` along +x on the ground.
  const Terrain terrain = make_simulation_terrain(options);
  std::ifstream poses(tmp.path() / "poses.txt");
  std::string line;
  int frame = 0;
  while (std::getline(poses, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string name;
    double t, x, y, z, qx, qy, qz, qw;
    ASSERT_TRUE(fields >> name >> t >> x >> y >> z >> qx >> qy >> qz >> qw) << line;
    char expected_name[8];
    std::snprintf(expected_name, sizeof(expected_name), "%06d", frame);
    EXPECT_EQ(name, expected_name);
    EXPECT_EQ(t, frame);
    EXPECT_NEAR(x, frame * options.step_m, 1e-12);
    EXPECT_EQ(y, 0.0);
    EXPECT_NEAR(z, terrain.ground_height_m(x, 0.0), 1e-11);
    EXPECT_EQ(Eigen::Vector4d(qx, qy, qz, qw), Eigen::Vector4d(0, 0, 0, 1));
    EXPECT_TRUE(fs::exists(tmp.path() / "right" / (name + ".png")));
    const cv::Mat image = cv::imread((tmp.path() / "left" / (name + ".png")).string(),
                                     cv::IMREAD_UNCHANGED);
    EXPECT_EQ(image.type(), CV_8UC1);
    EXPECT_EQ(image.cols, 160);
    EXPECT_EQ(image.rows, 130);
    ++frame;
  }
  EXPECT_EQ(frame, 3);

  // Ground truth: travelled area +- 0.3 m at 1 cm, cell borders on the 1 cm lattice.
  const JdemGrid height = read_jdem(tmp.path() / "gt_height.jdem");
  const JdemGrid hazard = read_jdem(tmp.path() / "gt_hazard.jdem");
  EXPECT_EQ(height.rows, 60);
  EXPECT_EQ(height.cols, 68);  // x from -0.30 to 0.38
  EXPECT_NEAR(height.center_x_m, 0.04, 1e-12);
  EXPECT_NEAR(height.resolution_m, 0.01, 1e-12);
  EXPECT_EQ(hazard.values.size(), height.values.size());
  float max_hazard_m = 0.0f;
  for (float v : hazard.values) max_hazard_m = std::max(max_hazard_m, v);
  double max_rock_m = 0.0;
  for (const Rock& rock : terrain.rocks()) {
    if (rock.x_m - rock.radius_m < 0.38) {
      max_rock_m = std::max(max_rock_m, rock.radius_m - rock.buried_m);
    }
  }
  EXPECT_LE(max_hazard_m, max_rock_m + 0.01);
  EXPECT_GT(max_hazard_m, 0.0f);  // default rocks start 0.25 m ahead: some are in the grid
}

TEST(SimulateSequence, RejectsBadOptions) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.frames = 0;
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  options = small_options();
  options.scenario = "moon";
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  options = small_options();
  options.scale = 0.0;
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
}

}  // namespace
}  // namespace hazmap::sim
