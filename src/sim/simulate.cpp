#include "hazmap/sim/simulate.hpp"


#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "hazmap/core/progress.hpp"

#include "hazmap/core/error.hpp"
#include "hazmap/eval/ground_truth.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/jdem.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// SPEC 11: CADRE OV2311 stereo pair.
constexpr double kCadreWidthPx = 1600.0;
constexpr double kCadreHeightPx = 1300.0;
constexpr double kCadreFocalPx = 671.0;
constexpr double kCadreBaselineM = 0.05;
constexpr double kCadreHeightM = 0.15;
constexpr double kFovTopAboveHorizonDeg = 10.0;

// POLAR Traverse, station "1m" (../shared/data/planetary_analog/README_SOURCE.txt).
constexpr double kPolarSizePx = 2048.0;
constexpr double kPolarFocalPx = 1457.0;
constexpr double kPolarBaselineM = 0.40;
constexpr double kPolarHeightM = 1.30;
constexpr double kPolarPitchDownDeg = 28.0;

// Lunar polar light (apply_lunar_polar_light).
constexpr double kPolarSunElevationDeg = 8.0;
constexpr double kPolarOppositionSurge = 0.3;

// Rounds to 12 significant digits, so that a value survives printing and parsing exactly.
double quantize(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.12g", value);
  return std::strtod(buffer, nullptr);
}

// Shortest text that reads back as the same double ("0.05", "268.4", "0").
std::string num(double value) {
  if (value == 0.0) value = 0.0;  // no "-0"
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string frame_name(int index) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%06d", index);
  return buffer;
}

// Quaternion with qw >= 0 (one of the two equivalent signs, chosen for stable output).
Eigen::Quaterniond canonical(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  return q;
}

std::string list(const std::vector<double>& values) {
  std::string s = "[";
  for (const double v : values) s += (s.size() > 1 ? ", " : "") + num(v);
  return s + "]";
}

std::string camera_yaml(const PinholeCamera& c) {
  const std::string K = list({c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1});
  const auto& d = c.distortion;
  return "{K: " + K + ", D: " + list({d[0], d[1], d[2], d[3], d[4]}) + "}";
}

std::string calibration_yaml(const StereoRig& rig, const std::string& rig_name, double scale) {
  const std::string geometry = rig_name == "polar" ? "POLAR Traverse" : "CADRE";
  const Eigen::Quaterniond q = canonical(rig.T_B_CL.linear());
  const Eigen::Vector3d t = rig.T_B_CL.translation();
  const std::string body = "T_body_left: {translation: " + list({t.x(), t.y(), t.z()}) +
                           ", quaternion: " +
                           list({quantize(q.x()), quantize(q.y()), quantize(q.z()),
                                 quantize(q.w())}) +
                           "}\n";
  std::ostringstream out;
  if (rig.rectified()) {
    out << "# Synthetic rectified stereo pair (hazmap simulate): " << geometry << " geometry at scale "
        << num(scale) << ".\n"
        << "image_width: " << rig.camera.width_px << "\n"
        << "image_height: " << rig.camera.height_px << "\n"
        << "rectified: true                  # ideal pinhole pair: no remapping needed\n"
        << "left:  " << camera_yaml(rig.camera) << "\n"
        << "right: " << camera_yaml(rig.camera_right) << "\n"
        << "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]   # x_right = R x_left + T\n"
        << "T: " << list({-rig.baseline_m, 0, 0}) << "                 # metres\n"
        << body;
    return out.str();
  }
  // x_right = R x_left + T: the inverse of the right camera's pose in the left frame.
  const Pose3d T_CR_CL = rig.T_CL_CR.inverse();
  const Eigen::Matrix3d R = T_CR_CL.linear();
  const Eigen::Vector3d T = T_CR_CL.translation();
  out << "# Synthetic stereo pair (hazmap simulate): " << geometry << " geometry at scale " << num(scale)
      << ", with the true lens\n# distortion and right-camera misalignment; hazmap rectifies it.\n"
      << "image_width: " << rig.camera.width_px << "\n"
      << "image_height: " << rig.camera.height_px << "\n"
      << "rectified: false\n"
      << "left:  " << camera_yaml(rig.camera) << "\n"
      << "right: " << camera_yaml(rig.camera_right) << "\n"
      << "R: "
      << list({quantize(R(0, 0)), quantize(R(0, 1)), quantize(R(0, 2)), quantize(R(1, 0)),
               quantize(R(1, 1)), quantize(R(1, 2)), quantize(R(2, 0)), quantize(R(2, 1)),
               quantize(R(2, 2))})
      << "   # x_right = R x_left + T\n"
      << "T: " << list({quantize(T.x()), quantize(T.y()), quantize(T.z())}) << "   # metres\n"
      << body;
  return out.str();
}

