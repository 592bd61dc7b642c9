#include "hazmap/io/images.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {

namespace {

std::uint32_t big_endian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

/// PNG allows 2^31 - 1 per side; OpenCV refuses images above 2^30 pixels (its
/// CV_IO_MAX_IMAGE_PIXELS default), so a header beyond that cannot be read either.
constexpr double kMaxImagePixels = 1073741824.0;

/// CRC-32 as PNG uses it (ISO 3309, polynomial 0xedb88320), table built once.
std::uint32_t crc32(const unsigned char* p, size_t n) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

/// Empty when the PNG bytes are a chain of whole chunks with matching CRCs up to IEND,
/// else what is wrong. Checked before decoding because libpng prints its own
/// "libpng error: ..." line on stderr for a damaged file, beside ours.
std::string png_chunk_problem(const std::vector<unsigned char>& b) {
  size_t at = 8;
  while (at + 12 <= b.size()) {
    const std::uint32_t length = big_endian32(&b[at]);
    if (length > b.size() - at - 12) return "PNG file cut short inside a chunk";
    const std::string type(&b[at + 4], &b[at + 8]);
    if (crc32(&b[at + 4], length + 4) != big_endian32(&b[at + 8 + length]))
      return "damaged PNG file (CRC mismatch in a '" + type + "' chunk at byte " +
             std::to_string(at) + ")";
    if (type == "IEND") return "";
    at += 12 + length;
  }
  return "PNG file cut short (it does not end with the IEND chunk)";
}

}  // namespace

std::string PngHeader::describe() const {
  const char* kind = colour_type == 0   ? "grey"
                     : colour_type == 2 ? "RGB"
                     : colour_type == 3 ? "palette"
                     : colour_type == 4 ? "grey+alpha"
                                        : "RGBA";
  return std::to_string(width) + "x" + std::to_string(height) + " " + std::to_string(bit_depth) +
         "-bit " + kind;
}

PngHeader read_png_header(const std::filesystem::path& path) {
  auto fail = [&](const std::string& what) { return Error(path.string() + ": " + what); };
  if (!std::filesystem::is_regular_file(path)) throw fail("image not found");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fail("cannot open image");
  // Signature (8 bytes), then the IHDR chunk: length 13, "IHDR", 13 data bytes, CRC.
  std::array<unsigned char, 33> head{};
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  if (in.gcount() < 8 || !std::equal(kSignature, kSignature + 8, head.begin()))
    throw fail("not a PNG file (no PNG signature)");
  if (in.gcount() < static_cast<std::streamsize>(head.size()))
    throw fail("PNG file cut short inside its header");
  if (big_endian32(&head[8]) != 13 || std::string(&head[12], &head[16]) != "IHDR")
    throw fail("damaged PNG header (no IHDR chunk first)");
  PngHeader h;
  const std::uint32_t w = big_endian32(&head[16]), ht = big_endian32(&head[20]);
  h.bit_depth = head[24];
  h.colour_type = head[25];
  if (w == 0 || ht == 0 || w > 0x7fffffffu || ht > 0x7fffffffu)
    throw fail("damaged PNG header (size " + std::to_string(w) + "x" + std::to_string(ht) + ")");
  if (static_cast<double>(w) * static_cast<double>(ht) > kMaxImagePixels)
    throw fail("PNG claims " + std::to_string(w) + "x" + std::to_string(ht) +
               " pixels, more than the 2^30 an image may have");
  h.width = static_cast<int>(w);
  h.height = static_cast<int>(ht);
  const int d = h.bit_depth, c = h.colour_type;
  const bool valid = (c == 0 && (d == 1 || d == 2 || d == 4 || d == 8 || d == 16)) ||
                     (c == 3 && (d == 1 || d == 2 || d == 4 || d == 8)) ||
                     ((c == 2 || c == 4 || c == 6) && (d == 8 || d == 16));
  if (!valid)
    throw fail("damaged PNG header (bit depth " + std::to_string(d) + " with colour type " +
               std::to_string(c) + ")");
  // A complete PNG ends with the IEND chunk: length 0, "IEND", its fixed CRC.
  static const unsigned char kEnd[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
  std::array<unsigned char, 12> tail{};
  in.seekg(-static_cast<std::streamoff>(tail.size()), std::ios::end);
  in.read(reinterpret_cast<char*>(tail.data()), tail.size());
  if (!in || !std::equal(kEnd, kEnd + 12, tail.begin()))
    throw fail("PNG file cut short (it does not end with the IEND chunk)");
  return h;
}

cv::Mat read_image(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": image not found");
  // The bytes are read here and decoded from memory: imread would print its own warning
  // lines on stderr for a damaged file, besides our one-line error.
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (!in && !in.eof()) throw Error(path.string() + ": cannot read image");
  if (bytes.size() >= 8 && std::equal(kSignature, kSignature + 8, bytes.begin())) {
    const std::string problem = png_chunk_problem(bytes);
    if (!problem.empty()) throw Error(path.string() + ": " + problem);
  }
  cv::Mat image;
  try {
    if (!bytes.empty()) image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw Error(path.string() + ": cannot decode image (OpenCV: " + e.err + ")");
  }
  if (image.empty()) throw Error(path.string() + ": cannot decode image");
  return image;
}

void to_gray8(const cv::Mat& in, cv::Mat& out) {
  cv::Mat grey;
  if (in.channels() == 3) {
    cv::cvtColor(in, grey, cv::COLOR_BGR2GRAY);
  } else if (in.channels() == 4) {
    cv::cvtColor(in, grey, cv::COLOR_BGRA2GRAY);
  } else if (in.channels() == 1) {
    grey = in;
  } else {
    throw Error("image has " + std::to_string(in.channels()) + " channels");
  }
  if (grey.depth() == CV_8U) {
    if (grey.data != out.data) grey.copyTo(out);
  } else if (grey.depth() == CV_16U) {
    grey.convertTo(out, CV_8U, 1.0 / 256.0);
  } else {
    throw Error("unsupported image depth (expected 8 or 16 bit)");
  }
}

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) throw Error(path.string() + ": PNG encoding failed");
  write_file_atomically(path, bytes);
}

}  // namespace hazmap
