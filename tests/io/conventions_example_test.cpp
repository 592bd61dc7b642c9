// The worked example of docs/conventions.md, number for number: the documented
// calibration and pose line read by the project's own readers, a one-pixel disparity
// image through the rectifier's geometry and the point builder, against the numbers the
// document prints (and an independent double computation of its steps 1-4).

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "hazmap/camera/rectifier.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/stereo/point_cloud_builder.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

// Copied from docs/conventions.md ("Worked example").
constexpr const char* kCalibration = R"(image_width: 640
image_height: 520
rectified: true
left:  {K: [268.4, 0, 320, 0, 268.4, 260, 0, 0, 1], D: []}
right: {K: [268.4, 0, 320, 0, 268.4, 260, 0, 0, 1], D: []}
R: [1, 0, 0, 0, 1, 0, 0, 0, 1]
T: [-0.05, 0, 0]
T_body_left: {translation: [0, 0.025, 0.15], rpy_deg: [-110, 0, -90]}
)";
constexpr const char* kPoseLine = "000007 7.0 1.0 2.0 0.1 0 0 0.2588190451 0.9659258263\n";

// The document's printed results (7 decimals).
const Eigen::Vector3d kPC(0.05, 0.0, 0.419375);
const Eigen::Vector3d kPB(0.3940836, -0.025, 0.0065653);
const Eigen::Vector3d kPW(1.3537864, 2.1753912, 0.1065653);

TEST(ConventionsExample, DocumentedNumbersMatchTheCode) {
  testing::TempDir dir;
  { std::ofstream(dir / "calibration.yaml") << kCalibration; }
  const StereoCalibration calib = load_stereo_calibration(dir / "calibration.yaml");
  const auto poses = parse_poses(kPoseLine, "poses.txt");
  ASSERT_EQ(poses.size(), 1u);
  const Pose3d T_W_B = poses[0].second.T_W_B;

  // Independent: steps 1-4 by hand in double (R = Rz(yaw) Ry(pitch) Rx(roll), p = R p + t).
  const double deg = M_PI / 180.0;
  const double Z = 268.4 * 0.05 / 32.0;
  const Eigen::Vector3d p_C((352 - 320) * Z / 268.4, (260 - 260) * Z / 268.4, Z);
  const double c110 = std::cos(-110 * deg), s110 = std::sin(-110 * deg);
  Eigen::Matrix3d Rx, Rz, Rw;
  Rx << 1, 0, 0, 0, c110, -s110, 0, s110, c110;
  Rz << 0, 1, 0, -1, 0, 0, 0, 0, 1;  // Rz(-90 deg)
  Rw << std::cos(30 * deg), -std::sin(30 * deg), 0, std::sin(30 * deg), std::cos(30 * deg), 0, 0,
      0, 1;
  const Eigen::Vector3d p_B = Rz * Rx * p_C + Eigen::Vector3d(0, 0.025, 0.15);
  const Eigen::Vector3d p_W = Rw * p_B + Eigen::Vector3d(1.0, 2.0, 0.1);
  EXPECT_LT((p_C - kPC).norm(), 1e-12);
  EXPECT_LT((p_B - kPB).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((p_W - kPW).cwiseAbs().maxCoeff(), 1e-7);

  // The code: the readers' transforms, the rectifier's geometry and R1, the builder.
  EXPECT_LT((calib.T_B_C * p_C - kPB).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((T_W_B * kPB - kPW).cwiseAbs().maxCoeff(), 2e-7);  // quaternion has 10 digits
  const Rectifier rectifier(calib, 0.0);
  EXPECT_TRUE(rectifier.R1().isIdentity(0.0));
  EXPECT_LT((triangulate(rectifier.geometry(), 352, 260, 32) - kPC).norm(), 1e-12);
  StereoConfig stereo;  // defaults: z in [0.05, 3] m, points up to 0.5 m below ground kept
  const PointCloudBuilder builder(stereo, SensorConfig(), rectifier.geometry(), rectifier.R1(),
                                  calib.T_B_C, rectifier.valid_roi(),
                                  rectifier.valid_roi_right());
  cv::Mat disparity(520, 640, CV_16S, cv::Scalar(-16));
  disparity.at<int16_t>(260, 352) = 32 * 16;
  PointCloud cloud;
  builder.build(disparity, 0, T_W_B, cloud);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_LT((cloud[0].p_W.cast<double>() - kPW).cwiseAbs().maxCoeff(), 1e-5);  // float p_W
}

}  // namespace
}  // namespace hazmap