std::string pose_line(const std::string& name, int index, const Pose3d& T_W_B) {
  const Eigen::Vector3d p = T_W_B.translation();
  const Eigen::Quaterniond q = canonical(T_W_B.linear());
  std::ostringstream out;
  out << name << ' ' << index << ' ' << num(p.x()) << ' ' << num(p.y()) << ' ' << num(p.z())
      << ' ' << num(quantize(q.x())) << ' ' << num(quantize(q.y())) << ' ' << num(quantize(q.z()))
      << ' ' << num(quantize(q.w()));
  return out.str();
}

std::string poses_txt(const SimulationOptions& options, const std::vector<Pose3d>& T_W_B,
                      bool true_poses, bool noise_columns) {
  std::ostringstream out;
  out << "# hazmap simulate: scenario " << options.scenario << ", seed " << options.seed
      << ", " << options.frames << " frames, " << num(options.step_m) << " m per frame along a "
      << options.path.kind << " path\n"
      << "# T_W_B: body x forward, y left, z up; origin on the plane of the ground under the "
         "wheels\n";
  if (options.drift.fraction > 0.0) {
    out << (true_poses ? "# TRUE poses (the images were rendered from these)\n"
                       : "# DRIFTED poses: position off by " + num(options.drift.fraction) +
                             " x distance travelled; true poses in poses_true.txt\n");
  }
  out << "# name t x y z qx qy qz qw" << (noise_columns ? " sx sy sz syaw" : "") << "\n";
  for (std::size_t k = 0; k < T_W_B.size(); ++k) {
    out << pose_line(frame_name(static_cast<int>(k)), static_cast<int>(k), T_W_B[k]);
    if (noise_columns) {
      // Drift added since the previous frame, as the standard deviation of SPEC 2/7.
      const double s = k == 0 ? 0.0 : quantize(options.drift.fraction * options.step_m);
      out << ' ' << num(s) << ' ' << num(s) << " 0 0";
    }
    out << '\n';
  }
  return out.str();
}

std::string response_yaml(const CameraResponse& r) {
  return "{gain: " + num(r.gain) + ", exposure: " + num(r.exposure) +
         ", offset_dn: " + num(r.offset_dn) + ", electrons_per_dn: " + num(r.electrons_per_dn) +
         ", vignetting: " + num(r.vignetting) + ", bits: " + std::to_string(r.bits) + "}";
}

// Every lighting, albedo and camera setting, written only when one of them differs from
// the defaults (so sequences rendered the old way keep their simulation.yaml bytes).
std::string lighting_and_cameras_yaml(const SimulationOptions& options) {
  const RenderOptions& r = options.render;
  const RenderOptions d;
  const bool rig_default = options.rig == "cadre";
  const bool lighting_default =
      r.cast_shadows == d.cast_shadows && r.terrain_shadows == d.terrain_shadows &&
      r.ambient == d.ambient && r.albedo_model == d.albedo_model &&
      r.texture_contrast == d.texture_contrast && r.regolith_contrast == d.regolith_contrast &&
      r.regolith_correlation_m == d.regolith_correlation_m &&
      r.opposition_surge == d.opposition_surge &&
      r.opposition_width_deg == d.opposition_width_deg && r.exposure_dn == d.exposure_dn &&
      r.ground_albedo == d.ground_albedo && r.rock_albedo == d.rock_albedo;
  const bool cameras_default = options.left_response.is_identity() &&
                               options.right_response.is_identity() &&
                               options.row_offset_px == 0.0;
  if (rig_default && lighting_default && cameras_default) return "";
  std::ostringstream out;
  out << "rig: " << options.rig << "\n"
      << "lighting: {cast_shadows: " << (r.cast_shadows ? "true" : "false")
      << ", terrain_shadows: " << (r.terrain_shadows ? "true" : "false")
      << ", ambient: " << num(r.ambient) << ", sky: black"
      << ", opposition_surge: " << num(r.opposition_surge)
      << ", opposition_width_deg: " << num(r.opposition_width_deg)
      << ", exposure_dn: " << num(r.exposure_dn) << "}\n"
      << "albedo: {model: " << albedo_model_name(r.albedo_model)
      << ", ground: " << num(r.ground_albedo) << ", rock: " << num(r.rock_albedo);
  if (r.albedo_model == AlbedoModel::regolith) {
    out << ", contrast: " << num(r.regolith_contrast)
        << ", correlation_m: " << num(r.regolith_correlation_m);
  } else {
    out << ", contrast: " << num(r.texture_contrast)
        << ", min_wavelength_m: " << num(r.texture_min_wavelength_m)
        << ", octaves: " << r.texture_octaves;
  }
  out << "}\n"
      << "cameras: {read_noise_dn: " << num(r.noise_sigma_dn)
      << ", row_offset_px: " << num(options.row_offset_px)
      << ",   # row_offset: y_left - y_right of a scene point after rectification\n"
      << "  left: " << response_yaml(options.left_response)
      << ",\n  right: " << response_yaml(options.right_response) << "}\n";
  return out.str();
}

