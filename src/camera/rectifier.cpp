#include "hazmap/camera/rectifier.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

cv::Mat distortion_row(const std::vector<double>& d) {
  return d.empty() ? cv::Mat() : cv::Mat(d, true).reshape(1, 1);
}

/// Remap tables through a JPL model: rectified pixel -> direction in the rectified camera
/// (P's 3x3 inverse) -> the raw camera (R_rect^T) -> the model's frame -> the model's
/// pixel. Exact for any central model, unlike a pinhole + polynomial approximation of
/// it. Pixels the model cannot image map to (-1, -1): remap's border (black).
void model_maps(const CahvoreModel& model, const cv::Mat& R_rect, const cv::Mat& P,
                cv::Size size, cv::Mat& map1, cv::Mat& map2) {
  Eigen::Matrix3d R, P33;
  cv::cv2eigen(R_rect, R);
  cv::cv2eigen(P(cv::Rect(0, 0, 3, 3)), P33);
  const Eigen::Matrix3d R_M_C = cahv_pinhole(model).T_M_C.linear();
  const Eigen::Matrix3d to_model = R_M_C * R.transpose() * P33.inverse();
  // Fixed point straight from double, as cv::initUndistortRectifyMap does (integer pixel
  // and a 1/32 px sub-pixel index), so a pinhole given as CAHV gets the very same table.
  constexpr int kTab = cv::INTER_TAB_SIZE;
  map1.create(size, CV_16SC2);
  map2.create(size, CV_16UC1);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      short* m1 = map1.ptr<short>(v);
      ushort* m2 = map2.ptr<ushort>(v);
      for (int u = 0; u < size.width; ++u) {
        Eigen::Vector2d uv(-1.0, -1.0);
        if (!model.project_direction(to_model * Eigen::Vector3d(u, v, 1.0), uv) ||
            !(std::abs(uv.x()) < 16000.0 && std::abs(uv.y()) < 16000.0))
          uv = Eigen::Vector2d(-1.0, -1.0);  // outside any image: remap's border
        const int iu = cvRound(uv.x() * kTab), iv = cvRound(uv.y() * kTab);
        m1[2 * u] = cv::saturate_cast<short>(iu >> cv::INTER_BITS);
        m1[2 * u + 1] = cv::saturate_cast<short>(iv >> cv::INTER_BITS);
        m2[u] = static_cast<ushort>((iv & (kTab - 1)) * kTab + (iu & (kTab - 1)));
      }
    }
  });
}

/// The largest rectangle, shrunk side by side from the whole image, whose pixels all map
/// inside the raw image (stereoRectify's ROI assumes the pinhole part only).
cv::Rect valid_region(const cv::Mat& map1, const cv::Mat& map2, cv::Size size) {
  cv::Mat map_x, map_y;
  cv::convertMaps(map1, map2, map_x, map_y, CV_32FC1);
  cv::Mat ok = (map_x >= 0) & (map_y >= 0) & (map_x <= size.width - 1) & (map_y <= size.height - 1);
  cv::Rect r(0, 0, size.width, size.height);
  for (bool changed = true; changed && r.area() > 0;) {
    changed = false;
    auto bad = [&](cv::Rect line) { return cv::countNonZero(ok(line)) < line.area(); };
    if (bad({r.x, r.y, r.width, 1})) ++r.y, --r.height, changed = true;
    if (r.height > 0 && bad({r.x, r.y + r.height - 1, r.width, 1})) --r.height, changed = true;
    if (r.height > 0 && bad({r.x, r.y, 1, r.height})) ++r.x, --r.width, changed = true;
    if (r.height > 0 && r.width > 0 && bad({r.x + r.width - 1, r.y, 1, r.height}))
      --r.width, changed = true;
  }
  return r;
}

}  // namespace

