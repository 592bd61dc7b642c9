#include "hazmap/camera/rectifier.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

cv::Mat to_cv(const Eigen::Matrix3d& m) {
  cv::Mat out(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.at<double>(r, c) = m(r, c);
  return out;
}

}  // namespace

Rectifier::Rectifier(const StereoCalibration& calib, double alpha)
    : size_(calib.image_width, calib.image_height) {
  if (calib.rectified) {
    identity_ = true;
    geometry_.focal_px = calib.left.K(0, 0);
    geometry_.cx_px = calib.left.K(0, 2);
    geometry_.cy_px = calib.left.K(1, 2);
    geometry_.baseline_m = -calib.T.x();
    valid_roi_ = cv::Rect(0, 0, size_.width, size_.height);
    return;
  }
  const cv::Mat K1 = to_cv(calib.left.K), K2 = to_cv(calib.right.K);
  const cv::Mat D1(calib.left.D, true), D2(calib.right.D, true);
  const cv::Mat R = to_cv(calib.R);
  const cv::Mat T = (cv::Mat_<double>(3, 1) << calib.T.x(), calib.T.y(), calib.T.z());
  cv::Mat R1, R2, P1, P2, Q;
  cv::Rect roi_right;
  cv::stereoRectify(K1, D1.reshape(1, 1), K2, D2.reshape(1, 1), size_, R, T, R1, R2, P1, P2, Q,
                    cv::CALIB_ZERO_DISPARITY, alpha, size_, &valid_roi_, &roi_right);
  cv::initUndistortRectifyMap(K1, D1.reshape(1, 1), R1, P1, size_, CV_16SC2, map_left_x_,
                              map_left_y_);
  cv::initUndistortRectifyMap(K2, D2.reshape(1, 1), R2, P2, size_, CV_16SC2, map_right_x_,
                              map_right_y_);
  geometry_.focal_px = P2.at<double>(0, 0);
  geometry_.baseline_m = -P2.at<double>(0, 3) / geometry_.focal_px;
  geometry_.cx_px = P1.at<double>(0, 2);
  geometry_.cy_px = P1.at<double>(1, 2);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R1_(r, c) = R1.at<double>(r, c);
  if (!(geometry_.baseline_m > 0))
    throw Error("calibration: the right camera is not to the right of the left one (T.x must be "
                "negative)");
  if (valid_roi_.area() == 0) valid_roi_ = cv::Rect(0, 0, size_.width, size_.height);
}

void Rectifier::rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& out_left,
                        cv::Mat& out_right) const {
  if (left.size() != size_ || right.size() != size_)
    throw Error("image size " + std::to_string(left.cols) + "x" + std::to_string(left.rows) +
                " / " + std::to_string(right.cols) + "x" + std::to_string(right.rows) +
                " differs from the calibration's " + std::to_string(size_.width) + "x" +
                std::to_string(size_.height));
  if (identity_) {
    out_left = left;
    out_right = right;
    return;
  }
  cv::remap(left, out_left, map_left_x_, map_left_y_, cv::INTER_LINEAR);
  cv::remap(right, out_right, map_right_x_, map_right_y_, cv::INTER_LINEAR);
}

}  // namespace hazmap