std::string rocks_yaml(const Terrain& terrain) {
  std::ostringstream out;
  out << "rocks:" << (terrain.rocks().empty() ? " []" : "") << "\n";
  for (const Rock& rock : terrain.rocks()) {
    const double top_m =
        terrain.height_m(rock.x_m, rock.y_m) - terrain.ground_height_m(rock.x_m, rock.y_m);
    out << "  - {x: " << num(quantize(rock.x_m)) << ", y: " << num(quantize(rock.y_m))
        << ", radius: " << num(quantize(rock.radius_m))
        << ", buried: " << num(quantize(rock.buried_m)) << ", height: " << num(quantize(top_m))
        << "}\n";
  }
  return out.str();
}

std::string simulation_yaml(const SimulationOptions& options, const Terrain& terrain,
                            const std::vector<Crater>& craters, const StereoRig& rig,
                            double drift_direction_rad) {
  const bool drift = options.drift.fraction > 0.0;
  std::ostringstream out;
  out << "# How this sequence was made (hazmap simulate). Rock heights are above the\n"
      << "# local ground; rocks at least as high as a layer's h_min are hazards.\n"
      << "scenario: " << options.scenario << "\n"
      << "seed: " << options.seed << "\n"
      << "frames: " << options.frames << "\n"
      << "scale: " << num(options.scale) << "\n"
      << "step_m: " << num(options.step_m) << "\n";
  out << "path: {kind: " << options.path.kind;
  if (options.path.kind == "spline") {
    out << ", waypoint_spacing_m: " << num(options.path.waypoint_spacing_m)
        << ", max_turn_deg: " << num(options.path.max_turn_deg);
  }
  out << "}\n"
      << "wheels: {wheelbase_m: " << num(options.wheels.wheelbase_m)
      << ", track_m: " << num(options.wheels.track_m)
      << "}   # body height, roll, pitch: plane through the ground under the wheels (rocks "
         "ignored)\n"
      << "poses: poses.txt\n"
      << "poses_true: " << (drift ? "poses_true.txt" : "poses.txt") << "\n";
  if (drift) {
    out << "drift: {fraction: " << num(options.drift.fraction)
        << ", direction_deg: " << num(quantize(drift_direction_rad * 180.0 / kPi)) << "}\n";
  }
  if (!rig.rectified()) {
    const auto& d = options.rig_errors.distortion;
    const Eigen::Vector3d& a = options.rig_errors.misalignment_rpy_deg;
    const Eigen::Vector3d& m = options.rig_errors.misalignment_m;
    out << "rig_errors: {distortion: " << list({d[0], d[1], d[2], d[3], d[4]})
        << ", misalignment_rpy_deg: " << list({a.x(), a.y(), a.z()})
        << ", misalignment_m: " << list({m.x(), m.y(), m.z()}) << "}\n";
  }
  if (options.scenario == "ramp") out << "ramp_deg: " << num(options.ramp_deg) << "\n";
  if (options.scenario == "sine") {
    out << "sine: {amplitude_m: " << num(options.sine.amplitude_m)
        << ", wavelength_m: " << num(options.sine.wavelength_m)
        << ", direction_deg: " << num(quantize(options.sine.direction_rad * 180.0 / kPi))
        << ", max_slope_deg: " << num(quantize(std::atan(options.sine.max_slope()) * 180.0 / kPi))
        << "}\n";
  }
  if (options.scenario == "rocks" || options.scenario == "craters") {
    const FractalNoiseOptions& n = options.ground_noise;
    out << "ground_noise: {amplitude_m: " << num(n.amplitude_m)
        << ", wavelength_m: " << num(n.wavelength_m) << ", octaves: " << n.octaves
        << ", gain: " << num(n.gain) << "}\n";
  }
  const Heightfield& grid = terrain.detail();
  if (!grid.heights_m.empty()) {
    out << "terrain_grid: {origin: " << list({quantize(grid.origin_x_m), quantize(grid.origin_y_m)})
        << ", resolution_m: " << num(grid.resolution_m) << ", nodes: [" << grid.nodes_x << ", "
        << grid.nodes_y << "]}\n";
  }
  if (options.write_ground_truth) {
    out << "ground_truth: {height: gt_height.jdem, hazard: gt_hazard.jdem}   # hazard: rock "
           "height above the ground, 0 elsewhere (crater walls are ground: see height)\n";
  }
  if (options.write_depth) out << "depth: depth   # <name>.tiff, float32 Z [m] in the left camera\n";
  out << "samples_per_axis: " << options.render.samples_per_axis << "\n"
      << "noise_sigma_dn: " << num(options.render.noise_sigma_dn) << "\n"
      << "sun: {shading: " << (options.render.sun_shading ? "true" : "false")
      << ", elevation_deg: " << num(options.render.sun_elevation_deg)
      << ", azimuth_deg: " << num(options.render.sun_azimuth_deg) << "}\n";
  out << lighting_and_cameras_yaml(options);
  if (!craters.empty()) {
    out << "craters:\n";
    for (const Crater& c : craters) {
      out << "  - {x: " << num(quantize(c.x_m)) << ", y: " << num(quantize(c.y_m))
          << ", radius: " << num(quantize(c.radius_m)) << ", depth: " << num(quantize(c.depth_m))
          << ", rim_height: " << num(quantize(c.rim_height_m)) << "}\n";
    }
  }
  out << rocks_yaml(terrain);
  return out.str();
}

