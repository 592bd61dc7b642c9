#include "hazmap/sim/simulate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"
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

std::string list(std::initializer_list<double> values) {
  std::string s = "[";
  for (const double v : values) s += (s.size() > 1 ? ", " : "") + num(v);
  return s + "]";
}

// Quaternion with qw >= 0 (one of the two equivalent signs, chosen for stable output).
Eigen::Quaterniond canonical(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  return q;
}

std::string calibration_yaml(const StereoRig& rig, double scale) {
  const PinholeCamera& c = rig.camera;
  const std::string K = list({c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1});
  const Eigen::Quaterniond q = canonical(rig.T_B_CL.linear());
  const Eigen::Vector3d t = rig.T_B_CL.translation();
  std::ostringstream out;
  out << "# Synthetic rectified stereo pair (hazmap simulate): CADRE geometry at scale "
      << num(scale) << ".\n"
      << "image_width: " << c.width_px << "\n"
      << "image_height: " << c.height_px << "\n"
      << "rectified: true                  # ideal pinhole pair: no remapping needed\n"
      << "left:  {K: " << K << ", D: [0, 0, 0, 0, 0]}\n"
      << "right: {K: " << K << ", D: [0, 0, 0, 0, 0]}\n"
      << "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]   # x_right = R x_left + T\n"
      << "T: " << list({-rig.baseline_m, 0, 0}) << "                 # metres\n"
      << "T_body_left: {translation: " << list({t.x(), t.y(), t.z()})
      << ", quaternion: "
      << list({quantize(q.x()), quantize(q.y()), quantize(q.z()), quantize(q.w())}) << "}\n";
  return out.str();
}

std::string poses_txt(const SimulationOptions& options, const std::vector<Pose3d>& T_W_B) {
  std::ostringstream out;
  out << "# hazmap simulate: scenario " << options.scenario << ", seed " << options.seed
      << ", " << options.frames << " frames, " << num(options.step_m)
      << " m per frame along W +x\n"
      << "# T_W_B: body x forward, y left, z up; origin on the ground under the robot\n"
      << "# name t x y z qx qy qz qw\n";
  for (std::size_t k = 0; k < T_W_B.size(); ++k) {
    const Eigen::Vector3d p = T_W_B[k].translation();
    const Eigen::Quaterniond q(T_W_B[k].linear());
    out << frame_name(static_cast<int>(k)) << ' ' << k << ' ' << num(p.x()) << ' '
        << num(p.y()) << ' ' << num(p.z()) << ' ' << num(q.x()) << ' ' << num(q.y()) << ' '
        << num(q.z()) << ' ' << num(q.w()) << '\n';
  }
  return out.str();
}

std::string simulation_yaml(const SimulationOptions& options, const Terrain& terrain) {
  std::ostringstream out;
  out << "# How this sequence was made (hazmap simulate). Rock heights are above the\n"
      << "# local ground; rocks at least as high as a layer's h_min are hazards.\n"
      << "scenario: " << options.scenario << "\n"
      << "seed: " << options.seed << "\n"
      << "frames: " << options.frames << "\n"
      << "scale: " << num(options.scale) << "\n"
      << "step_m: " << num(options.step_m) << "\n";
  if (options.scenario == "ramp") out << "ramp_deg: " << num(options.ramp_deg) << "\n";
  out << "samples_per_axis: " << options.render.samples_per_axis << "\n"
      << "noise_sigma_dn: " << num(options.render.noise_sigma_dn) << "\n"
      << "sun: {shading: " << (options.render.sun_shading ? "true" : "false")
      << ", elevation_deg: " << num(options.render.sun_elevation_deg)
      << ", azimuth_deg: " << num(options.render.sun_azimuth_deg) << "}\n"
      << "rocks:" << (terrain.rocks().empty() ? " []" : "") << "\n";
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

std::vector<unsigned char> encode_png(const cv::Mat& image, int compression) {
  std::vector<unsigned char> bytes;
  check(cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, compression}),
        "simulate: PNG encoding failed");
  return bytes;
}

