#include "hazmap/io/sequence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/images.hpp"

namespace fs = std::filesystem;

namespace hazmap {
namespace {

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".png";
}

std::map<std::string, fs::path> list_images(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": image folder not found");
  std::map<std::string, fs::path> images;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && is_image(entry.path()))
      images.emplace(entry.path().stem().string(), entry.path());
  }
  return images;
}

/// poses.txt parsed; Error naming the file when it cannot be read.
std::vector<std::pair<std::string, FramePose>> read_pose_file(const fs::path& poses_path) {
  std::ifstream in(poses_path);
  if (!in) throw Error(poses_path.string() + ": cannot open pose file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_poses(text.str(), poses_path.string());
}

/// FNV-1a, 64 bit (Fowler, Noll, Vo): tiny, stable across platforms and versions, and
/// enough to tell two pose files apart (it guards against mistakes, not adversaries).
class Fnv1a64 {
 public:
  void bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * kPrime;
  }
  /// The value rounded to a multiple of `quantum`, as 8 bytes least significant first
  /// (the same on any host). Hashed as a double, so no value overflows an integer.
  void rounded(double value, double quantum) {
    const double q = std::nearbyint(value / quantum) + 0.0;  // + 0.0: -0 hashes as 0
    std::uint64_t bits = 0;
    std::memcpy(&bits, &q, sizeof bits);
    unsigned char le[sizeof bits];
    for (size_t i = 0; i < sizeof bits; ++i) le[i] = static_cast<unsigned char>(bits >> (8 * i));
    bytes(le, sizeof le);
  }
  std::uint64_t value() const { return hash_; }

 private:
  static constexpr std::uint64_t kOffsetBasis = 14695981039346656037ull;
  static constexpr std::uint64_t kPrime = 1099511628211ull;
  std::uint64_t hash_ = kOffsetBasis;
};

}  // namespace

std::uint64_t poses_fingerprint(std::vector<std::pair<std::string, FramePose>> poses) {
  std::sort(poses.begin(), poses.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Fnv1a64 h;
  for (const auto& [name, pose] : poses) {
    h.bytes(name.data(), name.size());
    h.bytes("", 1);  // a NUL ends the name: "ab"+"c" and "a"+"bc" differ
    const Eigen::Vector3d p = pose.T_W_B.translation();
    for (int i = 0; i < 3; ++i) h.rounded(p[i], kFingerprintQuantumM);
    const Eigen::Matrix3d R = pose.T_W_B.linear();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) h.rounded(R(r, c), kFingerprintQuantumRad);
    const unsigned char has_noise = pose.has_noise ? 1 : 0;
    h.bytes(&has_noise, 1);
    if (pose.has_noise) {
      h.rounded(pose.noise.sx_m, kFingerprintQuantumM);
      h.rounded(pose.noise.sy_m, kFingerprintQuantumM);
      h.rounded(pose.noise.sz_m, kFingerprintQuantumM);
      h.rounded(pose.noise.syaw_rad, kFingerprintQuantumRad);
    }
  }
  return h.value();
}

std::uint64_t poses_fingerprint(const std::vector<SequenceFrame>& frames) {
  std::vector<std::pair<std::string, FramePose>> poses;
  poses.reserve(frames.size());
  for (const SequenceFrame& f : frames) poses.emplace_back(f.name, f.pose);
  return poses_fingerprint(std::move(poses));
}

std::uint64_t fingerprint_of(const Sequence& sequence) {
  return sequence.poses_fingerprint ? *sequence.poses_fingerprint
                                    : poses_fingerprint(sequence.frames);
}

std::uint64_t read_poses_fingerprint(const fs::path& sequence_dir) {
  return poses_fingerprint(read_pose_file(sequence_dir / "poses.txt"));
}

fs::path absolute_folder(const fs::path& dir) {
  fs::path p = fs::absolute(dir).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

std::string fingerprint_hex(std::uint64_t fingerprint) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(fingerprint));
  return text;
}

std::optional<std::uint64_t> parse_fingerprint_hex(const std::string& text) {
  constexpr size_t kDigits = 16;
  if (text.size() != kDigits ||
      !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isxdigit(c); }))
    return std::nullopt;
  return static_cast<std::uint64_t>(std::strtoull(text.c_str(), nullptr, 16));
}

std::string check_position(double x_m, double y_m, double z_m) {
  const double v[3] = {x_m, y_m, z_m};
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(v[i]) <= kMaxPositionM)) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "position %c = %g m is implausible: |x|, |y|, |z| must be <= 1e7 m "
                    "(10 000 km, beyond any traverse)",
                    "xyz"[i], v[i]);
      return text;
    }
  return {};
}

