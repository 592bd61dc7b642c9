#include "hazmap/io/calibration_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/opencv_calibration.hpp"
#include "io/yaml_access.hpp"

namespace hazmap {
namespace {

Eigen::Matrix3d matrix3(const std::vector<double>& v) {
  Eigen::Matrix3d m;
  m << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
  return m;
}

CameraIntrinsics parse_camera(YamlMap m) {
  CameraIntrinsics cam;
  std::vector<double> k;
  if (!m.has("K")) m.fail("K", "missing required key");
  m.get("K", k, 9);
  cam.K = matrix3(k);
  if (m.has("D")) {
    const YAML::Node d = m.raw("D");
    if (!d.IsSequence() || !(d.size() == 0 || d.size() == 4 || d.size() == 5 || d.size() == 8 ||
                             d.size() == 12 || d.size() == 14))
      m.fail("D", "expected a list of 0, 4, 5, 8, 12 or 14 numbers");
    std::vector<double> dist;
    m.get("D", dist, d.size());
    cam.D = dist;
  }
  m.finish();
  return cam;
}

/// {translation: [x, y, z], rpy_deg: [r, p, y] | quaternion: [qx, qy, qz, qw]}.
Pose3d parse_pose(YamlMap b, BodyPoseSource* source = nullptr) {
  std::vector<double> tr{0, 0, 0};
  b.get("translation", tr, 3);
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  if (b.has("rpy_deg") && b.has("quaternion"))
    b.fail("quaternion", "give either rpy_deg or quaternion, not both");
  if (b.has("rpy_deg")) {
    std::vector<double> rpy;
    b.get("rpy_deg", rpy, 3);
    const double d2r = M_PI / 180.0;
    rot = rotation_from_rpy(rpy[0] * d2r, rpy[1] * d2r, rpy[2] * d2r);
    if (source != nullptr) *source = BodyPoseSource::rpy_deg;
  } else if (b.has("quaternion")) {
    std::vector<double> q;
    b.get("quaternion", q, 4);
    const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);  // stored scalar last
    if (std::abs(quat.norm() - 1.0) > 1e-3)
      b.fail("quaternion", "is not a unit quaternion (norm " + std::to_string(quat.norm()) + ")");
    rot = quat.normalized().toRotationMatrix();
    if (source != nullptr) *source = BodyPoseSource::quaternion;
  }
  b.finish();
  Pose3d pose = Pose3d::Identity();
  pose.linear() = rot;
  pose.translation() = Eigen::Vector3d(tr[0], tr[1], tr[2]);
  return pose;
}

Eigen::Vector3d vector3(YamlMap& m, const std::string& key) {
  std::vector<double> v;
  if (!m.has(key)) m.fail(key, "missing required key");
  m.get(key, v, 3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

/// One camera's JPL model: C A H V, + O R (cahvor), + E type [parameter] (cahvore), or
/// {pds_label: FILE} (relative to the calibration file's folder).
CahvoreModel parse_model(YamlMap m, CahvoreKind kind, const std::string& side,
                         const std::filesystem::path& folder) {
  if (m.has("pds_label")) {
    std::string file;
    m.get("pds_label", file);
    m.finish();
    const std::filesystem::path path =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : folder / file;
    CahvoreModel model = read_pds_camera_model(path);
    if (model.kind != kind)
      m.fail("pds_label", path.string() + " holds a " + cahvore_kind_name(model.kind) +
                              " model, camera_model says " + cahvore_kind_name(kind));
    return model;
  }
  CahvoreModel model;
  model.kind = kind;
  model.C = vector3(m, "C");
  model.A = vector3(m, "A");
  model.H = vector3(m, "H");
  model.V = vector3(m, "V");
  model.O = model.A;
  if (kind != CahvoreKind::cahv) {
    model.O = vector3(m, "O");
    model.R = vector3(m, "R");
  }
  if (kind == CahvoreKind::cahvore) {
    model.E = vector3(m, "E");
    m.require("type", model.type);
    if (model.type == 3) m.require("parameter", model.parameter);
    else m.get("parameter", model.parameter);
  }
  m.finish();
  validate(model, m.source() + ": " + side);
  return model;
}

std::string vec(const Eigen::Vector3d& v);

/// OpenCV's FileStorage writes "%YAML:1.0" (not valid YAML 1.2 for yaml-cpp) or XML.
bool is_opencv_file_storage(const std::string& text) {
  const auto start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos) return false;
  return text.compare(start, 6, "%YAML:") == 0 || text.compare(start, 5, "<?xml") == 0;
}

std::string number(double v) { return printf_double(v, "%.17g"); }

std::string list(const double* v, size_t n) {
  std::string out = "[";
  for (size_t i = 0; i < n; ++i) out += (i ? ", " : "") + number(v[i]);
  return out + "]";
}

std::string camera_line(const char* name, const CameraIntrinsics& cam) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> K = cam.K;
  return std::string(name) + ": {K: " + list(K.data(), 9) + ", D: " + list(cam.D.data(), cam.D.size()) +
         "}\n";
}

std::string vec(const Eigen::Vector3d& v) { return list(v.data(), 3); }

}  // namespace

