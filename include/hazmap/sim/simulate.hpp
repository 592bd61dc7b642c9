#pragma once
// Synthetic stereo sequences (`hazmap simulate`, SPEC 13): a rover drives a straight or
// spline path over a synthetic Terrain while a CADRE-like stereo pair (SPEC 11) looks
// ahead. Writes a sequence folder in the SPEC 2 layout, plus optional ground truth
// (SPEC 9, 10) and per-frame depth, so the whole pipeline can be run and scored against
// known answers.
//
// Exactness: poses and calibration are rounded to 12 significant digits *before* they
// are used for rendering, so the files written are the exact truth of the images (the
// misaligned right camera's R, to 1e-11).

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hazmap/core/types.hpp"
#include "hazmap/sim/camera_model.hpp"
#include "hazmap/sim/path.hpp"
#include "hazmap/sim/renderer.hpp"
#include "hazmap/sim/rover_pose.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {

/// Imperfections of the stereo rig: lens distortion of both cameras and a small error
/// in the right camera's pose. Rendered through the true (imperfect) cameras and written
/// to calibration.yaml (rectified: false) so that the project's rectifier undoes them.
struct RigErrors {
  std::array<double, 5> distortion{0.0, 0.0, 0.0, 0.0, 0.0};  ///< k1 k2 p1 p2 k3, both lenses
  /// Rotation of the right camera away from the left camera's orientation, about the
  /// right camera's axes: R_CL_CR = Rz(yaw) Ry(pitch) Rx(roll), degrees (roll, pitch, yaw).
  Eigen::Vector3d misalignment_rpy_deg = Eigen::Vector3d::Zero();
  /// Offset of the right camera centre from its ideal place (baseline_m, 0, 0), in the
  /// left camera frame, metres.
  Eigen::Vector3d misalignment_m = Eigen::Vector3d::Zero();

  /// Barrel distortion of a wide-angle lens (k1 -0.08, k2 0.012, p1 4e-4, p2 -3e-4,
  /// k3 0): points at the left and right edges of the 90 deg CADRE view move 9 % of their
  /// radius inwards (71 px at full size); monotonic well beyond the image corners.
  /// What `hazmap simulate --distort` uses.
  static std::array<double, 5> typical_distortion();
  /// A right camera 0.3, -0.2, 0.4 deg (roll, pitch, yaw) and (0.5, -0.3, 0.4) mm off:
  /// several pixels of row misalignment if left uncorrected. `--misalign`.
  static Eigen::Vector3d typical_misalignment_rpy_deg();
  static Eigen::Vector3d typical_misalignment_m();
};

/// A stereo pair. In the ideal rig both cameras share `camera` and orientation and the
/// right camera centre is at (+baseline_m, 0, 0) in the left camera frame, i.e.
/// x_right = x_left + T with T = (-baseline_m, 0, 0).
struct StereoRig {
  PinholeCamera camera;        ///< left camera
  PinholeCamera camera_right;  ///< right camera (equal to `camera` in the CADRE rig)
  double baseline_m = 0.0;
  Pose3d T_B_CL = Pose3d::Identity();  ///< left camera in the body frame: p_B = T_B_CL p_CL
  Pose3d T_CL_CR = Pose3d::Identity(); ///< right camera in the left camera frame

  /// Right camera in the body frame.
  Pose3d T_B_CR() const;
  /// True for an undistorted pair with equal intrinsics, equal orientation and the right
  /// camera on the left camera's +x axis: its images are already rectified.
  bool rectified() const;
};

/// The CADRE rig of SPEC 11 at `scale` (image size relative to 1600 x 1300):
/// width = round(1600 scale), height = round(1300 scale), f = 671 scale px,
/// principal point at the image centre ((w-1)/2, (h-1)/2), baseline 0.05 m; left camera
/// at body (0, 0.025, 0.15) looking along body +x, pitched down so that the top edge of
/// the image (v = -0.5) looks 10 deg above the horizon (for the undistorted lens).
/// `errors` adds distortion and misalignment. Numbers are rounded to 12 significant
/// digits, as written to calibration.yaml. Throws Error if scale is outside [0.05, 2]
/// or the errors are not finite.
StereoRig make_cadre_rig(double scale, const RigErrors& errors = RigErrors());

/// The POLAR Traverse rig (NASA Ames lunar-polar analog dataset, station "1m") at `scale`
/// (image size relative to 2048 x 2048): f = 1457 scale px, principal point at the image
/// centre, baseline 0.40 m; left camera at body (0, 0.20, 1.30) looking along body +x,
/// pitched 28 deg down (the mount fitted to that pair). `errors` as for make_cadre_rig.
StereoRig make_polar_rig(double scale, const RigErrors& errors = RigErrors());

/// The rigs `hazmap simulate --rig` knows: "cadre" (the default) and "polar".
const std::vector<std::string>& rig_names();

/// make_cadre_rig or make_polar_rig by name; throws Error on an unknown name.
StereoRig make_rig(const std::string& name, double scale, const RigErrors& errors = RigErrors());

/// Lunar polar light (`hazmap simulate --lunar-polar-light`): sun 8 deg above the horizon
/// (polar sites see it between a few degrees and about 15), ground shadows traced, no
/// ambient light (black sky, no atmosphere), dull regolith albedo, opposition surge.
/// Only lighting and albedo change; the caller's camera settings stay.
void apply_lunar_polar_light(RenderOptions& render);