std::vector<unsigned char> encode_png(const cv::Mat& image, int compression) {
  std::vector<unsigned char> bytes;
  check(cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, compression}),
        "simulate: PNG encoding failed");
  return bytes;
}

// Ground-truth grid over [x0, x1] x [y0, y1], cell borders on multiples of the resolution
// (SPEC 1) and an even number of cells per axis, so the centre is a cell corner.
// Independent random streams from the one user seed: the first draws of a mt19937_64.
// New streams are appended, so older ones keep their values.
struct Seeds {
  std::uint64_t terrain = 0;
  std::uint64_t texture = 0;
  std::uint64_t image_noise = 0;
  std::uint64_t path = 0;
  std::uint64_t drift = 0;
};

Seeds derive_seeds(std::uint64_t seed) {
  std::mt19937_64 master(seed);
  Seeds seeds;
  seeds.terrain = master();
  seeds.texture = master();
  seeds.image_noise = master();
  seeds.path = master();
  seeds.drift = master();
  return seeds;
}

// Rotation as it will be read back: quaternion rounded as written, then normalised.
Eigen::Matrix3d as_written(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q = canonical(R);
  const Eigen::Quaterniond q_written(quantize(q.w()), quantize(q.x()), quantize(q.y()),
                                     quantize(q.z()));
  return q_written.normalized().toRotationMatrix();
}

Pose3d pose_as_written(const Pose3d& T) {
  Pose3d out = Pose3d::Identity();
  out.linear() = as_written(T.linear());
  const Eigen::Vector3d t = T.translation();
  out.translation() = Eigen::Vector3d(quantize(t.x()), quantize(t.y()), quantize(t.z()));
  return out;
}

Eigen::Matrix3d rotation_deg(const Eigen::Vector3d& rpy_deg) {
  return rotation_from_rpy(rpy_deg.x() * kPi / 180.0, rpy_deg.y() * kPi / 180.0,
                           rpy_deg.z() * kPi / 180.0);
}

// Horizontal bounding box of the path points.
void path_bounds(const std::vector<PathPoint>& path, Eigen::Vector2d& lo, Eigen::Vector2d& hi) {
  lo = hi = path.front().p_W;
  for (const PathPoint& point : path) {
    lo = lo.cwiseMin(point.p_W);
    hi = hi.cwiseMax(point.p_W);
  }
}

}  // namespace

