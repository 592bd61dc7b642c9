#include "hazmap/camera/stereo_calibration.hpp"

#include <fstream>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

const char* kBase =
    "image_width: 640\nimage_height: 480\n"
    "left:  {K: [500, 0, 320, 0, 501, 240, 0, 0, 1], D: [-0.1, 0.01, 0, 0, 0]}\n"
    "right: {K: [502, 0, 321, 0, 503, 241, 0, 0, 1], D: [-0.1, 0.01, 0, 0]}\n"
    "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-0.12, 0, 0.001]\n";

StereoCalibration load_text(const testing::TempDir& dir, const std::string& text) {
  std::ofstream(dir / "calibration.yaml") << text;
  return load_stereo_calibration(dir / "calibration.yaml");
}

TEST(Calibration, ReadsIntrinsicsExtrinsicsAndDistortion) {
  testing::TempDir dir;
  const StereoCalibration c = load_text(dir, std::string(kBase) +
      "T_body_left: {translation: [0.1, 0.2, 0.3], rpy_deg: [0, 0, 0]}\n");
  EXPECT_EQ(c.image_width, 640);
  EXPECT_DOUBLE_EQ(c.left.K(1, 1), 501);
  EXPECT_DOUBLE_EQ(c.right.K(0, 2), 321);
  ASSERT_EQ(c.left.D.size(), 5u);
  ASSERT_EQ(c.right.D.size(), 4u);
  EXPECT_DOUBLE_EQ(c.T.z(), 0.001);
  EXPECT_DOUBLE_EQ(c.T_B_C.translation().y(), 0.2);
}

TEST(Calibration, RpyAndQuaternionGiveTheSameCameraPose) {
  testing::TempDir dir;
  // Camera looking along body x, pitched down 30 deg: R = Ry(30) Rz(-90) Rx(-90).
  const Eigen::Matrix3d expected =
      Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      rotation_from_rpy(-M_PI / 2, 0, -M_PI / 2);
  const Eigen::Quaterniond q(expected);
  const std::string quat = "T_body_left: {translation: [0, 0, 0.15], quaternion: [" +
                           std::to_string(q.x()) + ", " + std::to_string(q.y()) + ", " +
                           std::to_string(q.z()) + ", " + std::to_string(q.w()) + "]}\n";
  const StereoCalibration from_q = load_text(dir, std::string(kBase) + quat);
  EXPECT_LT((from_q.T_B_C.linear() - expected).norm(), 1e-5);
  // The optical axis (camera z) points forward and 30 deg down in the body frame.
  const Eigen::Vector3d axis = from_q.T_B_C.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.x(), std::cos(30 * M_PI / 180), 1e-5);
  EXPECT_NEAR(axis.z(), -std::sin(30 * M_PI / 180), 1e-5);

  // rpy_deg: zero pitch, roll -90 and yaw -90 maps camera z to body x.
  const StereoCalibration from_rpy = load_text(
      dir, std::string(kBase) + "T_body_left: {translation: [0, 0, 0], rpy_deg: [-90, 0, -90]}\n");
  EXPECT_LT((from_rpy.T_B_C.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_LT((from_rpy.T_B_C.linear() * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(), 1e-12);
}

TEST(Calibration, ErrorsNameFileAndKey) {
  testing::TempDir dir;
  auto error = [&](const std::string& text) {
    try {
      load_text(dir, text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string path = (dir / "calibration.yaml").string();
  EXPECT_EQ(error("image_width: 640\nimage_height: 480\nleft: {D: []}\nright: {K: [1,0,0,0,1,0,0,0,1]}\n"),
            path + ":3: key 'left.K': missing required key");
  EXPECT_NE(error(std::string(kBase) + "extra: 1\n").find("unknown key 'extra'"), std::string::npos);
  EXPECT_NE(error(std::string(kBase) + "rectified: true\n").find("must be zero for a rectified"),
            std::string::npos);
  EXPECT_NE(error("image_width: 640\nimage_height: 480\n"
                  "left:  {K: [500, 0, 320, 0, 501, 240, 0, 0, 1]}\n"
                  "right: {K: [502, 0, 321, 0, 503, 241, 0, 0, 1]}\n"
                  "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [0, 0, 0]\n")
                .find("key 'T': baseline must be non-zero"),
            std::string::npos);
}

}  // namespace
}  // namespace hazmap
