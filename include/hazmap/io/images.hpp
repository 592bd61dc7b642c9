#pragma once
// Image input for the stereo front end.

#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

namespace hazmap {

/// What a PNG file's header (IHDR) says, read without decoding the pixels.
struct PngHeader {
  int width = 0;
  int height = 0;
  int bit_depth = 0;   ///< 1, 2, 4, 8 or 16 bits per sample
  int colour_type = 0; ///< 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
  /// The depth the image decodes to: 16 for 16-bit samples, 8 otherwise.
  int decoded_bits() const { return bit_depth == 16 ? 16 : 8; }
  /// "64x48 8-bit grey" for messages.
  std::string describe() const;
};

/// Reads and checks a PNG file's signature, IHDR chunk and the IEND chunk that ends a
/// complete file (a truncated file lacks it), without decoding pixels. Throws Error
/// naming the file: missing, not a PNG, a damaged header, zero or over-large size, or cut
/// short.
PngHeader read_png_header(const std::filesystem::path& path);

/// Reads an image unchanged (8/16-bit, grey or colour). Throws Error naming the file
/// when it is missing or cannot be decoded; the decoder's own messages (libpng's
/// warnings on stderr) are kept off the terminal.
cv::Mat read_image(const std::filesystem::path& path);

/// Converts any supported image to 8-bit grey into `out` (reusing its buffer): colour
/// is converted to luminance, 16-bit is scaled by 1/256. Throws Error on other depths.
void to_gray8(const cv::Mat& in, cv::Mat& out);

/// Encodes `image` as PNG and writes it atomically. Throws Error naming the file.
void write_png(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace hazmap
