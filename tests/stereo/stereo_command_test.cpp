// `hazmap stereo` end to end on the embedded sample sequence, and the disparity images
// it writes.

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/stereo/disparity_image.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

TEST(DisparityImage, SixteenBitKeepsFixedPointAndZeroIsInvalid) {
  cv::Mat d = (cv::Mat_<int16_t>(1, 5) << -16, 0, 16 * 4, 16 * 4 + 1, 16 * 100 + 7);
  cv::Mat u16;
  disparity_to_u16(d, 0, u16);
  ASSERT_EQ(u16.type(), CV_16UC1);
  EXPECT_EQ(u16.at<uint16_t>(0), 0);
  EXPECT_EQ(u16.at<uint16_t>(1), 0);
  EXPECT_EQ(u16.at<uint16_t>(2), 64);
  EXPECT_EQ(u16.at<uint16_t>(4), 1607);
  disparity_to_u16(d, 16 * 4, u16);  // min_disparity 4: d <= 4 px is invalid
  EXPECT_EQ(u16.at<uint16_t>(2), 0);
  EXPECT_EQ(u16.at<uint16_t>(3), 65);
  cv::Mat bgr;
  colorize_disparity(d, 0, 0, 128, bgr);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(bgr.at<cv::Vec3b>(1), cv::Vec3b(0, 0, 0));
  EXPECT_NE(bgr.at<cv::Vec3b>(2), cv::Vec3b(0, 0, 0));
  EXPECT_NE(bgr.at<cv::Vec3b>(2), bgr.at<cv::Vec3b>(4));
}

TEST(StereoCommand, WritesImagesDisparityAndCloudPerFrame) {
  testing::TempDir out;
  const std::filesystem::path seq_dir = testing::source_dir() / "data/sample";
  const std::filesystem::path config = testing::source_dir() / "config/default.yaml";
  const std::string cmd = std::string(HAZMAP_CLI) + " stereo --config " + config.string() +
                          " --sequence " + seq_dir.string() + " --out " + out.path().string() +
                          " --frames 1:3 --quiet";
  ASSERT_EQ(std::system(cmd.c_str()), 0);

  // The same frame through the library: the files must hold exactly its results.
  const Sequence seq = load_sequence(seq_dir);
  const Config cfg = load_config(config);
  StereoFrontEnd front_end(cfg.stereo, cfg.sensor, seq.calibration);
  const SequenceFrame& f = seq.frames[1];
  front_end.process(read_image(f.left_path), read_image(f.right_path), f.pose.T_W_B);
  const std::filesystem::path dir = out / "frames" / f.name;
  EXPECT_FALSE(std::filesystem::exists(out / "frames" / seq.frames[0].name));
  EXPECT_TRUE(std::filesystem::exists(out / "frames" / seq.frames[2].name / "cloud.ply"));

  const cv::Mat rect = cv::imread((dir / "left_rect.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cv::norm(rect, front_end.rectified_left(), cv::NORM_INF), 0);
  const cv::Mat disparity = cv::imread((dir / "disparity.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(disparity.type(), CV_16UC1);
  cv::Mat expected;
  disparity_to_u16(front_end.disparity_x16(), front_end.matcher().invalid_below(), expected);
  EXPECT_EQ(cv::norm(disparity, expected, cv::NORM_INF), 0);
  const cv::Mat colour = cv::imread((dir / "disparity_color.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(colour.type(), CV_8UC3);
  EXPECT_EQ(colour.size(), disparity.size());

  const std::string ply = testing::read_text(dir / "cloud.ply");
  EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex " + std::to_string(front_end.cloud().size()) + "\n"),
            std::string::npos);
  const size_t header_end = ply.find("end_header\n") + 11;
  EXPECT_EQ(ply.size() - header_end, front_end.cloud().size() * (9 * 4 + 3));
  const std::string summary = testing::read_text(out / "stereo_summary.json");
  EXPECT_NE(summary.find("\"frames\": 2"), std::string::npos) << summary;
}

TEST(StereoCommand, BadInputLeavesNoOutput) {
  testing::TempDir tmp;
  const std::string cmd = std::string(HAZMAP_CLI) + " stereo --config " +
                          (testing::source_dir() / "config/default.yaml").string() +
                          " --sequence " + (tmp / "missing").string() + " --out " +
                          (tmp / "out").string() + " 2> " + (tmp / "err.txt").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(testing::read_text(tmp / "err.txt").find("missing: sequence folder not found"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(tmp / "out"));
}

}  // namespace
}  // namespace hazmap
