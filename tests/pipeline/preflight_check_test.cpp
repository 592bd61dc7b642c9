// hazmap check (preflight_check): its measurements against what a rendered scene is known
// to be (flat ground under the wheels, the camera mounted at T_body_left), against the
// matcher's own disparities, and against real chessboards; and its verdict lines for the
// mistakes it exists to catch.

#include <cmath>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/camera/chessboard_calibration.hpp"
#include "hazmap/io/chessboard_pairs.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/euroc.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/preflight_check.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const std::string& p : problems)
    if (p.find(text) != std::string::npos) return true;
  return false;
}

/// Flat ground (z = 0 in W, the wheels on it), 2 frames at the sample's 0.4 scale.
class FlatScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    sim::SimulationOptions o;
    o.scenario = "flat";
    o.seed = 4242;
    o.frames = 2;
    o.scale = 0.4;
    o.png_compression = 1;
    sim::simulate_sequence(o, dir_->path());
  }
  static void TearDownTestSuite() { delete dir_; }
  static Config config(const std::vector<std::string>& sets = {}) {
    return load_config(testing::source_dir() / "config/default.yaml", sets);
  }
  static TempDir* dir_;
};
TempDir* FlatScene::dir_ = nullptr;

TEST_F(FlatScene, MeasuresTheMountAndALevelGround) {
  const Sequence seq = load_sequence(dir_->path());
  const PreflightReport r = preflight_check(config(), seq, {});
  ASSERT_EQ(r.frames.size(), 2u);
  EXPECT_TRUE(r.problems.empty()) << r.problems.front();
  EXPECT_FALSE(r.calibration.rows.found);  // no chessboard in a rendered field
  for (const FrameCheck& f : r.frames) {
    ASSERT_TRUE(f.ground.found);
    EXPECT_GT(f.ground.inlier_share, 0.9);
    EXPECT_LT(f.tilt_w_deg, 0.3);
    EXPECT_LT(f.tilt_body_deg, 0.3);
    // The camera sits T_body_left's z above the wheels, the wheels on the ground: 5 mm.
    EXPECT_NEAR(f.camera_height_m, seq.calibration.T_B_C.translation().z(), 0.005);
    EXPECT_NEAR(f.body_height_m, 0.0, 0.005);
    EXPECT_GT(f.valid_disparity_share, 0.3);
    EXPECT_EQ(f.points_below_ground, 0u);
    ASSERT_EQ(f.layer_share.size(), 1u);
    EXPECT_GT(f.layer_share[0], 0.5);
  }
  const std::string text = format_report(r);
  EXPECT_NE(text.find("verdict: OK"), std::string::npos) << text;
}

TEST_F(FlatScene, NearestGroundMatchesTheMatchersDisparities) {
  // The disparity the check predicts for the lowest valid row, against the largest the
  // matcher found on the bottom rows of the same frame: 1 px (a full search of 160).
  const Sequence seq = load_sequence(dir_->path());
  PreflightOptions o;
  o.max_frames = 1;
  const PreflightReport r = preflight_check(config(), seq, o);
  ASSERT_EQ(r.frames.size(), 1u);
  const double predicted = r.frames[0].nearest_ground_disparity_px;
  ASSERT_TRUE(std::isfinite(predicted));
  ASSERT_LT(predicted, r.search_num_disparities);

  const Config c = config();
  StereoFrontEnd front(c.stereo, c.sensor, seq.calibration, false);
  front.process(read_image(seq.frames[0].left_path), read_image(seq.frames[0].right_path),
                seq.frames[0].pose.T_W_B);
  const cv::Rect region = front.builder().region();
  double seen = 0;
  // The lowest rows a block can be matched on: the block's half-height above the edge.
  const int bottom = region.y + region.height - 1 - c.stereo.block_size / 2;
  const cv::Mat row = front.disparity_x16().row(bottom);
  for (int x = region.x; x < region.x + region.width; ++x)
    seen = std::max(seen, row.at<short>(0, x) / 16.0);
  // The predicted ray is the region's last row, `block_size / 2` rows lower: allow the
  // flat ground's disparity change over those rows.
  EXPECT_NEAR(predicted, seen, 1.0 + 0.02 * predicted);
}

