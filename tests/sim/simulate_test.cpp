// The sequence simulator (`hazmap simulate`): the files of a sequence (SPEC 2), seeded
// determinism, drifted and true poses, and the calibration of distorted and misaligned
// rigs.

#include "hazmap/sim/simulate.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/sequence.hpp"
#include "sim_fixtures.hpp"
#include "test_support.hpp"

namespace hazmap::sim {
namespace {

namespace fs = std::filesystem;

using testing::kTestScale;
using testing::small_options;
constexpr double kWrittenM = 1e-11;  // values rounded to 12 significant digits

// Relative path -> content of every regular file below `root`.
std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) {
      files[fs::relative(entry.path(), root).string()] = testing::read_text(entry.path());
    }
  }
  return files;
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
    // Standing on the plane through the ground under the wheels (rover_pose.hpp).
    PathPoint point;
    point.p_W = Eigen::Vector2d(x, y);
    const Pose3d T_W_B = pose_on_ground(terrain, point, options.wheels);
    EXPECT_NEAR(z, T_W_B.translation().z(), 1e-11);
    const Eigen::Quaterniond q_W_B(qw, qx, qy, qz);
    EXPECT_TRUE(q_W_B.normalized().toRotationMatrix().isApprox(T_W_B.linear(), 1e-11));
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
  options = small_options();
  options.path.kind = "zigzag";
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  options = small_options();
  options.drift.fraction = -0.1;
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  options = small_options();
  options.wheels.track_m = 0.0;
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  options = small_options();
  options.rig_errors.misalignment_rpy_deg.x() = 45.0;
  EXPECT_THROW(simulate_sequence(options, tmp.path()), Error);
  EXPECT_FALSE(fs::exists(tmp.path() / "poses.txt"));  // nothing written before the check
}

TEST(SimulateSequence, EveryFeatureIsDeterministic) {
  // Spline path, drift, craters with scattered rocks, distortion, misalignment, depth and
  // ground truth: the same seed gives the same bytes.
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.scenario = "craters";
  options.scatter_rocks = true;
  options.path.kind = "spline";
  options.frames = 3;
  options.drift.fraction = 0.1;
  options.rig_errors.distortion = RigErrors::typical_distortion();
  options.rig_errors.misalignment_rpy_deg = RigErrors::typical_misalignment_rpy_deg();
  options.rig_errors.misalignment_m = RigErrors::typical_misalignment_m();
  options.write_depth = true;
  options.write_ground_truth = true;
  options.ground_truth_margin_m = 0.3;
  simulate_sequence(options, tmp.path() / "a");
  simulate_sequence(options, tmp.path() / "b");
  const auto a = read_tree(tmp.path() / "a");
  for (const char* name : {"left/000002.png", "right/000002.png", "depth/000002.tiff",
                           "poses.txt", "poses_true.txt", "calibration.yaml", "simulation.yaml",
                           "gt_height.jdem", "gt_hazard.jdem"}) {
    EXPECT_EQ(a.count(name), 1u) << name;
  }
  EXPECT_TRUE(a == read_tree(tmp.path() / "b"));
}

// Pose lines (name -> T_W_B and noise) via the project's own reader.
std::vector<std::pair<std::string, FramePose>> read_poses(const fs::path& path) {
  return parse_poses(testing::read_text(path), path.string());
}

TEST(SimulateSequence, DriftedPosesAreOffByTheFractionOfDistanceTravelled) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.scale = 0.05;  // images do not matter here
  options.frames = 6;
  options.path.kind = "spline";
  options.drift.fraction = 0.1;
  options.drift.direction_deg = 30.0;
  simulate_sequence(options, tmp.path());
  const auto drifted = read_poses(tmp.path() / "poses.txt");
  const auto truth = read_poses(tmp.path() / "poses_true.txt");
  ASSERT_EQ(drifted.size(), 6u);
  ASSERT_EQ(truth.size(), 6u);
  const Eigen::Vector3d direction(std::cos(M_PI / 6), std::sin(M_PI / 6), 0.0);
  for (std::size_t k = 0; k < drifted.size(); ++k) {
    EXPECT_EQ(drifted[k].first, truth[k].first);
    const Pose3d& T_d = drifted[k].second.T_W_B;
    const Pose3d& T_t = truth[k].second.T_W_B;
    // Error = fraction x arc length travelled (k steps), along the requested direction.
    const Eigen::Vector3d error = T_d.translation() - T_t.translation();
    const double travelled_m = 0.04 * static_cast<double>(k);
    EXPECT_NEAR(error.norm(), 0.1 * travelled_m, kWrittenM) << k;
    EXPECT_NEAR((error - 0.1 * travelled_m * direction).norm(), 0.0, kWrittenM) << k;
    EXPECT_TRUE(T_d.linear().isApprox(T_t.linear(), 1e-14));
    // Noise columns: the drift added since the previous frame.
    ASSERT_TRUE(drifted[k].second.has_noise);
    EXPECT_FALSE(truth[k].second.has_noise);
    EXPECT_NEAR(drifted[k].second.noise.sx_m, k == 0 ? 0.0 : 0.004, 1e-15);
    EXPECT_NEAR(drifted[k].second.noise.sy_m, k == 0 ? 0.0 : 0.004, 1e-15);
  }
  const YAML::Node sim = YAML::LoadFile((tmp.path() / "simulation.yaml").string());
  EXPECT_EQ(sim["poses"].as<std::string>(), "poses.txt");
  EXPECT_EQ(sim["poses_true"].as<std::string>(), "poses_true.txt");
  EXPECT_EQ(sim["drift"]["fraction"].as<double>(), 0.1);
  EXPECT_EQ(sim["drift"]["direction_deg"].as<double>(), 30.0);

  // Without drift there is one pose file and it is the truth.
  options.drift.fraction = 0.0;
  testing::TempDir plain;
  simulate_sequence(options, plain.path());
  EXPECT_FALSE(fs::exists(plain.path() / "poses_true.txt"));
  EXPECT_EQ(YAML::LoadFile((plain.path() / "simulation.yaml").string())["poses_true"].as<std::string>(),
            "poses.txt");
  const auto plain_poses = read_poses(plain.path() / "poses.txt");
  for (std::size_t k = 0; k < plain_poses.size(); ++k) {
    EXPECT_TRUE(plain_poses[k].second.T_W_B.isApprox(truth[k].second.T_W_B, 1e-12));
  }
}

