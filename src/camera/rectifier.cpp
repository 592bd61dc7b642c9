#include "hazmap/camera/rectifier.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

cv::Mat distortion_row(const std::vector<double>& d) {
  return d.empty() ? cv::Mat() : cv::Mat(d, true).reshape(1, 1);
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
    valid_roi_ = valid_roi_right_ = cv::Rect(0, 0, size_.width, size_.height);
    return;
  }
  cv::eigen2cv(calib.left.K, K1_);
  cv::eigen2cv(calib.right.K, K2_);
  D1_ = distortion_row(calib.left.D);
  D2_ = distortion_row(calib.right.D);
  cv::Mat R, T, Q;
  cv::eigen2cv(calib.R, R);
  cv::eigen2cv(calib.T, T);
  cv::stereoRectify(K1_, D1_, K2_, D2_, size_, R, T, R1_cv_, R2_cv_, P1_, P2_, Q,
                    cv::CALIB_ZERO_DISPARITY, alpha, size_, &valid_roi_, &valid_roi_right_);
  cv::initUndistortRectifyMap(K1_, D1_, R1_cv_, P1_, size_, CV_16SC2, map_left_x_, map_left_y_);
  cv::initUndistortRectifyMap(K2_, D2_, R2_cv_, P2_, size_, CV_16SC2, map_right_x_,
                              map_right_y_);
  geometry_.focal_px = P2_.at<double>(0, 0);
  geometry_.baseline_m = -P2_.at<double>(0, 3) / geometry_.focal_px;
  geometry_.cx_px = P1_.at<double>(0, 2);
  geometry_.cy_px = P1_.at<double>(1, 2);
  cv::cv2eigen(R1_cv_, R1_);
  if (!(geometry_.baseline_m > 0))
    throw Error((calib.source.empty() ? std::string("calibration") : calib.source) +
                ": key 'T': the right camera is not to the right of the left one (T.x must be "
                "negative)");
  const cv::Rect whole(0, 0, size_.width, size_.height);
  if (valid_roi_.area() == 0) valid_roi_ = whole;
  if (valid_roi_right_.area() == 0) valid_roi_right_ = whole;
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

void Rectifier::rectify_points(StereoSide side, const std::vector<cv::Point2f>& raw_px,
                               std::vector<cv::Point2f>& rectified_px) const {
  if (identity_ || raw_px.empty()) {
    rectified_px = raw_px;
    return;
  }
  const bool left = side == StereoSide::left;
  // The iterative undistortion needs more than OpenCV's default 5 iterations to be exact
  // (to 1e-4 px) near the corners of strongly distorted lenses such as EuRoC's.
  cv::undistortPoints(raw_px, rectified_px, left ? K1_ : K2_, left ? D1_ : D2_,
                      left ? R1_cv_ : R2_cv_, left ? P1_ : P2_,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-9));
}

}  // namespace hazmap
