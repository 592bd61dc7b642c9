#pragma once
// Stereo calibration from chessboard image pairs (`hazmap calibrate`, SPEC 2):
// cv::findChessboardCorners + cv::cornerSubPix in each image, a mono cv::calibrateCamera
// per camera for the starting intrinsics, then cv::stereoCalibrate refining intrinsics
// and extrinsics together with OpenCV's 5-parameter distortion model (k1 k2 p1 p2 k3).
// Board geometry: `inner_corners` = corners per row x per column ("9x6"), squares of
// `square_m` metres, so T comes out in metres. Calibrating from a folder of image pairs:
// hazmap/io/chessboard_pairs.hpp.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/camera/rectifier.hpp"
#include "hazmap/camera/stereo_calibration.hpp"

namespace hazmap {

struct ChessboardOptions {
  cv::Size inner_corners{9, 6};
  double square_m = 0.025;
  /// cv::cornerSubPix half window [px]: (2 n + 1)^2 pixels, smaller than a square.
  int subpix_half_window_px = 11;
};

/// Inner corners of the board in an 8-bit grey image, refined to sub-pixel, row by row.
/// Returns false (and leaves `corners_px` empty) when the whole board is not found.
bool detect_chessboard(const cv::Mat& grey8, const ChessboardOptions& options,
                       std::vector<cv::Point2f>& corners_px);

/// Corners of one pair, in the same board order in both images.
struct ChessboardView {
  std::string name;
  std::vector<cv::Point2f> left_px;
  std::vector<cv::Point2f> right_px;
};

/// Detects the board in both images of a pair (nearly parallel cameras) and numbers the
/// right corners in the left image's order. Returns false unless both show the whole
/// board.
bool detect_chessboard_pair(const cv::Mat& left_grey8, const cv::Mat& right_grey8,
                            const ChessboardOptions& options, ChessboardView& view);

struct ChessboardCalibration {
  StereoCalibration calibration;  ///< T_body_left = identity
  double rms_px = 0.0;            ///< cv::stereoCalibrate RMS over both images of all views
  std::vector<double> view_rms_px;  ///< per used view: sqrt((e_left^2 + e_right^2) / 2)
  std::vector<ChessboardView> views;  ///< views used
  std::vector<std::string> rejected;  ///< pairs where a board was not found in both images
};

/// Calibrates from detected views (image size in pixels). Throws Error as above.
ChessboardCalibration calibrate_stereo(const std::vector<ChessboardView>& views,
                                       cv::Size image_size, const ChessboardOptions& options);

/// How well rectification puts corresponding points on one row: |y_left - y_right| of
/// every corner after mapping both through the rectifier.
struct RowAlignment {
  size_t points = 0;
  double mean_abs_dy_px = 0.0;
  double p99_abs_dy_px = 0.0;
  double max_abs_dy_px = 0.0;
};

/// Row alignment of matching point pairs in raw pixels (left_px[i] <-> right_px[i]).
RowAlignment measure_row_alignment(const Rectifier& rectifier,
                                   const std::vector<ChessboardView>& views);

/// Row alignment of points already in rectified pixels.
RowAlignment row_alignment(const std::vector<ChessboardView>& rectified_views);

}  // namespace hazmap