struct SimulationOptions {
  std::string rig = "cadre";       ///< cadre | polar (make_rig)
  std::string scenario = "rocks";  ///< flat | ramp | sine | rocks | craters (TerrainOptions)
  std::uint64_t seed = 1;
  int frames = 8;
  double scale = 0.4;    ///< image size relative to CADRE's 1600 x 1300, f = 671 px
  /// Horizontal travel per frame along the path (1 Hz: 4 cm/s, SPEC 11).
  double step_m = 0.04;
  PathOptions path;
  WheelGeometry wheels;  ///< body height, roll and pitch from the ground under the wheels
  /// Drift of the poses written to poses.txt (the true ones go to poses_true.txt).
  DriftOptions drift;
  RigErrors rig_errors;
  /// Write gt_height.jdem / gt_hazard.jdem over the path's bounding box +- margin.
  bool write_ground_truth = false;
  double ground_truth_resolution_m = 0.01;
  double ground_truth_margin_m = 2.0;
  /// Write depth/<name>.tiff: 32-bit float Z [m] in the left camera frame through each
  /// pixel centre (through the lens model), NaN for sky.
  bool write_depth = false;

  /// Terrain (TerrainOptions has the meaning of each scenario).
  /// Straight path: a square of side terrain_size_m from 2.5 m behind the start (more if
  /// the ground-truth margin needs it), extended to reach at least 5.5 m beyond the last
  /// pose. Spline path: that square joined with the path's bounding box +- 5.5 m.
  /// Beyond the grid the ground continues at its edge values.
  double terrain_size_m = 8.0;
  double terrain_resolution_m = 0.01;
  double ramp_deg = 15.0;
  SineWave sine{0.05, 1.0, 0.0};      ///< sine scenario
  FractalNoiseOptions ground_noise;   ///< rocks and craters scenarios
  RockFieldOptions rock_field;        ///< rocks scenario, or any with scatter_rocks
  bool scatter_rocks = false;
  /// > 0: random rocks keep this clearance from the path (the rover never drives into
  /// one). 0: the path ignores rocks; the body pose ignores them anyway.
  double rock_path_clearance_m = 0.0;
  CraterFieldOptions crater_field;    ///< craters scenario
  std::vector<Rock> extra_rocks;      ///< added in every scenario
  std::vector<Crater> extra_craters;  ///< added in every scenario
  RenderOptions render;
  /// The cameras' responses (gain, exposure, offset, shot noise, vignetting, bit depth).
  CameraResponse left_response;
  CameraResponse right_response;
  /// Residual row offset after rectification, px: a scene point at row y in the left
  /// image appears at row y - row_offset_px in the right one (the right camera is rendered
  /// with its principal point that much higher; calibration.yaml keeps the nominal one).
  double row_offset_px = 0.0;
  int png_compression = 9;  ///< zlib level 0-9 for the PNG files
  /// One spdlog info line per rendered frame with rate and time left (the CLI's
  /// progress); off, the lines go to debug.
  bool log_progress = false;
};

/// Throws Error naming the option if it is unusable (frames < 1, scale outside
/// [0.05, 2], negative or non-finite step, ...). Terrain options are checked by
/// make_simulation_terrain.
void validate(const SimulationOptions& options);

/// The path simulate_sequence drives (same options => same path).
std::vector<PathPoint> simulation_path_points(const SimulationOptions& options);

/// The terrain simulate_sequence renders (same options => same terrain).
Terrain make_simulation_terrain(const SimulationOptions& options);

/// True body poses T_W_B of the frames: along simulation_path_points, standing on the
/// wheel plane (rover_pose.hpp; rocks ignored). Rounded as written to poses.txt.
std::vector<Pose3d> simulation_path(const SimulationOptions& options, const Terrain& terrain);

/// The poses written to poses.txt: the true ones, or with drift.fraction > 0 the
/// drifted ones (rounded as written).
std::vector<Pose3d> reported_path(const SimulationOptions& options,
                                  const std::vector<Pose3d>& true_path);

/// What a simulation did, for the log.
struct SimulationSummary {
  int frames = 0;
  int width_px = 0;
  int height_px = 0;
  std::size_t rocks = 0;
  std::size_t craters = 0;
  double render_seconds = 0.0;  ///< wall time spent rendering images (both cameras)
};

/// Renders the sequence into `out_dir`:
///   left/<name>.png, right/<name>.png   8-bit grey, name = 6-digit frame index (000000)
///   poses.txt          '#' comment lines, then `name t x y z qx qy qz qw` (t = index s);
///                      with drift: the drifted poses plus `sx sy sz syaw` (the drift
///                      added since the previous frame as a standard deviation)
///   poses_true.txt     with drift only: the true poses, same format (9 columns)
///   calibration.yaml   SPEC 2 format; ideal rig: rectified (identical K, zero D, R = I,
///                      T = (-B,0,0)); with rig errors: the true K, D, R, T, rectified: false
///   simulation.yaml    the options used, pose files, craters and rocks (for people and tools)
///   gt_height.jdem, gt_hazard.jdem   if write_ground_truth (SPEC 9/10)
///   depth/<name>.tiff  if write_depth
/// Creates folders as needed; files of the same names are replaced atomically, other
/// files are left alone (hazmap simulate refuses a non-empty folder, or clears it with
/// --overwrite through `before_writing`). Same options => byte-identical files, for any
/// thread count. Rendering is parallel over image rows (all cores). Throws Error on
/// invalid options or I/O failure. `before_writing`, when given, is called once every
/// option has been checked and the terrain, rig and path built, before the first file is
/// written; an error it throws stops the simulation with nothing written.
SimulationSummary simulate_sequence(const SimulationOptions& options,
                                    const std::filesystem::path& out_dir,
                                    const std::function<void()>& before_writing = {});

}  // namespace hazmap::sim
