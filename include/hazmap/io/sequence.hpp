#pragma once
// A stereo sequence folder (SPEC 2):
//   SEQ/left/<name>.png, SEQ/right/<name>.png   pairs matched by identical name
//   SEQ/calibration.yaml
//   SEQ/poses.txt    name t x y z qx qy qz qw [sx sy sz syaw]   ('#' starts a comment)
// load_sequence checks everything up front, so a run never stops half-way through
// because of a missing file.

#include <cstdint>
#include <filesystem>
#include <optional>
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
  /// poses_fingerprint() of the sequence's poses, set by the loaders: load_sequence over
  /// every record of poses.txt (frames without images included), load_euroc_sequence
  /// over the poses of the frames it keeps (what import_euroc writes to poses.txt). Empty
  /// for a Sequence assembled in code: fingerprint_of(sequence) then uses `frames`.
  std::optional<std::uint64_t> poses_fingerprint;
  /// The file the poses came from, for messages ("" for a Sequence assembled in code).
  std::string poses_source;
  /// No pose source at all (an EuRoC folder without ground truth, read with
  /// EurocOptions::identity_poses): every frame at the identity, W = B.
  bool poses_assumed_identity = false;
};

/// Parses poses.txt content; `source` names the file in messages ("<source>:<line>: ...").
/// Returns (name, pose) in file order; rejects duplicate names.
std::vector<std::pair<std::string, FramePose>> parse_poses(const std::string& text,
                                                           const std::string& source);

/// Fingerprints tell `hazmap evaluate` whether a run was made from the sequence it is
/// given (summary.json records the run's). Positions, orientations and pose noise are
/// rounded to these quanta first, so that one trajectory written by two writers (EuRoC
/// read in place, and the poses.txt import_euroc writes from it with %.17g quaternions)
/// fingerprints alike, while any change that could move a map cell does not: a
/// micrometre, or a microradian, is far below the finest map resolution.
constexpr double kFingerprintQuantumM = 1e-6;
constexpr double kFingerprintQuantumRad = 1e-6;

/// FNV-1a (64 bit) over the poses sorted by name: each name, its position, its rotation
/// matrix (not the quaternion: q and -q are one rotation) and its noise when given, all
/// rounded to the quanta above. Timestamps are left out: the mapping does not use them,
/// names identify the frames, and EuRoC's nanosecond times do not survive a round trip
/// through seconds in a double. Independent of the order of `poses`.
std::uint64_t poses_fingerprint(std::vector<std::pair<std::string, FramePose>> poses);

/// The same over a sequence's frames (their names and poses).
std::uint64_t poses_fingerprint(const std::vector<SequenceFrame>& frames);

/// `sequence.poses_fingerprint`, or else the fingerprint of its frames.
std::uint64_t fingerprint_of(const Sequence& sequence);

/// The fingerprint of DIR/poses.txt as load_sequence(DIR) records it, reading nothing
/// else (a sequence whose images were deleted after its runs still has one). Throws
/// Error naming the file when it is missing or malformed.
std::uint64_t read_poses_fingerprint(const std::filesystem::path& sequence_dir);

/// 16 lower-case hexadecimal digits, as summary.json stores a fingerprint (a JSON number
/// would lose bits beyond 2^53 in most readers).
std::string fingerprint_hex(std::uint64_t fingerprint);

/// Parses fingerprint_hex()'s form; nullopt when `text` is not 16 hexadecimal digits.
std::optional<std::uint64_t> parse_fingerprint_hex(const std::string& text);

/// A folder as summary.json records it and `hazmap evaluate` compares it: absolute (a
/// relative path means nothing once the shell has moved on), lexically normal, without
/// a trailing separator ("./seq/" run from /data is /data/seq).
std::filesystem::path absolute_folder(const std::filesystem::path& dir);

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
