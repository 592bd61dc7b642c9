#include "hazmap/io/euroc.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>
#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "yaml_access.hpp"

namespace fs = std::filesystem;

namespace hazmap {
namespace {

std::string read_text(const fs::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// PNG files of a folder by stem.
std::map<std::string, fs::path> png_files(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": image folder not found");
  std::map<std::string, fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".png") out.emplace(e.path().stem().string(), e.path());
  return out;
}

struct StampedPose {
  std::int64_t t_ns = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

std::vector<StampedPose> read_pose_csv(const fs::path& path) {
  std::istringstream in(read_text(path, "pose file"));
  std::vector<StampedPose> poses;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#')
      continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    auto fail = [&](const std::string& what) {
      return Error(path.string() + ":" + std::to_string(line_no) + ": " + what);
    };
    if (fields.size() < 8)
      throw fail("expected t_ns, x, y, z, qw, qx, qy, qz; found " + std::to_string(fields.size()) +
                 " fields");
    StampedPose pose;
    char* end = nullptr;
    pose.t_ns = std::strtoll(fields[0].c_str(), &end, 10);
    if (end == fields[0].c_str() || (*end != '\0' && *end != ' '))
      throw fail("timestamp '" + fields[0] + "' is not an integer (nanoseconds)");
    double v[7];
    for (int i = 0; i < 7; ++i) {
      v[i] = std::strtod(fields[static_cast<size_t>(i) + 1].c_str(), &end);
      if (end == fields[static_cast<size_t>(i) + 1].c_str())
        throw fail("field " + std::to_string(i + 2) + " is not a number");
    }
    const std::string position = check_position(v[0], v[1], v[2]);
    if (!position.empty()) throw fail(position);
    pose.p = Eigen::Vector3d(v[0], v[1], v[2]);
    pose.q = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);  // file order qw qx qy qz
    if (std::abs(pose.q.norm() - 1.0) > 1e-3)
      throw fail("quaternion is not a unit quaternion (norm " + std::to_string(pose.q.norm()) + ")");
    pose.q.normalize();
    if (!poses.empty() && pose.t_ns <= poses.back().t_ns)
      throw fail("timestamps must increase");
    poses.push_back(pose);
  }
  return poses;
}

/// Pose at t: an exact sample, or interpolated between bracketing samples at most
/// max_gap_ns apart. False when there is none.
bool pose_at(const std::vector<StampedPose>& poses, std::int64_t t_ns, std::int64_t max_gap_ns,
             Pose3d& out) {
  const auto it = std::lower_bound(poses.begin(), poses.end(), t_ns,
                                   [](const StampedPose& p, std::int64_t t) { return p.t_ns < t; });
  if (it != poses.end() && it->t_ns == t_ns) {
    out.setIdentity();
    out.linear() = it->q.toRotationMatrix();
    out.translation() = it->p;
    return true;
  }
  if (it == poses.begin() || it == poses.end()) return false;
  const StampedPose& a = *(it - 1);
  const StampedPose& b = *it;
  if (b.t_ns - a.t_ns > max_gap_ns) return false;
  const double s = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  out.setIdentity();
  out.linear() = a.q.slerp(s, b.q).toRotationMatrix();
  out.translation() = (1.0 - s) * a.p + s * b.p;
  return true;
}

std::string fixed(double v, const char* format) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

