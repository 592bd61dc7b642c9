#pragma once
// Reading a scanned point cloud (`hazmap ground-truth`): x y z in metres, world frame W.
//   *.ply   PLY 1.0, `format ascii` or `binary_little_endian`; the first element must be
//           `vertex` with scalar properties x, y, z (any PLY number type); other vertex
//           properties and later elements (faces) are skipped.
//   other   text, one point per line: x y z [more columns ignored], separated by blanks
//           or commas; blank lines and '#' comments skipped (.xyz, .txt, .asc, .csv).
// Every point must be finite. Errors are one line naming the file and the line (text
// and ASCII PLY) or the vertex index (binary PLY).

#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace hazmap {

/// Reads every point of the file. Throws Error on a missing or unreadable file, a
/// malformed line or header, a non-finite coordinate, a truncated binary body or a
/// cloud without points.
std::vector<Eigen::Vector3d> read_point_cloud(const std::filesystem::path& path);

}  // namespace hazmap
