#include "hazmap/io/opencv_calibration.hpp"

#include <cmath>
#include <cstdio>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& key,
                       const std::string& what) {
  throw Error(path.string() + ": key '" + key + "': " + what);
}

cv::FileStorage open(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": cannot open calibration file");
  try {
    cv::FileStorage fs(path.string(), cv::FileStorage::READ);
    if (!fs.isOpened()) throw Error(path.string() + ": cannot open calibration file");
    return fs;
  } catch (const cv::Exception& e) {
    throw Error(path.string() + ": not a readable OpenCV FileStorage file: " + e.err);
  }
}

/// The largest matrix a calibration file holds: 14 distortion coefficients (a 3 x 3 is 9).
constexpr long long kMaxMatrixValues = 14;

cv::Mat read_matrix(const cv::FileStorage& fs, const std::filesystem::path& path,
                    const std::string& key) {
  const cv::FileNode node = fs[key];
  if (node.empty()) fail(path, key, "missing required key");
  // OpenCV allocates rows x cols from the header before it reads the data (a mutated
  // "rows: 100000000" asked for 48 GB in the fuzz pass): every matrix here is at most
  // 3 x 3 or 14 distortion coefficients, and must hold as many numbers as it claims.
  if (node.isMap()) {
    const cv::FileNode rows = node["rows"], cols = node["cols"], data = node["data"];
    if (!rows.isInt() || !cols.isInt()) fail(path, key, "matrix rows and cols must be integers");
    const long long r = static_cast<int>(rows), c = static_cast<int>(cols);
    if (r < 1 || c < 1 || r * c > kMaxMatrixValues)
      fail(path, key, "a " + std::to_string(r) + " x " + std::to_string(c) +
                          " matrix is implausible for a calibration (at most " +
                          std::to_string(kMaxMatrixValues) + " numbers)");
    if (!data.isSeq() || static_cast<long long>(data.size()) != r * c)
      fail(path, key, "matrix data must hold rows x cols = " + std::to_string(r * c) + " numbers");
  }
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception& e) {
    fail(path, key, "not a matrix: " + e.err);
  }
  if (m.empty()) fail(path, key, "not a matrix (expected !!opencv-matrix)");
  cv::Mat out;
  m.convertTo(out, CV_64F);
  // Checked here, under the key as this file spells it (D1, not the calibration's left.D).
  if (!cv::checkRange(out)) fail(path, key, "holds a value that is not a finite number");
  return out;
}

Eigen::Matrix3d matrix3(const cv::Mat& m, const std::filesystem::path& path,
                        const std::string& key) {
  if (m.rows != 3 || m.cols != 3) fail(path, key, "expected a 3x3 matrix");
  Eigen::Matrix3d out;
  cv::cv2eigen(m, out);
  return out;
}

std::vector<double> distortion(const cv::Mat& m, const std::filesystem::path& path,
                               const std::string& key) {
  const int n = static_cast<int>(m.total());
  if ((m.rows != 1 && m.cols != 1) || !(n == 4 || n == 5 || n == 8 || n == 12 || n == 14))
    fail(path, key, "expected 4, 5, 8, 12 or 14 distortion coefficients");
  return std::vector<double>(m.ptr<double>(), m.ptr<double>() + n);
}

/// An image dimension: a whole number of pixels in [1, kMaxImageSidePx], range-checked
/// before the conversion to int (a double beyond int's range is undefined to convert).
constexpr double kMaxImageSidePx = 1e6;

int image_side(double v, const std::filesystem::path& path, const std::string& key) {
  if (!(v >= 1 && v <= kMaxImageSidePx) || v != std::floor(v)) {
    char text[160];
    std::snprintf(text, sizeof text, "expected a whole number of pixels in [1, 1000000], found %g",
                  v);
    fail(path, key, text);
  }
  return static_cast<int>(v);
}

int read_int(const cv::FileNode& node, const std::filesystem::path& path, const std::string& key) {
  if (!node.isInt() && !node.isReal()) fail(path, key, "expected a number of pixels");
  return image_side(node.isInt() ? static_cast<double>(static_cast<int>(node))
                                 : static_cast<double>(node),
                    path, key);
}

StereoCalibration load(const std::filesystem::path& path, const OpenCvCalibrationOptions& options,
                       const std::filesystem::path& extrinsics) {
  const cv::FileStorage fs = open(path);
  StereoCalibration c;
  c.left.K = matrix3(read_matrix(fs, path, "M1"), path, "M1");
  c.left.D = distortion(read_matrix(fs, path, "D1"), path, "D1");
  c.right.K = matrix3(read_matrix(fs, path, "M2"), path, "M2");
  c.right.D = distortion(read_matrix(fs, path, "D2"), path, "D2");

  const std::filesystem::path& ext_path = extrinsics.empty() ? path : extrinsics;
  const cv::FileStorage ext_fs = extrinsics.empty() ? fs : open(extrinsics);
  const cv::Mat R = read_matrix(ext_fs, ext_path, "R");
  cv::Mat R33;
  if (R.rows == 3 && R.cols == 3) {
    R33 = R;
  } else if (R.total() == 3) {
    cv::Rodrigues(R.reshape(1, 3), R33);
  } else {
    fail(ext_path, "R", "expected a 3x3 rotation matrix or a Rodrigues vector");
  }
  c.R = matrix3(R33, ext_path, "R");
  const cv::Mat T = read_matrix(ext_fs, ext_path, "T");
  if (T.total() != 3) fail(ext_path, "T", "expected 3 numbers");
  c.T = Eigen::Vector3d(T.at<double>(0), T.at<double>(1), T.at<double>(2)) * options.T_to_m;

  c.image_width = options.image_width;
  c.image_height = options.image_height;
  if (!fs["image_width"].empty() && !fs["image_height"].empty()) {
    c.image_width = read_int(fs["image_width"], path, "image_width");
    c.image_height = read_int(fs["image_height"], path, "image_height");
  } else {
    for (const char* key : {"imageSize", "image_size"}) {
      const cv::FileNode node = fs[key];
      if (node.empty()) continue;
      std::vector<int> size;
      if (node.isSeq()) {
        for (const auto& item : node) size.push_back(read_int(item, path, key));
      } else {
        const cv::Mat m = read_matrix(fs, path, key);
        for (size_t i = 0; i < m.total(); ++i)
          size.push_back(image_side(m.at<double>(static_cast<int>(i)), path, key));
      }
      if (size.size() != 2) fail(path, key, "expected [width, height]");
      c.image_width = size[0];
      c.image_height = size[1];
    }
  }
  if (c.image_width <= 0 || c.image_height <= 0)
    fail(path, "image_width", "no image size in the file (image_width/image_height or imageSize) "
                              "and none given");
  c.source = path.string();
  c.body_pose_source = BodyPoseSource::absent;  // FileStorage files hold no T_body_left
  validate(c, path.string());
  return c;
}

}  // namespace

StereoCalibration load_opencv_stereo_calibration(const std::filesystem::path& path,
                                                 const OpenCvCalibrationOptions& options,
                                                 const std::filesystem::path& extrinsics) {
  // FileStorage asserts rather than reports on a file whose top level is not a map (a
  // lone "-" after the header, measured by the parser fuzz test), and Rodrigues on odd
  // input: those assertions become one line naming the file, not OpenCV's raw text.
  try {
    return load(path, options, extrinsics);
  } catch (const cv::Exception& e) {
    throw Error(path.string() + ": not a usable OpenCV calibration file (OpenCV: " + e.err + ")");
  }
}

}  // namespace hazmap
