#pragma once
// Chessboard image pairs on disk (`hazmap calibrate`, SPEC 2): found in a folder, read,
// turned grey as the stereo path sees them, and calibrated with
// hazmap/camera/chessboard_calibration.hpp.

#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/camera/chessboard_calibration.hpp"

namespace hazmap {

/// Image pair of one board pose.
struct ChessboardPairFiles {
  std::string name;  ///< "01" for left01.jpg/right01.jpg, the stem for left/<stem>.png
  std::filesystem::path left;
  std::filesystem::path right;
};

/// Pairs in `dir`: either `left/<stem>.<ext>` with `right/<stem>.<ext>`, or
/// `left<tag>.<ext>` with `right<tag>.<ext>` (OpenCV's sample naming); ext one of png,
/// jpg, jpeg, bmp, tif, tiff, pgm, ppm. Sorted by name; a left image without its right
/// partner is skipped. Throws Error if `dir` holds no pair.
std::vector<ChessboardPairFiles> find_chessboard_pairs(const std::filesystem::path& dir);

/// Detects the board in every pair of `dir` and calibrates. Throws Error when images
/// differ in size, or fewer than 3 pairs show the whole board in both images.
ChessboardCalibration calibrate_chessboard_pairs(const std::filesystem::path& dir,
                                                 const ChessboardOptions& options);

}  // namespace hazmap