std::array<double, 5> RigErrors::typical_distortion() { return {-0.08, 0.012, 4e-4, -3e-4, 0.0}; }

Eigen::Vector3d RigErrors::typical_misalignment_rpy_deg() { return {0.3, -0.2, 0.4}; }

Eigen::Vector3d RigErrors::typical_misalignment_m() { return {5e-4, -3e-4, 4e-4}; }

Pose3d StereoRig::T_B_CR() const { return T_B_CL * T_CL_CR; }

bool StereoRig::rectified() const {
  const PinholeCamera& l = camera;
  const PinholeCamera& r = camera_right;
  const bool same_intrinsics = l.width_px == r.width_px && l.height_px == r.height_px &&
                               l.fx_px == r.fx_px && l.fy_px == r.fy_px && l.cx_px == r.cx_px &&
                               l.cy_px == r.cy_px;
  const Eigen::Vector3d t = T_CL_CR.translation();
  return same_intrinsics && !l.distorted() && !r.distorted() &&
         T_CL_CR.linear() == Eigen::Matrix3d::Identity() && t.y() == 0.0 && t.z() == 0.0 &&
         t.x() > 0.0;
}

namespace {

// A pair of equal pinhole cameras, the left one at body (0, B/2, height_m) looking along
// body +x pitched down by pitch_down_rad, the right one B to its right (plus `errors`).
StereoRig make_pinhole_rig(int width_px, int height_px, double focal_px, double baseline_m,
                           double height_m, const std::function<double(const PinholeCamera&)>& pitch_down_rad,
                           const RigErrors& errors) {
  check(std::all_of(errors.distortion.begin(), errors.distortion.end(),
                    [](double d) { return std::isfinite(d) && std::abs(d) < 10.0; }),
        "simulate: distortion coefficients must be finite and below 10 in magnitude");
  check(errors.misalignment_rpy_deg.allFinite() &&
            errors.misalignment_rpy_deg.cwiseAbs().maxCoeff() <= 10.0,
        "simulate: misalignment angles must be within +-10 deg");
  check(errors.misalignment_m.allFinite() && errors.misalignment_m.cwiseAbs().maxCoeff() <= 0.02,
        "simulate: misalignment offsets must be within +-0.02 m");
  StereoRig rig;
  PinholeCamera& c = rig.camera;
  c.width_px = width_px;
  c.height_px = height_px;
  c.fx_px = c.fy_px = quantize(focal_px);
  c.cx_px = 0.5 * (c.width_px - 1);
  c.cy_px = 0.5 * (c.height_px - 1);
  for (std::size_t i = 0; i < 5; ++i) c.distortion[i] = quantize(errors.distortion[i]);
  rig.camera_right = c;
  rig.baseline_m = baseline_m;

  // Looking along body +x: camera z -> body x, camera x -> body -y, camera y -> body -z.
  Eigen::Matrix3d R_B_C0;
  R_B_C0 << 0, 0, 1,  //
      -1, 0, 0,       //
      0, -1, 0;
  const Eigen::Matrix3d R_B_C =
      Eigen::AngleAxisd(pitch_down_rad(c), Eigen::Vector3d::UnitY()).toRotationMatrix() * R_B_C0;
  // Render with the quaternion as written (rounded, then normalised as a reader would).
  rig.T_B_CL = Pose3d::Identity();
  rig.T_B_CL.linear() = as_written(R_B_C);
  // Left camera at body y = +B/2, so the pair straddles the body centre.
  rig.T_B_CL.translation() = Eigen::Vector3d(0.0, 0.5 * baseline_m, height_m);

  rig.T_CL_CR = Pose3d::Identity();
  rig.T_CL_CR.translation() =
      Eigen::Vector3d(baseline_m, 0.0, 0.0) +
      Eigen::Vector3d(quantize(errors.misalignment_m.x()), quantize(errors.misalignment_m.y()),
                      quantize(errors.misalignment_m.z()));
  if (!errors.misalignment_rpy_deg.isZero(0.0)) {
    rig.T_CL_CR.linear() = rotation_deg(errors.misalignment_rpy_deg);
  }
  return rig;
}

}  // namespace

