#include "hazmap/io/ply.hpp"

#include <cstring>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {
namespace {

/// Appends a float as 4 little-endian bytes, whatever the host's byte order.
void put_float(std::vector<unsigned char>& out, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>((bits >> (8 * i)) & 0xFF));
}

}  // namespace

std::vector<unsigned char> encode_ply(const PointCloud& cloud,
                                      const std::vector<std::uint8_t>* intensity,
                                      const std::vector<std::string>& comments) {
  if (intensity && intensity->size() != cloud.size())
    throw Error("PLY: " + std::to_string(intensity->size()) + " intensities for " +
                std::to_string(cloud.size()) + " points");
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : comments) {
    if (c.find_first_of("\r\n") != std::string::npos)
      throw Error("PLY: header comment holds a line break");
    header += "comment " + c + "\n";
  }
  header += "element vertex " + std::to_string(cloud.size()) + "\n";
  for (const char* name : {"x", "y", "z", "cov_xx", "cov_xy", "cov_xz", "cov_yy", "cov_yz", "cov_zz"})
    header += std::string("property float ") + name + "\n";
  if (intensity) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "end_header\n";

  const size_t vertex_bytes = 9 * 4 + (intensity ? 3 : 0);
  std::vector<unsigned char> out(header.begin(), header.end());
  out.reserve(out.size() + cloud.size() * vertex_bytes);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Measurement& m = cloud[i];
    for (float v : {m.p_W.x(), m.p_W.y(), m.p_W.z(), m.cov_xx, m.cov_xy, m.cov_xz, m.cov_yy,
                    m.cov_yz, m.cov_zz})
      put_float(out, v);
    if (intensity) out.insert(out.end(), 3, (*intensity)[i]);
  }
  return out;
}

void write_ply(const std::filesystem::path& path, const PointCloud& cloud,
               const std::vector<std::uint8_t>* intensity,
               const std::vector<std::string>& comments) {
  try {
    write_file_atomically(path, encode_ply(cloud, intensity, comments));
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.rfind("PLY:", 0) == 0) throw Error(path.string() + ": " + what);
    throw;
  }
}

}  // namespace hazmap
