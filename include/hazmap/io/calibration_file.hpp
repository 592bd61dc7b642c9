#pragma once
// Calibration files (SPEC 2): our calibration.yaml read and written, and OpenCV's
// FileStorage stereo files recognised and handed to hazmap/io/opencv_calibration.hpp.

#include <filesystem>
#include <string>

#include "hazmap/camera/stereo_calibration.hpp"

namespace hazmap {

/// Reads our calibration.yaml (SPEC 2). A file in OpenCV's FileStorage layout (it starts
/// with `%YAML:1.0` or `<?xml`; keys M1 D1 M2 D2 R T and the image size) is read with
/// load_opencv_stereo_calibration (hazmap/io/opencv_calibration.hpp) instead. Throws
/// Error naming the file, line and key.
StereoCalibration load_stereo_calibration(const std::filesystem::path& path);

/// Our calibration.yaml text for `calibration` (SPEC 2): numbers with 17 significant
/// digits, so loading it gives back the same values; T_body_left as translation and
/// quaternion [qx, qy, qz, qw]. `comment` (may hold several lines) is written first,
/// each line prefixed with "# ".
std::string format_stereo_calibration(const StereoCalibration& calibration,
                                      const std::string& comment = "");

/// Validates and writes format_stereo_calibration() atomically. Throws Error.
void save_stereo_calibration(const std::filesystem::path& path,
                             const StereoCalibration& calibration,
                             const std::string& comment = "");

}  // namespace hazmap