Rectifier::Rectifier(const StereoCalibration& calib, double alpha, double row_offset_px)
    : size_(calib.image_width, calib.image_height) {
  if (calib.rectified) {
    identity_ = true;
    geometry_.focal_px = calib.left.K(0, 0);
    geometry_.cx_px = calib.left.K(0, 2);
    geometry_.cy_px = calib.left.K(1, 2);
    geometry_.baseline_m = -calib.T.x();
    valid_roi_ = valid_roi_right_ = roi_right_unshifted_ = cv::Rect(0, 0, size_.width, size_.height);
    if (row_offset_px != 0.0) set_row_offset(row_offset_px);
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
  if (calib.models.empty()) {
    cv::initUndistortRectifyMap(K1_, D1_, R1_cv_, P1_, size_, CV_16SC2, map_left_x_, map_left_y_);
    cv::initUndistortRectifyMap(K2_, D2_, R2_cv_, P2_, size_, CV_16SC2, map_right_x_,
                                map_right_y_);
  } else {
    // JPL models: K1_, K2_ are their linear parts, so stereoRectify chose the rectified
    // pair for them; the maps go through the full models.
    models_ = calib.models;
    model_maps(models_[0], R1_cv_, P1_, size_, map_left_x_, map_left_y_);
    model_maps(models_[1], R2_cv_, P2_, size_, map_right_x_, map_right_y_);
    valid_roi_ = valid_region(map_left_x_, map_left_y_, size_);
    valid_roi_right_ = valid_region(map_right_x_, map_right_y_, size_);
  }
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
  roi_right_unshifted_ = valid_roi_right_;
  P2_shifted_ = P2_;
  if (row_offset_px != 0.0) set_row_offset(row_offset_px);
}

void Rectifier::set_row_offset(double px) {
  if (!std::isfinite(px)) throw Error("rectifier: the row offset must be a finite number");
  row_offset_px_ = px;
  const cv::Rect whole(0, 0, size_.width, size_.height);
  if (identity_) {
    // Already rectified: only the right image moves, through a plain shift map.
    remap_right_ = px != 0.0;
    if (remap_right_) {
      cv::Mat map_x(size_, CV_32FC1), map_y(size_, CV_32FC1);
      for (int v = 0; v < size_.height; ++v)
        for (int u = 0; u < size_.width; ++u) {
          map_x.at<float>(v, u) = static_cast<float>(u);
          map_y.at<float>(v, u) = static_cast<float>(v - px);
        }
      cv::convertMaps(map_x, map_y, map_right_x_, map_right_y_, CV_16SC2);
    }
  } else {
    // A principal point px lower moves every rectified right pixel px rows down.
    P2_shifted_ = P2_.clone();
    P2_shifted_.at<double>(1, 2) += px;
    if (models_.empty()) {
      cv::initUndistortRectifyMap(K2_, D2_, R2_cv_, P2_shifted_, size_, CV_16SC2, map_right_x_,
                                  map_right_y_);
    } else {
      model_maps(models_[1], R2_cv_, P2_shifted_, size_, map_right_x_, map_right_y_);
      valid_roi_right_ = valid_region(map_right_x_, map_right_y_, size_);
      if (valid_roi_right_.area() == 0) valid_roi_right_ = whole;
      return;
    }
  }
  // The valid region moves with the image, shrunk to whole rows.
  const cv::Rect& r = roi_right_unshifted_;
  const int top = static_cast<int>(std::ceil(r.y + px));
  const int bottom = static_cast<int>(std::floor(r.y + r.height + px));
  valid_roi_right_ = cv::Rect(r.x, top, r.width, std::max(0, bottom - top)) & whole;
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
    if (remap_right_) cv::remap(right, out_right, map_right_x_, map_right_y_, cv::INTER_LINEAR);
    else out_right = right;
    return;
  }
  cv::remap(left, out_left, map_left_x_, map_left_y_, cv::INTER_LINEAR);
  cv::remap(right, out_right, map_right_x_, map_right_y_, cv::INTER_LINEAR);
}

void Rectifier::rectify_points(StereoSide side, const std::vector<cv::Point2f>& raw_px,
                               std::vector<cv::Point2f>& rectified_px) const {
  const bool left = side == StereoSide::left;
  if (identity_ || raw_px.empty()) {
    rectified_px = raw_px;
    if (!left)
      for (cv::Point2f& p : rectified_px) p.y += static_cast<float>(row_offset_px_);
    return;
  }
  if (!models_.empty()) {
    // Through the model: raw pixel -> direction (Newton) -> rectified camera -> P.
    const CahvoreModel& model = models_[left ? 0 : 1];
    Eigen::Matrix3d R, P33;
    cv::cv2eigen(left ? R1_cv_ : R2_cv_, R);
    cv::cv2eigen((left ? P1_ : P2_shifted_)(cv::Rect(0, 0, 3, 3)), P33);
    const Eigen::Matrix3d to_rectified = P33 * R * cahv_pinhole(model).T_M_C.linear().transpose();
    rectified_px.resize(raw_px.size());
    for (size_t i = 0; i < raw_px.size(); ++i) {
      Eigen::Vector3d d;
      if (!model.unproject(Eigen::Vector2d(raw_px[i].x, raw_px[i].y), d)) {
        rectified_px[i] = cv::Point2f(NAN, NAN);
        continue;
      }
      const Eigen::Vector3d q = to_rectified * d;
      rectified_px[i] = cv::Point2f(static_cast<float>(q.x() / q.z()), static_cast<float>(q.y() / q.z()));
    }
    return;
  }
  // The iterative undistortion needs more than OpenCV's default 5 iterations to be exact
  // (to 1e-4 px) near the corners of strongly distorted lenses such as EuRoC's.
  cv::undistortPoints(raw_px, rectified_px, left ? K1_ : K2_, left ? D1_ : D2_,
                      left ? R1_cv_ : R2_cv_, left ? P1_ : P2_shifted_,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-9));
}

}  // namespace hazmap