StereoRig make_cadre_rig(double scale, const RigErrors& errors) {
  check(scale >= 0.05 && scale <= 2.0, "simulate: scale must be in [0.05, 2]");
  return make_pinhole_rig(
      static_cast<int>(std::lround(kCadreWidthPx * scale)),
      static_cast<int>(std::lround(kCadreHeightPx * scale)), kCadreFocalPx * scale,
      kCadreBaselineM, kCadreHeightM,
      [](const PinholeCamera& c) {
        // Top image edge (v = -0.5, half a pixel above row 0) at 10 deg above the horizon.
        const double half_vfov_rad = std::atan(0.5 * c.height_px / c.fy_px);
        return half_vfov_rad - kFovTopAboveHorizonDeg * kPi / 180.0;
      },
      errors);
}

StereoRig make_polar_rig(double scale, const RigErrors& errors) {
  check(scale >= 0.05 && scale <= 2.0, "simulate: scale must be in [0.05, 2]");
  const int size_px = static_cast<int>(std::lround(kPolarSizePx * scale));
  return make_pinhole_rig(
      size_px, size_px, kPolarFocalPx * scale, kPolarBaselineM, kPolarHeightM,
      [](const PinholeCamera&) { return kPolarPitchDownDeg * kPi / 180.0; }, errors);
}

const std::vector<std::string>& rig_names() {
  static const std::vector<std::string> names = {"cadre", "polar"};
  return names;
}

StereoRig make_rig(const std::string& name, double scale, const RigErrors& errors) {
  if (name == "cadre") return make_cadre_rig(scale, errors);
  if (name == "polar") return make_polar_rig(scale, errors);
  throw Error("simulate: unknown rig '" + name + "' (cadre | polar)");
}

void apply_lunar_polar_light(RenderOptions& render) {
  render.sun_shading = true;
  render.sun_elevation_deg = kPolarSunElevationDeg;
  render.cast_shadows = true;
  render.terrain_shadows = true;
  render.ambient = 0.0;
  render.albedo_model = AlbedoModel::regolith;
  render.opposition_surge = kPolarOppositionSurge;
}

void validate(const SimulationOptions& options) {
  check(options.frames >= 1 && options.frames <= 100000,
        "simulate: frames must be in [1, 100000]");
  check(options.scale >= 0.05 && options.scale <= 2.0, "simulate: scale must be in [0.05, 2]");
  check(std::isfinite(options.step_m) && options.step_m >= 0.0 && options.step_m <= 10.0,
        "simulate: step_m must be in [0, 10]");
  check(options.ground_truth_resolution_m > 0.0,
        "simulate: ground_truth_resolution_m must be positive");
  check(options.ground_truth_margin_m >= 0.0 && options.ground_truth_margin_m <= 50.0,
        "simulate: ground_truth_margin_m must be in [0, 50]");
  // Nodes per side (size / terrain_resolution_m) are converted to int: bounded first.
  check(options.terrain_size_m > 0.0 && options.terrain_size_m <= 1000.0,
        "simulate: terrain_size_m (--terrain-size) must be in (0, 1000] m");
  check(options.png_compression >= 0 && options.png_compression <= 9,
        "simulate: png_compression must be in [0, 9]");
  check(options.wheels.wheelbase_m > 0.0 && options.wheels.wheelbase_m <= 10.0 &&
            options.wheels.track_m > 0.0 && options.wheels.track_m <= 10.0,
        "simulate: wheelbase_m and track_m must be in (0, 10]");
  check(options.rock_path_clearance_m >= 0.0 && std::isfinite(options.rock_path_clearance_m),
        "simulate: rock_path_clearance_m must be >= 0");
  check(std::find(rig_names().begin(), rig_names().end(), options.rig) != rig_names().end(),
        "simulate: unknown rig '" + options.rig + "' (cadre | polar)");
  validate(options.left_response);
  validate(options.right_response);
  check(std::isfinite(options.row_offset_px) && std::abs(options.row_offset_px) <= 50.0,
        "simulate: row_offset_px must be within +-50 px");
  validate(options.path);
  validate(options.drift);
}

std::vector<PathPoint> simulation_path_points(const SimulationOptions& options) {
  validate(options);
  return plan_path(options.path, options.frames, options.step_m, derive_seeds(options.seed).path);
}

