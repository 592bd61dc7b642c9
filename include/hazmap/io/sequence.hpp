#pragma once
// A stereo sequence folder (SPEC 2):
//   SEQ/left/<name>.png, SEQ/right/<name>.png   pairs matched by identical name
//   SEQ/calibration.yaml
//   SEQ/poses.txt    name t x y z qx qy qz qw [sx sy sz syaw]   ('#' starts a comment)
// load_sequence checks everything up front, so a run never stops half-way through
// because of a missing file.

#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/types.hpp"

namespace hazmap {

/// Largest |x|, |y|, |z| (m) a pose file may give: 10 000 km, beyond any traverse on a
/// planet's surface. A larger position (1e300, say) is a corrupt file, and would overflow
/// the map's cell indices.
constexpr double kMaxPositionM = 1e7;

/// Empty when |x|, |y|, |z| <= kMaxPositionM, otherwise the one-line reason (no source).
std::string check_position(double x_m, double y_m, double z_m);

struct FramePose {
  double t_s = 0.0;
  Pose3d T_W_B = Pose3d::Identity();
  PoseNoise noise;
  bool has_noise = false;
};

struct SequenceFrame {
  std::string name;  ///< image stem, e.g. "000012"
  std::filesystem::path left_path;
  std::filesystem::path right_path;
  FramePose pose;
};

struct Sequence {
  std::filesystem::path dir;
  StereoCalibration calibration;
  std::vector<SequenceFrame> frames;  ///< sorted by name
};

/// Parses poses.txt content; `source` names the file in messages ("<source>:<line>: ...").
/// Returns (name, pose) in file order; rejects duplicate names.
std::vector<std::pair<std::string, FramePose>> parse_poses(const std::string& text,
                                                           const std::string& source);

/// Loads and checks a sequence folder. Throws Error with a one-line message naming the
/// missing or malformed file (a left image without its right partner, a frame without a
/// pose, an unreadable calibration).
Sequence load_sequence(const std::filesystem::path& dir);

/// Checks the PNG headers of every frame's images without decoding pixels (SPEC 2's
/// "checked before the first frame"): each image is a complete PNG (signature, IHDR,
/// IEND), of the calibration's size, and left and right agree in bit depth and colour
/// type. Throws Error naming the image at fault.
void check_frame_images(const std::vector<SequenceFrame>& frames, const StereoCalibration& calibration);

/// Selects frames [first, last) by index in the sorted list, from "A:B", "A:" or ":B"
/// (Python-like; negative indices count from the end). Throws Error on a bad range.
std::vector<SequenceFrame> select_frames(const std::vector<SequenceFrame>& frames,
                                         const std::string& range);

}  // namespace hazmap