// Ground-truth grid over [x0, x1] x [y0, y1], cell borders on multiples of the resolution
// (SPEC 1) and an even number of cells per axis, so the centre is a cell corner.
struct GridFrame {
  Eigen::Vector2d center_W;
  int rows = 0;
  int cols = 0;
};

GridFrame aligned_grid(double x0, double x1, double y0, double y1, double resolution_m) {
  auto axis = [&](double lo, double hi, double& center, int& cells) {
    // The 1e-9 slack keeps -0.3 / 0.01 = -29.999999999999996 on lattice line -30.
    const double first = std::floor(lo / resolution_m + 1e-9);
    cells = static_cast<int>(std::ceil(hi / resolution_m - 1e-9) - first);
    cells += cells % 2;
    center = (first + 0.5 * cells) * resolution_m;
  };
  GridFrame grid;
  axis(x0, x1, grid.center_W.x(), grid.cols);
  axis(y0, y1, grid.center_W.y(), grid.rows);
  return grid;
}

// Independent random streams from the one user seed: the first draws of a mt19937_64.
struct Seeds {
  std::uint64_t terrain = 0;
  std::uint64_t texture = 0;
  std::uint64_t image_noise = 0;
};

Seeds derive_seeds(std::uint64_t seed) {
  std::mt19937_64 master(seed);
  Seeds seeds;
  seeds.terrain = master();
  seeds.texture = master();
  seeds.image_noise = master();
  return seeds;
}

}  // namespace

Pose3d StereoRig::T_B_CR() const {
  return T_B_CL * Eigen::Translation3d(baseline_m, 0.0, 0.0);
}

StereoRig make_cadre_rig(double scale) {
  check(scale >= 0.05 && scale <= 2.0, "simulate: scale must be in [0.05, 2]");
  StereoRig rig;
  PinholeCamera& c = rig.camera;
  c.width_px = static_cast<int>(std::lround(kCadreWidthPx * scale));
  c.height_px = static_cast<int>(std::lround(kCadreHeightPx * scale));
  c.fx_px = c.fy_px = quantize(kCadreFocalPx * scale);
  c.cx_px = 0.5 * (c.width_px - 1);
  c.cy_px = 0.5 * (c.height_px - 1);
  rig.baseline_m = kCadreBaselineM;

  // Looking along body +x: camera z -> body x, camera x -> body -y, camera y -> body -z.
  Eigen::Matrix3d R_B_C0;
  R_B_C0 << 0, 0, 1,  //
      -1, 0, 0,       //
      0, -1, 0;
  // Top image edge (v = -0.5, half a pixel above row 0) at 10 deg above the horizon.
  const double half_vfov_rad = std::atan(0.5 * c.height_px / c.fy_px);
  const double pitch_down_rad = half_vfov_rad - kFovTopAboveHorizonDeg * kPi / 180.0;
  const Eigen::Matrix3d R_B_C =
      Eigen::AngleAxisd(pitch_down_rad, Eigen::Vector3d::UnitY()).toRotationMatrix() * R_B_C0;
  // Render with the quaternion as written (rounded, then normalised as a reader would).
  const Eigen::Quaterniond q = canonical(R_B_C);
  const Eigen::Quaterniond q_written(quantize(q.w()), quantize(q.x()), quantize(q.y()),
                                     quantize(q.z()));
  rig.T_B_CL = Pose3d::Identity();
  rig.T_B_CL.linear() = q_written.normalized().toRotationMatrix();
  // Left camera at body y = +B/2, so the pair straddles the body centre.
  rig.T_B_CL.translation() = Eigen::Vector3d(0.0, 0.5 * kCadreBaselineM, kCadreHeightM);
  return rig;
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
  check(options.terrain_size_m > 0.0, "simulate: terrain_size_m must be positive");
  check(options.png_compression >= 0 && options.png_compression <= 9,
        "simulate: png_compression must be in [0, 9]");
}

