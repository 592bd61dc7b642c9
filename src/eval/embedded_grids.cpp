#include "hazmap/eval/embedded_grids.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include <zlib.h>

#include "hazmap/core/error.hpp"

namespace hazmap::eval {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Arrays start on this boundary so that a Float32Array can view them in place.
constexpr std::size_t kAlignment = 4;

void check_inside(const std::vector<unsigned char>& buffer, const PackedArray& array,
                  std::size_t value_bytes) {
  check(array.offset <= buffer.size() &&
            array.count <= (buffer.size() - array.offset) / value_bytes,
        "packed array at byte " + std::to_string(array.offset) + " with " +
            std::to_string(array.count) + " values runs past the buffer's " +
            std::to_string(buffer.size()) + " bytes");
}

}  // namespace

void GridPacker::pad() {
  while (bytes_.size() % kAlignment != 0) bytes_.push_back(0);
}

PackedArray GridPacker::add_float32(const std::vector<float>& values) {
  static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559,
                "the page reads IEEE 754 binary32");
  PackedArray a{PackedType::float32, bytes_.size(), values.size()};
  bytes_.reserve(bytes_.size() + 4 * values.size());
  for (float v : values) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int b = 0; b < 4; ++b) bytes_.push_back(static_cast<unsigned char>(bits >> (8 * b)));
  }
  pad();
  return a;
}

PackedArray GridPacker::add_classes(const std::vector<float>& values) {
  PackedArray a{PackedType::class8, bytes_.size(), values.size()};
  bytes_.reserve(bytes_.size() + values.size() + kAlignment);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    if (std::isnan(v)) {
      bytes_.push_back(kClassNoData);
      continue;
    }
    if (!(v >= 0.0f && v < static_cast<float>(kClassNoData) && v == std::floor(v))) {
      bytes_.resize(a.offset);
      throw Error("value " + std::to_string(v) + " at cell " + std::to_string(i) +
                  " is not a hazard class (0 unknown, 1 traversable, 2 hazard)");
    }
    bytes_.push_back(static_cast<unsigned char>(v));
  }
  pad();
  return a;
}

std::string GridPacker::packed_base64() const { return base64_encode(zlib_compress(bytes_)); }

std::string base64_encode(const std::vector<unsigned char>& bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t n = (std::uint32_t(bytes[i]) << 16) | (std::uint32_t(bytes[i + 1]) << 8) |
                            bytes[i + 2];
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(n >> s) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t n = std::uint32_t(bytes[i]) << 16;
    if (rest == 2) n |= std::uint32_t(bytes[i + 1]) << 8;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += rest == 2 ? kAlphabet[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::vector<unsigned char> base64_decode(const std::string& text) {
  check(text.size() % 4 == 0, "base64: length " + std::to_string(text.size()) +
                                  " is not a multiple of 4");
  std::array<int, 256> value;
  value.fill(-1);
  for (int k = 0; k < 64; ++k) value[static_cast<unsigned char>(kAlphabet[k])] = k;
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t n = 0;
    int padding = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      // '=' only as the last one or two characters of the text.
      if (c == '=' && i + 4 == text.size() && k >= 2 && (k == 3 || text[i + 3] == '=')) {
        ++padding;
        n <<= 6;
        continue;
      }
      const int v = value[static_cast<unsigned char>(c)];
      check(v >= 0 && padding == 0,
            "base64: unexpected character at offset " + std::to_string(i + k));
      n = (n << 6) | static_cast<std::uint32_t>(v);
    }
    out.push_back(static_cast<unsigned char>(n >> 16));
    if (padding < 2) out.push_back(static_cast<unsigned char>(n >> 8));
    if (padding < 1) out.push_back(static_cast<unsigned char>(n));
  }
  return out;
}

std::vector<unsigned char> zlib_compress(const std::vector<unsigned char>& bytes) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  std::vector<unsigned char> out(size);
  const int status = compress2(out.data(), &size, bytes.data(), static_cast<uLong>(bytes.size()),
                               Z_BEST_COMPRESSION);
  check(status == Z_OK, "zlib: compression failed (" + std::to_string(status) + ")");
  out.resize(size);
  return out;
}

std::vector<unsigned char> zlib_decompress(const std::vector<unsigned char>& bytes) {
  z_stream s{};
  check(inflateInit(&s) == Z_OK, "zlib: cannot start decompression");
  std::vector<unsigned char> out;
  std::array<unsigned char, 1 << 16> chunk;
  s.next_in = const_cast<Bytef*>(bytes.data());  // zlib's API predates const
  s.avail_in = static_cast<uInt>(bytes.size());
  int status = Z_OK;
  while (status == Z_OK) {
    s.next_out = chunk.data();
    s.avail_out = static_cast<uInt>(chunk.size());
    status = inflate(&s, Z_NO_FLUSH);
    out.insert(out.end(), chunk.data(), chunk.data() + (chunk.size() - s.avail_out));
    if (status == Z_BUF_ERROR && s.avail_in == 0) break;  // input ended before the stream
  }
  inflateEnd(&s);
  check(status == Z_STREAM_END, "zlib: damaged or truncated stream");
  return out;
}

std::vector<float> unpack_float32(const std::vector<unsigned char>& buffer, const PackedArray& array) {
  check(array.type == PackedType::float32, "unpack_float32: the array holds classes");
  check_inside(buffer, array, 4);
  std::vector<float> out(array.count);
  for (std::size_t i = 0; i < array.count; ++i) {
    const unsigned char* p = &buffer[array.offset + 4 * i];
    const std::uint32_t bits = std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) |
                               (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
    std::memcpy(&out[i], &bits, sizeof bits);
  }
  return out;
}

std::vector<float> unpack_classes(const std::vector<unsigned char>& buffer, const PackedArray& array) {
  check(array.type == PackedType::class8, "unpack_classes: the array holds float32 values");
  check_inside(buffer, array, 1);
  std::vector<float> out(array.count);
  for (std::size_t i = 0; i < array.count; ++i) {
    const unsigned char b = buffer[array.offset + i];
    out[i] = b == kClassNoData ? std::nanf("") : static_cast<float>(b);
  }
  return out;
}

}  // namespace hazmap::eval