TEST(SimulateSequence, DistortedMisalignedRigWritesItsTrueCalibration) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.frames = 1;
  options.rig_errors.distortion = RigErrors::typical_distortion();
  options.rig_errors.misalignment_rpy_deg = RigErrors::typical_misalignment_rpy_deg();
  options.rig_errors.misalignment_m = RigErrors::typical_misalignment_m();
  simulate_sequence(options, tmp.path());
  // Read back with the project's reader: not rectified, true K, D, R, T.
  const StereoCalibration calib = load_stereo_calibration(tmp.path() / "calibration.yaml");
  const StereoRig rig = make_cadre_rig(kTestScale, options.rig_errors);
  EXPECT_FALSE(rig.rectified());
  EXPECT_FALSE(calib.rectified);
  EXPECT_EQ(calib.left.D, std::vector<double>({-0.08, 0.012, 4e-4, -3e-4, 0.0}));
  EXPECT_EQ(calib.right.D, calib.left.D);
  EXPECT_EQ(calib.left.K(0, 0), rig.camera.fx_px);
  // x_right = R x_left + T is the inverse of the right camera's pose in the left frame.
  const Pose3d T_CR_CL = rig.T_CL_CR.inverse();
  EXPECT_TRUE(calib.R.isApprox(T_CR_CL.linear(), 1e-11));
  EXPECT_TRUE(calib.T.isApprox(T_CR_CL.translation(), 1e-10));
  EXPECT_NEAR(calib.T.norm(), std::hypot(0.0505, 0.0003, 0.0004), 1e-12);
  // The right camera is rotated by the requested angles.
  const Eigen::Matrix3d R_expected = rotation_from_rpy(0.3 * M_PI / 180, -0.2 * M_PI / 180,
                                                       0.4 * M_PI / 180);
  EXPECT_TRUE(rig.T_CL_CR.linear().isApprox(R_expected, 1e-14));
  EXPECT_TRUE(calib.T_B_C.isApprox(rig.T_B_CL, 1e-11));

  // The ideal rig stays rectified.
  EXPECT_TRUE(make_cadre_rig(kTestScale).rectified());
}

TEST(SimulateSequence, DepthImagesHoldTheTrueDepth) {
  testing::TempDir tmp;
  SimulationOptions options = small_options();
  options.scenario = "flat";
  options.frames = 1;
  options.write_depth = true;
  simulate_sequence(options, tmp.path());
  const cv::Mat depth = cv::imread((tmp.path() / "depth/000000.tiff").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_32FC1);
  ASSERT_EQ(depth.cols, 160);
  EXPECT_TRUE(std::isnan(depth.at<float>(0, 80)));  // sky
  // Flat ground, body level at z = 0: the ray through pixel (u, v) meets z = 0 at depth
  // Z = -h / (R_W_C ray)_z with h the camera height. Tolerance: the ray caster's 1e-5 m
  // surface tolerance along the ray, plus float rounding.
  const StereoRig rig = make_cadre_rig(kTestScale);
  for (int v : {60, 90, 129}) {
    for (int u : {0, 80, 159}) {
      const Eigen::Vector3d ray_W = rig.T_B_CL.linear() * rig.camera.ray_C(u, v);
      const double z_expected = -rig.T_B_CL.translation().z() / ray_W.z();
      const double tolerance_m = 1e-5 / std::abs(ray_W.normalized().z()) + 1e-6 * z_expected;
      EXPECT_NEAR(depth.at<float>(v, u), z_expected, tolerance_m) << u << " " << v;
    }
  }
}

}  // namespace
}  // namespace hazmap::sim
