// Grids packed for hazmap view's page (embedded_grids.hpp): every float comes back bit
// for bit through deflate and base64 (NaN, -0, infinities and subnormals included),
// classes as bytes, each array aligned for a Float32Array; base64 against RFC 4648's
// test vectors; damaged input is refused.

#include "hazmap/eval/embedded_grids.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap::eval {
namespace {

std::vector<unsigned char> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

std::uint32_t bits(float v) {
  std::uint32_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// The buffer as the page receives it: through base64 and zlib.
std::vector<unsigned char> through_page(const GridPacker& packer) {
  return zlib_decompress(base64_decode(packer.packed_base64()));
}

TEST(EmbeddedGrids, FloatsRoundTripBitForBit) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> special = {0.0f, -0.0f, 1.0f, -1.5f, std::nanf(""), -std::nanf(""),
                                inf, -inf, std::numeric_limits<float>::denorm_min(),
                                std::numeric_limits<float>::max(),
                                std::numeric_limits<float>::lowest(), 0.1f, 1e-30f};
  std::mt19937 rng(7);  // seeded: any 32-bit pattern that is a float
  std::vector<float> random(10007);
  for (float& v : random) {
    const auto b = static_cast<std::uint32_t>(rng());
    std::memcpy(&v, &b, sizeof v);
  }
  GridPacker packer;
  const PackedArray a = packer.add_float32(special);
  const PackedArray c = packer.add_classes({0.0f, 1.0f, 2.0f});  // misaligns what follows...
  const PackedArray b = packer.add_float32(random);
  EXPECT_EQ(b.offset % 4, 0u);  // ...unless padded
  EXPECT_EQ(a.offset, 0u);
  EXPECT_EQ(c.offset, 4 * special.size());

  const std::vector<unsigned char> buffer = through_page(packer);
  EXPECT_EQ(buffer, packer.bytes());
  for (const auto& [array, values] : {std::make_pair(a, special), std::make_pair(b, random)}) {
    const std::vector<float> back = unpack_float32(buffer, array);
    ASSERT_EQ(back.size(), values.size());
    for (size_t i = 0; i < values.size(); ++i)
      ASSERT_EQ(bits(back[i]), bits(values[i])) << "value " << i;
  }
  // Little-endian on any host: 1.0f is 00 00 80 3f.
  EXPECT_EQ(std::vector<unsigned char>(buffer.begin() + 8, buffer.begin() + 12),
            (std::vector<unsigned char>{0x00, 0x00, 0x80, 0x3f}));
}

TEST(EmbeddedGrids, ClassesAreBytesWithNaNAsNoData) {
  GridPacker packer;
  const PackedArray a = packer.add_classes({0.0f, 1.0f, 2.0f, std::nanf(""), 254.0f});
  const std::vector<unsigned char> buffer = through_page(packer);
  EXPECT_EQ(std::vector<unsigned char>(buffer.begin(), buffer.begin() + 5),
            (std::vector<unsigned char>{0, 1, 2, kClassNoData, 254}));
  EXPECT_EQ(buffer.size(), 8u);  // padded to 4
  const std::vector<float> back = unpack_classes(buffer, a);
  EXPECT_EQ(back[2], 2.0f);
  EXPECT_TRUE(std::isnan(back[3]));
  EXPECT_THROW(unpack_float32(buffer, a), Error);  // the wrong type
}

TEST(EmbeddedGrids, RejectsValuesThatAreNotClasses) {
  for (float bad : {0.5f, -1.0f, 255.0f, 1e9f, std::numeric_limits<float>::infinity()}) {
    GridPacker packer;
    packer.add_classes({1.0f});
    try {
      packer.add_classes({0.0f, bad});
      FAIL() << "accepted " << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("at cell 1"), std::string::npos) << e.what();
    }
    EXPECT_EQ(packer.bytes().size(), 4u) << "the failed array left bytes behind";
  }
}

TEST(EmbeddedGrids, Base64MatchesRfc4648) {
  const std::pair<const char*, const char*> vectors[] = {
      {"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},        {"foo", "Zm9v"},
      {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : vectors) {
    EXPECT_EQ(base64_encode(bytes_of(plain)), coded);
    EXPECT_EQ(base64_decode(coded), bytes_of(plain));
  }
  std::vector<unsigned char> all(256);
  for (int i = 0; i < 256; ++i) all[static_cast<size_t>(i)] = static_cast<unsigned char>(i);
  EXPECT_EQ(base64_decode(base64_encode(all)), all);
  for (const char* bad : {"Zg=", "Zg=a", "Z===", "Zm9v!A==", "=Zm9", "Zg==Zg=="})
    EXPECT_THROW(base64_decode(bad), Error) << bad;
}

TEST(EmbeddedGrids, DamagedStreamsAreRefused) {
  const std::vector<unsigned char> packed = zlib_compress(std::vector<unsigned char>(1000, 7));
  EXPECT_EQ(zlib_decompress(packed), std::vector<unsigned char>(1000, 7));
  std::vector<unsigned char> cut(packed.begin(), packed.end() - 3);
  EXPECT_THROW(zlib_decompress(cut), Error);
  std::vector<unsigned char> flipped = packed;
  flipped[packed.size() / 2] ^= 0xff;
  EXPECT_THROW(zlib_decompress(flipped), Error);
  GridPacker packer;
  const PackedArray a = packer.add_float32({1.0f, 2.0f});
  EXPECT_THROW(unpack_float32(std::vector<unsigned char>(4), a), Error);  // runs past the end
}

}  // namespace
}  // namespace hazmap::eval