TEST_F(FlatScene, FlagsATiltedPoseConvention) {
  Sequence seq = load_sequence(dir_->path());
  // A pose convention off by 30 deg of roll (as if a frame were mislabelled).
  const Pose3d roll(Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  for (SequenceFrame& f : seq.frames) f.pose.T_W_B = f.pose.T_W_B * roll;
  const PreflightReport r = preflight_check(config(), seq, {});
  for (const FrameCheck& f : r.frames) {
    EXPECT_NEAR(f.tilt_w_deg, 30.0, 0.3);
    EXPECT_LT(f.tilt_body_deg, 0.3);  // in the body frame the ground is still level
  }
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_TRUE(mentions(r.problems, "tilted 30.0 deg in W")) << r.problems[0];
  EXPECT_TRUE(mentions(r.problems, "hazard.max_slope_deg 20.0"));
  EXPECT_EQ(ground_tilt_problem(19.9, 0, 20.0), "");
}

TEST_F(FlatScene, FlagsALayerNoPointReachesAndAShortSearch) {
  const Sequence seq = load_sequence(dir_->path());
  // Points only beyond 1.5 m deep: a 1.28 m window around the body gets none.
  PreflightReport r = preflight_check(config({"stereo.z_min=1.5", "map.layers.0.size=128"}), seq, {});
  for (const FrameCheck& f : r.frames) {
    EXPECT_EQ(f.layer_share[0], 0.0);
    EXPECT_GT(f.nearest_point_distance_m, 1.0);
  }
  EXPECT_TRUE(mentions(r.problems, "no point lands in layer 0: its window is 1.28 m"));
  EXPECT_TRUE(mentions(r.problems, "ground nearer than 1.50 m gives no points"));

  // A 16-disparity search: ground nearer than f B / 16 is lost.
  r = preflight_check(config({"stereo.num_disparities=16"}), seq, {});
  EXPECT_TRUE(mentions(r.problems, "search stops at 16 px")) << format_report(r);
}

fs::path chessboard_dir() { return testing::source_dir() / "../shared/data/chessboard"; }

/// Three of the real chessboard pairs as a sequence with the given calibration.
Sequence chessboard_sequence(const fs::path& dir, const StereoCalibration& calibration) {
  Sequence seq;
  seq.dir = dir;
  seq.calibration = calibration;
  fs::create_directories(dir / "left");
  fs::create_directories(dir / "right");
  for (const char* n : {"01", "03", "05"}) {
    SequenceFrame f;
    f.name = n;
    f.left_path = dir / "left" / (std::string(n) + ".png");
    f.right_path = dir / "right" / (std::string(n) + ".png");
    cv::imwrite(f.left_path.string(), cv::imread((chessboard_dir() / ("left" + f.name + ".jpg")).string()));
    cv::imwrite(f.right_path.string(), cv::imread((chessboard_dir() / ("right" + f.name + ".jpg")).string()));
    seq.frames.push_back(f);
  }
  return seq;
}

TEST(PreflightChessboard, MeasuresTheRowErrorAndFlagsABadRotation) {
  if (!fs::is_directory(chessboard_dir())) GTEST_SKIP() << "no shared chessboard data";
  ChessboardOptions board;
  board.inner_corners = {9, 6};
  board.square_m = 0.025;
  const StereoCalibration good = calibrate_chessboard_pairs(chessboard_dir(), board).calibration;
  TempDir dir;
  Config c = load_config(testing::source_dir() / "config/default.yaml");
  PreflightOptions o;
  o.boards = {{9, 6}};
  const PreflightReport ok = preflight_check(c, chessboard_sequence(dir / "good", good), o);
  ASSERT_TRUE(ok.calibration.rows.found);
  EXPECT_EQ(ok.calibration.rows.pairs, 3);
  // The calibration test's bound on the same rectified corners.
  EXPECT_LT(ok.calibration.rows.rms_px, 0.5);
  EXPECT_FALSE(mentions(ok.problems, "rectified rows"));

  // The right camera's rotation off by 0.5 deg about x: rows move by ~f * 0.0087.
  StereoCalibration bad = good;
  bad.R = bad.R * Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const PreflightReport r = preflight_check(c, chessboard_sequence(dir / "bad", bad), o);
  ASSERT_TRUE(r.calibration.rows.found);
  EXPECT_GT(r.calibration.rows.rms_px, 2.0);
  EXPECT_TRUE(mentions(r.problems, "rectified rows disagree"));
}

TEST(PreflightCli, ReportsAndExitsOneOnProblems) {
  const std::string cli = HAZMAP_CLI;
  const std::string sample = (testing::source_dir() / "data/sample").string();
  const std::string config = (testing::source_dir() / "config/default.yaml").string();
  auto ok = testing::run_command(cli + " check --config " + config + " --sequence " + sample +
                                 " --count 1 2>&1");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("verdict: OK"), std::string::npos) << ok.output;
  auto bad = testing::run_command(cli + " check --config " + config + " --sequence " + sample +
                                  " --count 1 --set stereo.z_min=2 2>&1");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("- no point lands in layer 0"), std::string::npos) << bad.output;
  auto usage = testing::run_command(cli + " check --config " + config + " --sequence " + sample +
                                    " --board 9by6 2>&1");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
  EXPECT_NE(usage.output.find("--board 9by6"), std::string::npos) << usage.output;
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

namespace fs = std::filesystem;

// docs/real_data.md's figures: config/euroc_indoor.yaml on the shared EuRoC frames.
TEST(PreflightEuroc, TheReadmeFiguresOfTheRealFloor) {
  const fs::path dir = testing::source_dir() / "../shared/data/euroc_v1_01_micro";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "no shared EuRoC data";
  EurocOptions e;
  e.poses_csv = dir / "poses_leftcam_gt.csv";
  e.poses_frame = EurocPoseFrame::left_camera;
  const Sequence seq = load_euroc_sequence(dir, e);
  const Config c = load_config(testing::source_dir() / "config/euroc_indoor.yaml");
  PreflightOptions o;
  o.max_frames = 3;
  const PreflightReport r = preflight_check(c, seq, o);
  EXPECT_TRUE(r.problems.empty()) << format_report(r);
  ASSERT_TRUE(r.calibration.rows.found);  // the chessboard standing in the room
  EXPECT_LT(r.calibration.rows.rms_px, 0.15);
  for (const FrameCheck& f : r.frames) {
    EXPECT_NEAR(f.camera_height_m, 0.936, 0.005);  // Vicon says 0.926 m
    EXPECT_NEAR(f.tilt_w_deg, 2.2, 0.35);
    EXPECT_GT(f.valid_disparity_share, 0.70);
    EXPECT_GT(f.layer_share[0], 0.5);
  }
}

}  // namespace
}  // namespace hazmap
