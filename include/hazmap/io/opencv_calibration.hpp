#pragma once
// Import of stereo calibrations in OpenCV's FileStorage layout (YAML `%YAML:1.0` or XML),
// as written by OpenCV's stereo_calib sample and many tools: M1 D1 M2 D2 (intrinsics and
// distortion of the left and right camera), R T (x_right = R x_left + T; R may also be a
// Rodrigues vector). The image size comes from `image_width` + `image_height`, or
// `imageSize` / `image_size` ([w, h]), or the caller. OpenCV files carry no body pose:
// T_body_left is the identity.

#include <filesystem>

#include "hazmap/camera/stereo_calibration.hpp"

namespace hazmap {

struct OpenCvCalibrationOptions {
  /// Image size used when the file has none; 0 x 0: the file must have one.
  int image_width = 0;
  int image_height = 0;
  /// Factor from the file's T units to metres (OpenCV's sample measures T in chessboard
  /// squares unless told the square size; then pass the square size in metres).
  double T_to_m = 1.0;
};

/// Reads and validates the file. `extrinsics` (optional) is a second file holding R and
/// T, as OpenCV's sample writes intrinsics.yml and extrinsics.yml apart. Throws Error
/// naming the file and key.
StereoCalibration load_opencv_stereo_calibration(const std::filesystem::path& path,
                                                 const OpenCvCalibrationOptions& options = {},
                                                 const std::filesystem::path& extrinsics = {});

}  // namespace hazmap
