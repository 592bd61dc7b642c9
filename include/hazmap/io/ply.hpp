#pragma once
// Point clouds as binary PLY (`hazmap stereo`, SPEC 13), readable by CloudCompare,
// MeshLab and Open3D. Layout: `format binary_little_endian 1.0`, one `vertex` element
// with float x y z [m, world frame], float cov_xx cov_xy cov_xz cov_yy cov_yz cov_zz
// [m^2, the upper triangle of the world-frame covariance] (CloudCompare shows them as
// scalar fields) and, when intensities are given, uchar red green blue (grey).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/map/measurement.hpp"

namespace hazmap {

/// The PLY bytes. `intensity` (optional): one grey value per point, same length as
/// `cloud`; `comments`: header comment lines (no line breaks). Throws Error on a
/// length mismatch or a comment with a line break.
std::vector<unsigned char> encode_ply(const PointCloud& cloud,
                                      const std::vector<std::uint8_t>* intensity = nullptr,
                                      const std::vector<std::string>& comments = {});

/// encode_ply() written atomically. Throws Error naming the file.
void write_ply(const std::filesystem::path& path, const PointCloud& cloud,
               const std::vector<std::uint8_t>* intensity = nullptr,
               const std::vector<std::string>& comments = {});

}  // namespace hazmap
