#include "hazmap/camera/chessboard_calibration.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

std::vector<cv::Point3f> board_points(const ChessboardOptions& o) {
  std::vector<cv::Point3f> points;
  for (int row = 0; row < o.inner_corners.height; ++row)
    for (int col = 0; col < o.inner_corners.width; ++col)
      points.emplace_back(static_cast<float>(col * o.square_m),
                          static_cast<float>(row * o.square_m), 0.0f);
  return points;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k =
      std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

}  // namespace

bool detect_chessboard(const cv::Mat& grey8, const ChessboardOptions& o,
                       std::vector<cv::Point2f>& corners_px) {
  corners_px.clear();
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(grey8, o.inner_corners, corners_px, flags)) {
    corners_px.clear();
    return false;
  }
  const int w = o.subpix_half_window_px;
  cv::cornerSubPix(grey8, corners_px, cv::Size(w, w), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-4));
  return true;
}

bool detect_chessboard_pair(const cv::Mat& left_grey8, const cv::Mat& right_grey8,
                            const ChessboardOptions& o, ChessboardView& view) {
  view.right_px.clear();
  if (!detect_chessboard(left_grey8, o, view.left_px) ||
      !detect_chessboard(right_grey8, o, view.right_px)) {
    view.left_px.clear();
    view.right_px.clear();
    return false;
  }
  // A board of 9x6 inner corners looks the same turned by 180 deg, so the detector may
  // number the corners from opposite ends in the two images: the first-to-last corner
  // vector must point the same way in both (the cameras are nearly parallel).
  const cv::Point2f dl = view.left_px.back() - view.left_px.front();
  const cv::Point2f dr = view.right_px.back() - view.right_px.front();
  if (dl.dot(dr) < 0) std::reverse(view.right_px.begin(), view.right_px.end());
  return true;
}

ChessboardCalibration calibrate_stereo(const std::vector<ChessboardView>& views,
                                       cv::Size image_size, const ChessboardOptions& o) {
  if (views.size() < 3)
    throw Error("calibration: the board was found in both images of only " +
                std::to_string(views.size()) + " pairs; at least 3 are needed");
  const std::vector<cv::Point3f> board = board_points(o);
  std::vector<std::vector<cv::Point3f>> object(views.size(), board);
  std::vector<std::vector<cv::Point2f>> left, right;
  for (const auto& v : views) {
    if (v.left_px.size() != board.size() || v.right_px.size() != board.size())
      throw Error("calibration: view " + v.name + " does not hold " +
                  std::to_string(board.size()) + " corners in both images");
    left.push_back(v.left_px);
    right.push_back(v.right_px);
  }
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-10);
  // Mono calibrations first: stereoCalibrate's joint optimisation is local, and starts
  // far better from each camera's own intrinsics than from a guess.
  cv::Mat K1, D1, K2, D2;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms_left = cv::calibrateCamera(object, left, image_size, K1, D1, rvecs, tvecs, 0,
                                              criteria);
  const double rms_right = cv::calibrateCamera(object, right, image_size, K2, D2, rvecs, tvecs, 0,
                                               criteria);
  spdlog::debug("mono calibration RMS: left {:.3f} px, right {:.3f} px", rms_left, rms_right);
  cv::Mat R, T, E, F, per_view;
  const double rms = cv::stereoCalibrate(object, left, right, K1, D1, K2, D2, image_size, R, T, E,
                                         F, per_view, cv::CALIB_USE_INTRINSIC_GUESS, criteria);
  ChessboardCalibration out;
  out.rms_px = rms;
  out.views = views;
  for (int i = 0; i < per_view.rows; ++i) {
    const double el = per_view.at<double>(i, 0), er = per_view.at<double>(i, 1);
    out.view_rms_px.push_back(std::sqrt((el * el + er * er) / 2.0));
  }
  StereoCalibration& c = out.calibration;
  c.image_width = image_size.width;
  c.image_height = image_size.height;
  cv::cv2eigen(K1, c.left.K);
  cv::cv2eigen(K2, c.right.K);
  c.left.D.assign(D1.ptr<double>(), D1.ptr<double>() + D1.total());
  c.right.D.assign(D2.ptr<double>(), D2.ptr<double>() + D2.total());
  cv::cv2eigen(R, c.R);
  cv::cv2eigen(T, c.T);
  validate(c, "calibration");
  return out;
}

RowAlignment row_alignment(const std::vector<ChessboardView>& views) {
  std::vector<double> dy;
  for (const auto& v : views)
    for (size_t i = 0; i < v.left_px.size() && i < v.right_px.size(); ++i)
      dy.push_back(std::abs(static_cast<double>(v.left_px[i].y) - v.right_px[i].y));
  RowAlignment a;
  a.points = dy.size();
  if (dy.empty()) return a;
  for (double d : dy) a.mean_abs_dy_px += d;
  a.mean_abs_dy_px /= static_cast<double>(dy.size());
  a.max_abs_dy_px = *std::max_element(dy.begin(), dy.end());
  a.p99_abs_dy_px = percentile(dy, 0.99);
  return a;
}

RowAlignment measure_row_alignment(const Rectifier& rectifier,
                                   const std::vector<ChessboardView>& views) {
  std::vector<ChessboardView> rectified(views.size());
  for (size_t i = 0; i < views.size(); ++i) {
    rectified[i].name = views[i].name;
    rectifier.rectify_points(StereoSide::left, views[i].left_px, rectified[i].left_px);
    rectifier.rectify_points(StereoSide::right, views[i].right_px, rectified[i].right_px);
  }
  return row_alignment(rectified);
}

}  // namespace hazmap