Terrain make_simulation_terrain(const SimulationOptions& options) {
  validate(options);
  const double travel_m = (options.frames - 1) * options.step_m;
  const double behind_m = std::max(2.5, options.ground_truth_margin_m + 0.5);
  const double x_min = -behind_m;
  const double x_max = std::max(x_min + options.terrain_size_m, travel_m + 5.5);
  const double half_y = std::max(0.5 * options.terrain_size_m, options.ground_truth_margin_m + 0.5);

  TerrainOptions terrain;
  terrain.scenario = options.scenario;
  terrain.seed = derive_seeds(options.seed).terrain;
  terrain.center_W = Eigen::Vector2d(0.5 * (x_min + x_max), 0.0);
  terrain.size_x_m = x_max - x_min;
  terrain.size_y_m = 2.0 * half_y;
  terrain.resolution_m = options.terrain_resolution_m;
  terrain.ramp_deg = options.ramp_deg;
  terrain.noise = options.ground_noise;
  terrain.rock_field = options.rock_field;
  terrain.extra_rocks = options.extra_rocks;
  return make_terrain(terrain);
}

std::vector<Pose3d> simulation_path(const SimulationOptions& options, const Terrain& terrain) {
  std::vector<Pose3d> path;
  for (int k = 0; k < options.frames; ++k) {
    Pose3d T_W_B = Pose3d::Identity();
    const double x_m = quantize(k * options.step_m);
    T_W_B.translation() = Eigen::Vector3d(x_m, 0.0, quantize(terrain.ground_height_m(x_m, 0.0)));
    path.push_back(T_W_B);
  }
  return path;
}

void simulate_sequence(const SimulationOptions& options, const std::filesystem::path& out_dir) {
  validate(options);
  const Seeds seeds = derive_seeds(options.seed);
  const Terrain terrain = make_simulation_terrain(options);
  const StereoRig rig = make_cadre_rig(options.scale);
  const std::vector<Pose3d> path = simulation_path(options, terrain);
  const Renderer renderer(terrain, options.render, seeds.texture);

  spdlog::debug("simulate: scenario {}, seed {}, {} frames of {}x{} px, {} rocks -> {}",
               options.scenario, options.seed, options.frames, rig.camera.width_px,
               rig.camera.height_px, terrain.rocks().size(), out_dir.string());

  write_file_atomically(out_dir / "calibration.yaml", calibration_yaml(rig, options.scale));
  write_file_atomically(out_dir / "poses.txt", poses_txt(options, path));
  write_file_atomically(out_dir / "simulation.yaml", simulation_yaml(options, terrain));

  for (int k = 0; k < options.frames; ++k) {
    const std::string name = frame_name(k);
    const Pose3d T_W_CL = path[k] * rig.T_B_CL;
    const Pose3d T_W_CR = path[k] * rig.T_B_CR();
    const std::uint64_t frame_key =
        hash_combine(seeds.image_noise, static_cast<std::uint64_t>(k));
    const cv::Mat left = renderer.render(rig.camera, T_W_CL, hash_combine(frame_key, 0));
    const cv::Mat right = renderer.render(rig.camera, T_W_CR, hash_combine(frame_key, 1));
    write_file_atomically(out_dir / "left" / (name + ".png"),
                          encode_png(left, options.png_compression));
    write_file_atomically(out_dir / "right" / (name + ".png"),
                          encode_png(right, options.png_compression));
    spdlog::debug("simulate: frame {} written", name);
  }

  if (options.write_ground_truth) {
    const double travel_m = (options.frames - 1) * options.step_m;
    const double m = options.ground_truth_margin_m;
    const GridFrame g =
        aligned_grid(-m, travel_m + m, -m, m, options.ground_truth_resolution_m);
    const std::vector<std::pair<std::string, std::string>> metadata = {
        {"source", "hazmap simulate"},
        {"scenario", options.scenario},
        {"seed", std::to_string(options.seed)}};
    JdemGrid height =
        terrain.ground_truth_height(options.ground_truth_resolution_m, g.center_W, g.rows, g.cols);
    height.metadata = metadata;
    write_jdem(out_dir / "gt_height.jdem", height);
    JdemGrid hazard =
        terrain.ground_truth_hazard(options.ground_truth_resolution_m, g.center_W, g.rows, g.cols);
    hazard.metadata = metadata;
    write_jdem(out_dir / "gt_hazard.jdem", hazard);
  }
}

}  // namespace hazmap::sim