std::vector<std::pair<std::string, FramePose>> parse_poses(const std::string& text,
                                                           const std::string& source) {
  std::vector<std::pair<std::string, FramePose>> poses;
  std::set<std::string> seen;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string tok; fields >> tok;) tokens.push_back(tok);
    if (tokens.empty()) continue;
    auto fail = [&](const std::string& what) {
      return Error(source + ":" + std::to_string(line_no) + ": " + what);
    };
    if (tokens.size() != 9 && tokens.size() != 13)
      throw fail("expected 9 fields (name t x y z qx qy qz qw) or 13 (+ sx sy sz syaw), found " +
                 std::to_string(tokens.size()));
    double v[12];
    for (size_t i = 1; i < tokens.size(); ++i) {
      char* end = nullptr;
      v[i - 1] = std::strtod(tokens[i].c_str(), &end);
      if (*end != '\0' || !std::isfinite(v[i - 1]))
        throw fail("field " + std::to_string(i + 1) + " is not a number: '" + tokens[i] + "'");
    }
    const std::string& name = tokens[0];
    if (!seen.insert(name).second) throw fail("second pose for frame '" + name + "'");
    FramePose pose;
    pose.t_s = v[0];
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // file order qx qy qz qw
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw fail("quaternion of frame '" + name + "' is not a unit quaternion (norm " +
                 std::to_string(q.norm()) + ")");
    pose.T_W_B.linear() = q.normalized().toRotationMatrix();
    const std::string position = check_position(v[1], v[2], v[3]);
    if (!position.empty()) throw fail("frame '" + name + "': " + position);
    pose.T_W_B.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    if (tokens.size() == 13) {
      for (int i = 8; i < 12; ++i)
        if (v[i] < 0) throw fail("pose noise of frame '" + name + "' must be >= 0");
      pose.noise = PoseNoise{v[8], v[9], v[10], v[11]};
      pose.has_noise = true;
    }
    poses.emplace_back(name, pose);
  }
  return poses;
}

Sequence load_sequence(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": sequence folder not found");
  Sequence seq;
  seq.dir = dir;
  seq.calibration = load_stereo_calibration(dir / "calibration.yaml");

  const auto lefts = list_images(dir / "left");
  const auto rights = list_images(dir / "right");
  if (lefts.empty()) throw Error((dir / "left").string() + ": no PNG images");
  for (const auto& [name, path] : lefts)
    if (!rights.count(name))
      throw Error((dir / "right" / (name + ".png")).string() + ": missing (right image of " +
                  path.string() + ")");
  for (const auto& [name, path] : rights)
    if (!lefts.count(name))
      throw Error((dir / "left" / (name + ".png")).string() + ": missing (left image of " +
                  path.string() + ")");

  const fs::path poses_path = dir / "poses.txt";
  const auto records = read_pose_file(poses_path);
  seq.poses_fingerprint = poses_fingerprint(records);
  seq.poses_source = poses_path.string();
  std::map<std::string, FramePose> poses(records.begin(), records.end());

  for (const auto& [name, left_path] : lefts) {
    const auto it = poses.find(name);
    if (it == poses.end())
      throw Error(poses_path.string() + ": no pose for frame '" + name + "' (" +
                  left_path.string() + ")");
    seq.frames.push_back(SequenceFrame{name, left_path, rights.at(name), it->second});
  }
  return seq;
}

void check_frame_images(const std::vector<SequenceFrame>& frames,
                        const StereoCalibration& calibration) {
  const int w = calibration.image_width, h = calibration.image_height;
  for (const SequenceFrame& f : frames) {
    const PngHeader left = read_png_header(f.left_path);
    const PngHeader right = read_png_header(f.right_path);
    for (const auto* side : {&left, &right})
      if (side->width != w || side->height != h)
        throw Error((side == &left ? f.left_path : f.right_path).string() + ": image is " +
                    std::to_string(side->width) + "x" + std::to_string(side->height) +
                    ", the calibration says " + std::to_string(w) + "x" + std::to_string(h));
    // The grey conversion needs the pair in one depth and channel layout.
    if (left.decoded_bits() != right.decoded_bits() || left.colour_type != right.colour_type)
      throw Error(f.right_path.string() + ": " + right.describe() + ", but its left image " +
                  f.left_path.string() + " is " + left.describe() +
                  " (a pair must agree in bit depth and colour type)");
  }
}

std::vector<SequenceFrame> select_frames(const std::vector<SequenceFrame>& frames,
                                         const std::string& range) {
  const auto colon = range.find(':');
  if (colon == std::string::npos) throw Error("--frames " + range + ": expected A:B");
  const long n = static_cast<long>(frames.size());
  auto parse = [&](const std::string& s, long fallback) {
    if (s.empty()) return fallback;
    char* end = nullptr;
    long v = std::strtol(s.c_str(), &end, 10);
    if (*end != '\0') throw Error("--frames " + range + ": '" + s + "' is not an integer");
    if (v < 0) v += n;
    return std::clamp(v, 0L, n);
  };
  const long first = parse(range.substr(0, colon), 0);
  const long last = parse(range.substr(colon + 1), n);
  if (first >= last)
    throw Error("--frames " + range + ": selects no frame of " + std::to_string(n));
  return std::vector<SequenceFrame>(frames.begin() + first, frames.begin() + last);
}

}  // namespace hazmap