EurocCamera read_euroc_camera(const fs::path& path) {
  std::string text = read_text(path, "camera file");
  // Kalibr/OpenCV files start with "%YAML:1.0", which yaml-cpp rejects: blank it out,
  // keeping the line count so that messages still name the right line.
  if (text.rfind("%YAML:", 0) == 0) text[0] = '#';
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw Error(path.string() + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML: " + e.msg);
  }
  YamlMap top(root, "", path.string());
  EurocCamera cam;
  std::string model = "pinhole";
  top.get("camera_model", model);
  if (model != "pinhole") top.fail("camera_model", "'" + model + "' is not supported (pinhole)");
  std::vector<double> resolution, intrinsics;
  if (!top.has("resolution")) top.fail("resolution", "missing required key");
  top.get("resolution", resolution, 2);
  // Range-checked before the conversion (a double beyond int's range is undefined to convert).
  for (const double side : resolution)
    if (!(side >= 1 && side <= 1e6) || side != std::floor(side))
      top.fail("resolution", "expected [width, height] in whole pixels in [1, 1000000]");
  cam.width_px = static_cast<int>(resolution[0]);
  cam.height_px = static_cast<int>(resolution[1]);
  if (!top.has("intrinsics")) top.fail("intrinsics", "missing required key");
  top.get("intrinsics", intrinsics, 4);
  cam.intrinsics.K << intrinsics[0], 0, intrinsics[2], 0, intrinsics[1], intrinsics[3], 0, 0, 1;
  std::string distortion = "radial-tangential";
  top.get("distortion_model", distortion);
  if (distortion == "radial-tangential" || distortion == "radtan") {
    if (top.has("distortion_coefficients"))
      top.get("distortion_coefficients", cam.intrinsics.D, 4);
  } else if (distortion != "none") {
    top.fail("distortion_model", "'" + distortion + "' is not supported (radial-tangential)");
  }
  if (!top.has("T_BS")) top.fail("T_BS", "missing required key");
  YamlMap t = top.child("T_BS");
  std::vector<double> data;
  if (!t.has("data")) t.fail("data", "missing required key");
  t.get("data", data, 16);
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = data[static_cast<size_t>(4 * r + c)];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if (!R.isUnitary(1e-4) || R.determinant() < 0 ||
      !M.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)))
    t.fail("data", "is not a rigid transform");
  // Re-orthonormalise: the file's 12 digits leave R a few 1e-9 off a rotation.
  cam.T_B_S.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  cam.T_B_S.translation() = M.topRightCorner<3, 1>();
  return cam;
}

StereoCalibration euroc_stereo_calibration(const fs::path& mav0) {
  const EurocCamera left = read_euroc_camera(mav0 / "cam0" / "sensor.yaml");
  const EurocCamera right = read_euroc_camera(mav0 / "cam1" / "sensor.yaml");
  if (left.width_px != right.width_px || left.height_px != right.height_px)
    throw Error((mav0 / "cam1" / "sensor.yaml").string() + ": key 'resolution': differs from cam0's");
  StereoCalibration c;
  c.image_width = left.width_px;
  c.image_height = left.height_px;
  c.left = left.intrinsics;
  c.right = right.intrinsics;
  const Pose3d T_C1_C0 = right.T_B_S.inverse() * left.T_B_S;
  c.R = T_C1_C0.linear();
  c.T = T_C1_C0.translation();
  c.T_B_C = left.T_B_S;
  validate(c, (mav0 / "cam0" / "sensor.yaml").string());
  return c;
}

fs::path find_euroc_mav0(const fs::path& dir) {
  for (const fs::path& candidate : {dir / "mav0", dir})
    if (fs::is_directory(candidate / "cam0") && fs::is_directory(candidate / "cam1")) return candidate;
  return {};
}

