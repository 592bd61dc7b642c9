// Binary PLY output: the header CloudCompare and Open3D read, and the bytes read back.

#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/ply.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

PointCloud three_points() {
  PointCloud cloud(3);
  for (size_t i = 0; i < 3; ++i) {
    const float k = static_cast<float>(i);
    Measurement& m = cloud[i];
    m = Measurement{};
    m.p_W = Eigen::Vector3f(1.5f * k, -0.25f, 3.0f + k);
    m.cov_xx = 1e-6f * (k + 1);
    m.cov_xy = -2e-7f;
    m.cov_xz = 3e-7f;
    m.cov_yy = 4e-6f;
    m.cov_yz = -5e-8f;
    m.cov_zz = 6e-5f * (k + 1);
  }
  return cloud;
}

TEST(Ply, BinaryLittleEndianWithCovarianceAndGrey) {
  testing::TempDir dir;
  const PointCloud cloud = three_points();
  const std::vector<std::uint8_t> grey{10, 128, 255};
  write_ply(dir / "c.ply", cloud, &grey, {"frame W"});
  std::ifstream in(dir / "c.ply", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment frame W\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float cov_xx\nproperty float cov_xy\nproperty float cov_xz\n"
      "property float cov_yy\nproperty float cov_yz\nproperty float cov_zz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  const size_t vertex = 9 * 4 + 3;
  ASSERT_EQ(bytes.size(), header.size() + 3 * vertex);
  for (size_t i = 0; i < 3; ++i) {
    const char* p = bytes.data() + header.size() + i * vertex;
    float v[9];
    std::memcpy(v, p, sizeof v);  // the test host is little-endian (x86, ARM)
    const Measurement& m = cloud[i];
    const float want[9] = {m.p_W.x(), m.p_W.y(), m.p_W.z(), m.cov_xx, m.cov_xy,
                           m.cov_xz, m.cov_yy, m.cov_yz, m.cov_zz};
    for (int k = 0; k < 9; ++k) EXPECT_EQ(v[k], want[k]) << i << "," << k;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(static_cast<std::uint8_t>(p[36 + c]), grey[i]);
  }
}

TEST(Ply, WithoutGreyAndEmpty) {
  const auto bytes = encode_ply(PointCloud{});
  const std::string text(bytes.begin(), bytes.end());
  EXPECT_NE(text.find("element vertex 0\n"), std::string::npos);
  EXPECT_EQ(text.find("red"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 11), "end_header\n");
  const std::vector<std::uint8_t> wrong_length{1};
  EXPECT_THROW(encode_ply(three_points(), &wrong_length), Error);
  EXPECT_THROW(encode_ply(three_points(), nullptr, {"two\nlines"}), Error);
}

}  // namespace
}  // namespace hazmap
