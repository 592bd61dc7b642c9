#pragma once
// Grids packed into text for a self-contained web page (`hazmap view`): the values of
// several grids are concatenated into one byte buffer, compressed with zlib (RFC 1950,
// what a browser's DecompressionStream("deflate") reads) and written as base64, which a
// <script type="application/octet-stream"> element can hold.
//
// The buffer, little-endian (as every browser's typed arrays):
//   float32 arrays  the grid's values as IEEE 754 binary32, bit for bit: the page shows
//                   the files' values exactly (NaN stays NaN, -0 stays -0);
//   class arrays    one byte per cell: the hazard class 0, 1 or 2, or kClassNoData for
//                   NaN;
// every array starts at a multiple of 4 bytes (zero padding), so that a Float32Array can
// view it in place.
//
// Why no byte shuffling or delta coding before deflate: measured on a 30-frame
// cadre_flight run at 0.4 scale, a frame's grids (2.25 MB raw, mostly NaN outside what
// the cameras saw) deflate to 48 kB as they are; splitting floats into byte planes made
// the sparse grids larger and helped only the dense distance map, which the viewer leaves
// out.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hazmap::eval {

/// The byte a class array holds for a NaN cell.
constexpr std::uint8_t kClassNoData = 255;

enum class PackedType { float32, class8 };

/// Where one array lies in the uncompressed buffer.
struct PackedArray {
  PackedType type = PackedType::float32;
  std::size_t offset = 0;  ///< bytes from the buffer's start, a multiple of 4
  std::size_t count = 0;   ///< values (cells)
};

/// Collects arrays into one buffer; finish with packed_base64().
class GridPacker {
 public:
  PackedArray add_float32(const std::vector<float>& values);
  /// Hazard classes: each value NaN or a whole number in [0, 254]. Throws Error naming
  /// the first other value and its index (the caller adds the file).
  PackedArray add_classes(const std::vector<float>& values);

  const std::vector<unsigned char>& bytes() const { return bytes_; }
  /// The buffer compressed (zlib, best compression) and base64-encoded.
  std::string packed_base64() const;

 private:
  void pad();
  std::vector<unsigned char> bytes_;
};

/// RFC 4648 base64 with padding, no line breaks.
std::string base64_encode(const std::vector<unsigned char>& bytes);
/// Inverse of base64_encode; throws Error on a character outside the alphabet or a
/// length that is not a multiple of 4.
std::vector<unsigned char> base64_decode(const std::string& text);

/// zlib format (RFC 1950), best compression.
std::vector<unsigned char> zlib_compress(const std::vector<unsigned char>& bytes);
/// Inverse of zlib_compress; throws Error on damaged input.
std::vector<unsigned char> zlib_decompress(const std::vector<unsigned char>& bytes);

/// The values of `array` in an uncompressed buffer, as a page reads them (tests, tools).
/// Class bytes come back as floats, kClassNoData as NaN. Throws Error when the array
/// does not lie inside `buffer` or has the other type.
std::vector<float> unpack_float32(const std::vector<unsigned char>& buffer, const PackedArray& array);
std::vector<float> unpack_classes(const std::vector<unsigned char>& buffer, const PackedArray& array);

}  // namespace hazmap::eval