Sequence load_euroc_sequence(const fs::path& dir, const EurocOptions& options) {
  const fs::path mav0 = find_euroc_mav0(dir);
  if (mav0.empty())
    throw Error(dir.string() + ": not an EuRoC folder (expected mav0/cam0 and mav0/cam1)");
  Sequence seq;
  seq.dir = mav0;
  seq.calibration = euroc_stereo_calibration(mav0);

  fs::path poses_path = options.poses_csv;
  EurocPoseFrame frame = options.poses_frame;
  if (poses_path.empty()) {
    const fs::path gt = mav0 / "state_groundtruth_estimate0" / "data.csv";
    if (fs::is_regular_file(gt)) {
      poses_path = gt;
      frame = EurocPoseFrame::body;
    }
  }
  std::vector<StampedPose> poses;
  if (!poses_path.empty()) {
    poses = read_pose_csv(poses_path);
  } else if (!options.identity_poses) {
    throw Error(mav0.string() + ": no pose file (mav0/state_groundtruth_estimate0/data.csv); "
                                "give one with --poses CSV");
  }
  seq.poses_source = poses_path.string();
  seq.poses_assumed_identity = poses_path.empty();
  const Pose3d T_C_B = seq.calibration.T_B_C.inverse();

  const auto lefts = png_files(mav0 / "cam0" / "data");
  const auto rights = png_files(mav0 / "cam1" / "data");
  size_t unpaired = 0, without_pose = 0;
  for (const auto& [name, left_path] : lefts) {
    const auto right = rights.find(name);
    if (right == rights.end()) {
      ++unpaired;
      continue;
    }
    SequenceFrame f;
    f.name = name;
    f.left_path = left_path;
    f.right_path = right->second;
    char* end = nullptr;
    const std::int64_t t_ns = std::strtoll(name.c_str(), &end, 10);
    if (*end != '\0') throw Error(left_path.string() + ": image name is not a timestamp in ns");
    f.pose.t_s = static_cast<double>(t_ns) * 1e-9;
    if (!poses_path.empty()) {
      Pose3d T_W_X;
      if (!pose_at(poses, t_ns, options.max_pose_gap_ns, T_W_X)) {
        ++without_pose;
        continue;
      }
      f.pose.T_W_B = frame == EurocPoseFrame::body ? T_W_X : T_W_X * T_C_B;
    }
    seq.frames.push_back(f);
  }
  unpaired += std::count_if(rights.begin(), rights.end(),
                            [&](const auto& r) { return !lefts.count(r.first); });
  spdlog::info("EuRoC {}: {} frames{}{}", mav0.string(), seq.frames.size(),
               unpaired ? ", " + std::to_string(unpaired) + " unpaired images skipped" : "",
               without_pose ? ", " + std::to_string(without_pose) + " frames without a pose skipped"
                            : "");
  if (seq.frames.empty())
    throw Error(mav0.string() + ": no stereo pair with a pose" +
                (poses_path.empty() ? "" : " in " + poses_path.string()));
  // The poses actually used (interpolated, in the body frame): what import_euroc writes
  // to poses.txt, so a run in place and a run of the import fingerprint alike.
  seq.poses_fingerprint = poses_fingerprint(seq.frames);
  return seq;
}

size_t import_euroc(const fs::path& src, const fs::path& dst, const EurocOptions& options,
                    const std::function<void()>& before_writing) {
  const Sequence seq = load_euroc_sequence(src, options);
  std::string poses = "# name t x y z qx qy qz qw   (T_W_B; imported from EuRoC " +
                      seq.dir.string() + ")\n";
  for (const SequenceFrame& f : seq.frames) {
    const Eigen::Quaterniond q(f.pose.T_W_B.linear());
    const Eigen::Vector3d p = f.pose.T_W_B.translation();
    poses += f.name + " " + fixed(f.pose.t_s, "%.9f");
    for (double v : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()}) poses += " " + fixed(v, "%.17g");
    poses += "\n";
  }
  // SRC is read and checked: only now may the caller clear an earlier import (--overwrite).
  if (before_writing) before_writing();
  // poses.txt first: its first line marks DST as an import, even one stopped early.
  write_file_atomically(dst / "poses.txt", poses);
  save_stereo_calibration(dst / "calibration.yaml", seq.calibration,
                          "imported from EuRoC " + seq.dir.string() +
                              " (cam0 = left, cam1 = right; body = EuRoC's IMU frame)");
  for (const SequenceFrame& f : seq.frames) {
    const auto bytes = [](const fs::path& p) {
      const std::string text = read_text(p, "image");
      return std::vector<unsigned char>(text.begin(), text.end());
    };
    write_file_atomically(dst / "left" / (f.name + ".png"), bytes(f.left_path));
    write_file_atomically(dst / "right" / (f.name + ".png"), bytes(f.right_path));
  }
  return seq.frames.size();
}

}  // namespace hazmap
