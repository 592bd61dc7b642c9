// Calibration files: our calibration.yaml written and read back exactly, and OpenCV
// FileStorage stereo files (M1 D1 M2 D2 R T) in YAML and XML.

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/opencv_calibration.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// What `load` throws (an Error's message), or "" when it succeeds.
template <class Load>
std::string error_of(Load&& load) {
  try {
    load();
  } catch (const Error& e) {
    return std::string(e.what());
  }
  return std::string();
}

StereoCalibration example() {
  StereoCalibration c;
  c.image_width = 752;
  c.image_height = 480;
  c.left.K << 458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1;
  c.right.K << 457.587, 0, 379.999, 0, 456.134, 255.238, 0, 0, 1;
  c.left.D = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  c.right.D = {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05, 0.001};
  c.R = Eigen::AngleAxisd(0.0139, Eigen::Vector3d(0.2, 0.9, -0.1).normalized()).toRotationMatrix();
  c.T = Eigen::Vector3d(-0.110074, 0.000399, -0.000853);
  c.T_B_C.linear() = rotation_from_rpy(-1.5, 0.1, -1.6);
  c.T_B_C.translation() = Eigen::Vector3d(-0.0216, -0.0647, 0.0098);
  return c;
}

void expect_same(const StereoCalibration& a, const StereoCalibration& b, double tol) {
  EXPECT_EQ(a.image_width, b.image_width);
  EXPECT_EQ(a.image_height, b.image_height);
  EXPECT_LE((a.left.K - b.left.K).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((a.right.K - b.right.K).cwiseAbs().maxCoeff(), tol);
  ASSERT_EQ(a.left.D.size(), b.left.D.size());
  ASSERT_EQ(a.right.D.size(), b.right.D.size());
  for (size_t i = 0; i < a.left.D.size(); ++i) EXPECT_NEAR(a.left.D[i], b.left.D[i], tol);
  for (size_t i = 0; i < a.right.D.size(); ++i) EXPECT_NEAR(a.right.D[i], b.right.D[i], tol);
  EXPECT_LE((a.R - b.R).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((a.T - b.T).cwiseAbs().maxCoeff(), tol);
  EXPECT_EQ(a.rectified, b.rectified);
}

TEST(CalibrationFile, WrittenAndReadBackExactly) {
  testing::TempDir dir;
  const StereoCalibration c = example();
  save_stereo_calibration(dir / "calibration.yaml", c, "made by a test\nsecond line");
  const StereoCalibration back = load_stereo_calibration(dir / "calibration.yaml");
  expect_same(back, c, 0.0);  // 17 significant digits: bit-exact
  EXPECT_LT((back.T_B_C.matrix() - c.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-15);

  StereoCalibration rectified;
  rectified.image_width = 640;
  rectified.image_height = 520;
  rectified.left.K << 268.4, 0, 319.5, 0, 268.4, 259.5, 0, 0, 1;
  rectified.right.K = rectified.left.K;
  rectified.T = Eigen::Vector3d(-0.05, 0, 0);
  rectified.rectified = true;
  save_stereo_calibration(dir / "r.yaml", rectified);
  expect_same(load_stereo_calibration(dir / "r.yaml"), rectified, 0.0);

  StereoCalibration broken = c;
  broken.T.setZero();
  EXPECT_THROW(save_stereo_calibration(dir / "broken.yaml", broken), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "broken.yaml"));
}

void write_opencv(const std::filesystem::path& path, const StereoCalibration& c, bool rodrigues,
                  bool size_as_list) {
  cv::FileStorage fs(path.string(), cv::FileStorage::WRITE);
  auto mat = [](const Eigen::Matrix3d& m) {
    cv::Mat out(3, 3, CV_64F);
    for (int i = 0; i < 9; ++i) out.at<double>(i / 3, i % 3) = m(i / 3, i % 3);
    return out;
  };
  fs << "M1" << mat(c.left.K) << "D1" << cv::Mat(c.left.D, true).reshape(1, 1);
  fs << "M2" << mat(c.right.K) << "D2" << cv::Mat(c.right.D, true);
  if (rodrigues) {
    cv::Mat r;
    cv::Rodrigues(mat(c.R), r);
    fs << "R" << r;
  } else {
    fs << "R" << mat(c.R);
  }
  fs << "T" << (cv::Mat_<double>(3, 1) << c.T.x() * 40, c.T.y() * 40, c.T.z() * 40);
  if (size_as_list) {
    fs << "imageSize" << "[" << c.image_width << c.image_height << "]";
  } else {
    fs << "image_width" << c.image_width << "image_height" << c.image_height;
  }
}

TEST(CalibrationFile, DuplicateKeyIsNamedWithFileAndLine) {
  testing::TempDir dir;
  save_stereo_calibration(dir / "calibration.yaml", example());
  std::ifstream in(dir / "calibration.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream(dir / "twice.yaml") << text.str() << "image_width: 640\n";
  try {
    load_stereo_calibration(dir / "twice.yaml");
    FAIL() << "a duplicate key was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find((dir / "twice.yaml").string() + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("duplicate key 'image_width'"), std::string::npos) << msg;
  }
}

TEST(CalibrationFile, OpenCvFileStorageYamlAndXml) {
  testing::TempDir dir;
  const StereoCalibration c = example();
  OpenCvCalibrationOptions options;
  options.T_to_m = 1.0 / 40;  // T written in units of 2.5 cm squares
  write_opencv(dir / "stereo.yml", c, false, false);
  expect_same(load_opencv_stereo_calibration(dir / "stereo.yml", options), c, 1e-12);
  write_opencv(dir / "stereo.xml", c, true, true);
  expect_same(load_opencv_stereo_calibration(dir / "stereo.xml", options), c, 1e-12);
  // A sequence's calibration.yaml may be an OpenCV file (T in metres then).
  write_opencv(dir / "calibration.yaml", c, false, false);
  const StereoCalibration auto_detected = load_stereo_calibration(dir / "calibration.yaml");
  EXPECT_NEAR(auto_detected.T.x(), 40 * c.T.x(), 1e-12);
  EXPECT_TRUE(auto_detected.T_B_C.isApprox(Pose3d::Identity()));
}

TEST(CalibrationFile, OpenCvSplitFilesAndErrors) {
  testing::TempDir dir;
  const StereoCalibration c = example();
  {
    // OpenCV's stereo_calib sample: intrinsics.yml and extrinsics.yml, no image size.
    cv::FileStorage in((dir / "intrinsics.yml").string(), cv::FileStorage::WRITE);
    cv::Mat K1(3, 3, CV_64F), K2(3, 3, CV_64F);
    for (int i = 0; i < 9; ++i) K1.at<double>(i / 3, i % 3) = c.left.K(i / 3, i % 3);
    for (int i = 0; i < 9; ++i) K2.at<double>(i / 3, i % 3) = c.right.K(i / 3, i % 3);
    in << "M1" << K1 << "D1" << cv::Mat(c.left.D, true) << "M2" << K2 << "D2"
       << cv::Mat(c.right.D, true);
    cv::FileStorage ex((dir / "extrinsics.yml").string(), cv::FileStorage::WRITE);
    cv::Mat R(3, 3, CV_64F);
    for (int i = 0; i < 9; ++i) R.at<double>(i / 3, i % 3) = c.R(i / 3, i % 3);
    ex << "R" << R << "T" << (cv::Mat_<double>(3, 1) << c.T.x(), c.T.y(), c.T.z());
  }
  auto message = [](auto&& f) { return error_of(f); };
  const std::string intrinsics = (dir / "intrinsics.yml").string();
  EXPECT_EQ(message([&] { load_opencv_stereo_calibration(dir / "intrinsics.yml"); }),
            intrinsics + ": key 'R': missing required key");
  EXPECT_EQ(message([&] {
              load_opencv_stereo_calibration(dir / "intrinsics.yml", {}, dir / "extrinsics.yml");
            }),
            intrinsics + ": key 'image_width': no image size in the file (image_width/image_height "
                         "or imageSize) and none given");
  OpenCvCalibrationOptions options;
  options.image_width = 752;
  options.image_height = 480;
  expect_same(load_opencv_stereo_calibration(dir / "intrinsics.yml", options, dir / "extrinsics.yml"),
              c, 1e-12);
  std::ofstream(dir / "garbage.yml") << "%YAML:1.0\nM1: [1, 2\n";
  EXPECT_NE(message([&] { load_opencv_stereo_calibration(dir / "garbage.yml"); })
                .find("garbage.yml"),
            std::string::npos);
}

// Issue 24: an image size of 1e300 was converted to int unchecked (undefined); it is now
// range-checked first and named with the file and key.
TEST(CalibrationFile, OpenCvImageSizeIsRangeCheckedBeforeTheConversion) {
  testing::TempDir dir;
  const StereoCalibration c = example();
  auto rewrite = [&](bool size_as_list, const std::string& from, const std::string& to) {
    write_opencv(dir / "stereo.yml", c, false, size_as_list);
    std::ifstream in(dir / "stereo.yml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << text;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    std::ofstream(dir / "stereo.yml") << text;
  };
  auto message = [&] { return error_of([&] { load_opencv_stereo_calibration(dir / "stereo.yml"); }); };
  const std::string file = (dir / "stereo.yml").string();
  rewrite(false, "image_width: 752", "image_width: 1.0e+300");
  EXPECT_EQ(message(), file + ": key 'image_width': expected a whole number of pixels in "
                              "[1, 1000000], found 1e+300");
  rewrite(false, "image_height: 480", "image_height: -3.0e+10");
  EXPECT_EQ(message(), file + ": key 'image_height': expected a whole number of pixels in "
                              "[1, 1000000], found -3e+10");
  rewrite(false, "image_width: 752", "image_width: 752.5");
  EXPECT_NE(message().find("key 'image_width': expected a whole number"), std::string::npos);
  rewrite(true, "752", "7.52e+300");
  EXPECT_EQ(message(), file + ": key 'imageSize': expected a whole number of pixels in "
                              "[1, 1000000], found 7.52e+300");
  rewrite(false, "image_width: 752", "image_width: 752.0");  // a whole real is fine
  EXPECT_EQ(message(), "");
}

TEST(CalibrationFile, OpenCvMatrixSizeIsCheckedBeforeOpenCvAllocatesIt) {
  // Found by the parser fuzz pass under ASan: "rows: 100000000" made OpenCV allocate
  // 48 GB before reading the data.
  testing::TempDir dir;
  const std::string head = "%YAML:1.0\n---\nimage_width: 64\nimage_height: 48\nM1: !!opencv-matrix\n";
  auto message = [&](const std::string& matrix) {
    std::ofstream(dir / "stereo.yml") << head << matrix;
    return error_of([&] { load_opencv_stereo_calibration(dir / "stereo.yml"); });
  };
  const std::string file = (dir / "stereo.yml").string();
  EXPECT_EQ(message("   rows: 100000000\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0. ]\n"),
            file + ": key 'M1': a 100000000 x 3 matrix is implausible for a calibration (at most "
                   "14 numbers)");
  EXPECT_EQ(message("   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0. ]\n"),
            file + ": key 'M1': matrix data must hold rows x cols = 9 numbers");
}

// Issue 37: a NaN in an OpenCV file's D1 was reported as key 'left.D'; every matrix is
// now checked as read, under the key the file spells.
TEST(CalibrationFile, OpenCvNonFiniteValueIsNamedWithTheFilesKey) {
  testing::TempDir dir;
  const std::string matrix3 = "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: ";
  const std::string k = matrix3 + "[ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n";
  const std::string d = "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: ";
  const std::string head = "%YAML:1.0\n---\nimage_width: 64\nimage_height: 48\n";
  auto message = [&](const std::string& text) {
    std::ofstream(dir / "stereo.yml", std::ios::trunc) << head << text;
    return error_of([&] { load_opencv_stereo_calibration(dir / "stereo.yml"); });
  };
  const std::string file = (dir / "stereo.yml").string();
  EXPECT_EQ(message("M1: " + k + "D1: " + d + "[ 0.01, .Nan, 0., 0., 0. ]\n"),
            file + ": key 'D1': holds a value that is not a finite number");
  EXPECT_EQ(message("M1: " + matrix3 + "[ 50., 0., .Inf, 0., 50., 23.5, 0., 0., 1. ]\n"),
            file + ": key 'M1': holds a value that is not a finite number");
  EXPECT_EQ(message("M1: " + k + "D1: " + d + "[ 0., 0., 0., 0., 0. ]\nM2: " + k + "D2: " + d +
                    "[ 0., 0., 0., 0., -.Inf ]\n"),
            file + ": key 'D2': holds a value that is not a finite number");
}

}  // namespace
}  // namespace hazmap