std::string format_stereo_calibration(const StereoCalibration& c, const std::string& comment) {
  std::string out;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out += "# " + line + "\n";
  out += "image_width: " + std::to_string(c.image_width) + "\n";
  out += "image_height: " + std::to_string(c.image_height) + "\n";
  if (!c.models.empty()) {
    out += std::string("camera_model: ") + cahvore_kind_name(c.models[0].kind) + "\n";
    for (int i = 0; i < 2; ++i) {
      const CahvoreModel& m = c.models[static_cast<size_t>(i)];
      out += std::string(i == 0 ? "left" : "right") + ": {C: " + vec(m.C) + ", A: " + vec(m.A) +
             ", H: " + vec(m.H) + ", V: " + vec(m.V);
      if (m.kind != CahvoreKind::cahv) out += ", O: " + vec(m.O) + ", R: " + vec(m.R);
      if (m.kind == CahvoreKind::cahvore)
        out += ", E: " + vec(m.E) + ", type: " + std::to_string(m.type) +
               ", parameter: " + number(m.parameter);
      out += "}\n";
    }
    const Eigen::Quaterniond q(c.T_B_M.linear());
    const double quat[4] = {q.x(), q.y(), q.z(), q.w()};
    out += "T_body_model: {translation: " + list(c.T_B_M.translation().data(), 3) +
           ", quaternion: " + list(quat, 4) + "}\n";
    return out;
  }
  if (c.rectified) out += "rectified: true\n";
  out += camera_line("left", c.left);
  out += camera_line("right", c.right);
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = c.R;
  out += "R: " + list(R.data(), 9) + "   # x_right = R x_left + T\n";
  out += "T: " + list(c.T.data(), 3) + "   # metres\n";
  if (c.body_pose_source == BodyPoseSource::absent) {
    // Not known here (hazmap calibrate sees no rover): a template to fill in, so that a
    // run says it is missing rather than silently looking up from the body origin.
    out += "# T_body_left: {translation: [x, y, z], rpy_deg: [-(90 + pitch_down), 0, -90]}"
           "   # the left camera on the rover (docs/conventions.md)\n";
    return out;
  }
  const Eigen::Quaterniond q(c.T_B_C.linear());
  const double quat[4] = {q.x(), q.y(), q.z(), q.w()};
  out += "T_body_left: {translation: " + list(c.T_B_C.translation().data(), 3) +
         ", quaternion: " + list(quat, 4) + "}\n";
  return out;
}

void save_stereo_calibration(const std::filesystem::path& path, const StereoCalibration& c,
                             const std::string& comment) {
  validate(c, path.string());
  write_file_atomically(path, format_stereo_calibration(c, comment));
}

StereoCalibration load_stereo_calibration(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open calibration file");
  std::ostringstream text;
  text << in.rdbuf();
  if (is_opencv_file_storage(text.str())) return load_opencv_stereo_calibration(path);
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    throw Error(path.string() + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML: " + e.msg);
  }
  const std::string source = path.string();
  reject_duplicate_keys(root, source);
  StereoCalibration c;
  YamlMap top(root, "", source);
  top.require("image_width", c.image_width);
  top.require("image_height", c.image_height);
  std::string model_name = "pinhole";
  top.get("camera_model", model_name);
  if (model_name != "pinhole") {
    // JPL models: both cameras in one frame M; R, T, K and T_body_left follow from them.
    if (model_name != "cahv" && model_name != "cahvor" && model_name != "cahvore")
      top.fail("camera_model", "unknown camera model '" + model_name +
                                   "' (pinhole, cahv, cahvor or cahvore)");
    const CahvoreKind kind = parse_cahvore_kind(model_name, source);
    if (!top.has("left")) top.fail("left", "missing required key");
    if (!top.has("right")) top.fail("right", "missing required key");
    const std::filesystem::path folder = path.parent_path();
    c.models = {parse_model(top.child("left"), kind, "left", folder),
                parse_model(top.child("right"), kind, "right", folder)};
    if (top.has("T_body_model")) c.T_B_M = parse_pose(top.child("T_body_model"));
    top.finish();
    derive_from_models(c, source);
    validate(c, source);
    return c;
  }
  if (!top.has("left")) top.fail("left", "missing required key");
  if (!top.has("right")) top.fail("right", "missing required key");
  c.left = parse_camera(top.child("left"));
  c.right = parse_camera(top.child("right"));
  top.get("rectified", c.rectified);
  std::vector<double> r, t;
  if (top.has("R")) {
    top.get("R", r, 9);
    c.R = matrix3(r);
  } else if (!c.rectified) {
    top.fail("R", "missing required key");
  }
  if (!top.has("T")) top.fail("T", "missing required key");
  top.get("T", t, 3);
  c.T = Eigen::Vector3d(t[0], t[1], t[2]);
  c.body_pose_source = BodyPoseSource::absent;  // unless given (or a bare translation)
  if (top.has("T_body_left")) {
    c.body_pose_source = BodyPoseSource::code;
    c.T_B_C = parse_pose(top.child("T_body_left"), &c.body_pose_source);
  }
  top.finish();
  c.source = source;
  validate(c, source);
  return c;
}

}  // namespace hazmap