Terrain make_simulation_terrain(const SimulationOptions& options) {
  const std::vector<PathPoint> path = simulation_path_points(options);
  Eigen::Vector2d lo, hi;
  path_bounds(path, lo, hi);
  const double behind_m = std::max(2.5, options.ground_truth_margin_m + 0.5);
  double x_min = -behind_m;
  double x_max = std::max(x_min + options.terrain_size_m, hi.x() + 5.5);
  double half_y = std::max(0.5 * options.terrain_size_m, options.ground_truth_margin_m + 0.5);
  double y_min = -half_y;
  double y_max = half_y;
  if (options.path.kind != "straight") {
    // The camera looks ahead along any heading: keep 5.5 m of detail around the path.
    const double ahead_m = std::max(5.5, options.ground_truth_margin_m + 0.5);
    x_min = std::min(x_min, lo.x() - ahead_m);
    x_max = std::max(x_max, hi.x() + ahead_m);
    y_min = std::min(y_min, lo.y() - ahead_m);
    y_max = std::max(y_max, hi.y() + ahead_m);
  }

  TerrainOptions terrain;
  terrain.scenario = options.scenario;
  terrain.seed = derive_seeds(options.seed).terrain;
  terrain.center_W = Eigen::Vector2d(0.5 * (x_min + x_max), 0.5 * (y_min + y_max));
  terrain.size_x_m = x_max - x_min;
  terrain.size_y_m = y_max - y_min;
  terrain.resolution_m = options.terrain_resolution_m;
  terrain.ramp_deg = options.ramp_deg;
  terrain.sine = options.sine;
  terrain.noise = options.ground_noise;
  terrain.rock_field = options.rock_field;
  terrain.scatter_rocks = options.scatter_rocks;
  terrain.crater_field = options.crater_field;
  terrain.extra_rocks = options.extra_rocks;
  terrain.extra_craters = options.extra_craters;
  if (options.rock_path_clearance_m > 0.0) {
    for (const PathPoint& point : path) terrain.keep_clear_W.push_back(point.p_W);
    terrain.keep_clear_m = options.rock_path_clearance_m;
  }
  return make_terrain(terrain);
}

std::vector<Pose3d> simulation_path(const SimulationOptions& options, const Terrain& terrain) {
  std::vector<Pose3d> poses;
  for (PathPoint point : simulation_path_points(options)) {
    point.p_W = Eigen::Vector2d(quantize(point.p_W.x()), quantize(point.p_W.y()));
    poses.push_back(pose_as_written(pose_on_ground(terrain, point, options.wheels)));
  }
  return poses;
}

std::vector<Pose3d> reported_path(const SimulationOptions& options,
                                  const std::vector<Pose3d>& true_path) {
  if (options.drift.fraction <= 0.0) return true_path;
  const double direction_rad = drift_direction_rad(options.drift, derive_seeds(options.seed).drift);
  std::vector<Pose3d> poses;
  for (std::size_t k = 0; k < true_path.size(); ++k) {
    poses.push_back(pose_as_written(drifted_pose(true_path[k], static_cast<double>(k) * options.step_m,
                                                 options.drift.fraction, direction_rad)));
  }
  return poses;
}

