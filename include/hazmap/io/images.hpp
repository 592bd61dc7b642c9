#pragma once
// Image input for the stereo front end.

#include <filesystem>

#include <opencv2/core.hpp>

namespace hazmap {

/// Reads an image unchanged (8/16-bit, grey or colour). Throws Error naming the file
/// when it is missing or cannot be decoded.
cv::Mat read_image(const std::filesystem::path& path);

/// Converts any supported image to 8-bit grey into `out` (reusing its buffer): colour
/// is converted to luminance, 16-bit is scaled by 1/256. Throws Error on other depths.
void to_gray8(const cv::Mat& in, cv::Mat& out);

/// Encodes `image` as PNG and writes it atomically. Throws Error naming the file.
void write_png(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace hazmap