SimulationSummary simulate_sequence(const SimulationOptions& options,
                                    const std::filesystem::path& out_dir,
                                    const std::function<void()>& before_writing) {
  validate(options);
  const Seeds seeds = derive_seeds(options.seed);
  const Terrain terrain = make_simulation_terrain(options);
  const StereoRig rig = make_rig(options.rig, options.scale, options.rig_errors);
  const std::vector<Pose3d> path = simulation_path(options, terrain);
  const std::vector<Pose3d> reported = reported_path(options, path);
  const bool drift = options.drift.fraction > 0.0;
  const Renderer renderer(terrain, options.render, seeds.texture);
  // The craters as make_terrain drew them (same seed), for simulation.yaml.
  TerrainOptions crater_source;
  crater_source.scenario = options.scenario;
  crater_source.seed = seeds.terrain;
  crater_source.crater_field = options.crater_field;
  crater_source.extra_craters = options.extra_craters;
  const std::vector<Crater> craters = terrain_craters(crater_source);

  spdlog::debug("simulate: scenario {}, seed {}, {} frames of {}x{} px, {} rocks, {} craters -> {}",
                options.scenario, options.seed, options.frames, rig.camera.width_px,
                rig.camera.height_px, terrain.rocks().size(), craters.size(), out_dir.string());

  // The ground truth's grid (its size checked) before anything is written; its values
  // are filled at the end.
  JdemGrid gt_grid;
  if (options.write_ground_truth) {
    std::vector<PathPoint> true_points;
    for (const Pose3d& T_W_B : path) {
      PathPoint point;
      point.p_W = T_W_B.translation().head<2>();
      true_points.push_back(point);
    }
    Eigen::Vector2d lo, hi;
    path_bounds(true_points, lo, hi);
    const double m = options.ground_truth_margin_m;
    gt_grid = aligned_ground_truth_grid("height", lo.x() - m, hi.x() + m, lo.y() - m,
                                        hi.y() + m, options.ground_truth_resolution_m);
    decltype(gt_grid.values)().swap(gt_grid.values);  // only its geometry is used
  }
  // Every option is checked and the terrain, rig and path are built: only now may the
  // caller clear an earlier output (hazmap simulate --overwrite).
  if (before_writing) before_writing();
  // simulation.yaml first: it marks the folder as a simulated sequence (output_folder.hpp),
  // so that even a simulation stopped early can be overwritten.
  write_file_atomically(
      out_dir / "simulation.yaml",
      simulation_yaml(options, terrain, craters, rig,
                      drift ? drift_direction_rad(options.drift, seeds.drift) : 0.0));
  write_file_atomically(out_dir / "calibration.yaml", calibration_yaml(rig, options.rig, options.scale));
  write_file_atomically(out_dir / "poses.txt", poses_txt(options, reported, false, drift));
  if (drift) write_file_atomically(out_dir / "poses_true.txt", poses_txt(options, path, true, false));

  SimulationSummary summary;
  summary.frames = options.frames;
  summary.width_px = rig.camera.width_px;
  summary.height_px = rig.camera.height_px;
  summary.rocks = terrain.rocks().size();
  summary.craters = craters.size();
  // The right camera as rendered: its rows off by the residual row offset.
  PinholeCamera right_render = rig.camera_right;
  right_render.cy_px -= options.row_offset_px;
  const Progress progress(options.frames);
  for (int k = 0; k < options.frames; ++k) {
    const std::string name = frame_name(k);
    const Pose3d T_W_CL = path[k] * rig.T_B_CL;
    const Pose3d T_W_CR = path[k] * rig.T_B_CR();
    const std::uint64_t frame_key =
        hash_combine(seeds.image_noise, static_cast<std::uint64_t>(k));
    const auto start = std::chrono::steady_clock::now();
    const cv::Mat left =
        renderer.render(rig.camera, T_W_CL, hash_combine(frame_key, 0), options.left_response);
    const cv::Mat right =
        renderer.render(right_render, T_W_CR, hash_combine(frame_key, 1), options.right_response);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.render_seconds += seconds;
    write_file_atomically(out_dir / "left" / (name + ".png"),
                          encode_png(left, options.png_compression));
    write_file_atomically(out_dir / "right" / (name + ".png"),
                          encode_png(right, options.png_compression));
    if (options.write_depth) {
      std::vector<unsigned char> bytes;
      check(cv::imencode(".tiff", renderer.render_depth(rig.camera, T_W_CL), bytes),
            "simulate: TIFF encoding of the depth image failed");
      write_file_atomically(out_dir / "depth" / (name + ".tiff"), bytes);
    }
    if (options.log_progress)
      spdlog::info("simulate: frame {} rendered in {:.1f} s; {}", name, seconds,
                   progress.step(k + 1));
    else
      spdlog::debug("simulate: frame {} rendered in {:.2f} s", name, seconds);
  }

  if (options.write_ground_truth) {
    const JdemGrid& g = gt_grid;
    const Eigen::Vector2d center_W(g.center_x_m, g.center_y_m);
    const std::vector<std::pair<std::string, std::string>> metadata = {
        {"source", "hazmap simulate"},
        {"scenario", options.scenario},
        {"seed", std::to_string(options.seed)}};
    JdemGrid height =
        terrain.ground_truth_height(options.ground_truth_resolution_m, center_W, g.rows, g.cols);
    height.metadata = metadata;
    write_jdem(out_dir / "gt_height.jdem", height);
    JdemGrid hazard =
        terrain.ground_truth_hazard(options.ground_truth_resolution_m, center_W, g.rows, g.cols);
    hazard.metadata = metadata;
    write_jdem(out_dir / "gt_hazard.jdem", hazard);
  }
  return summary;
}

}  // namespace hazmap::sim
