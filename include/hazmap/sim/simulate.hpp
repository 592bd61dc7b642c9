#pragma once
// Synthetic stereo sequences (`hazmap simulate`, SPEC 13): a rover drives straight along
// W +x over a synthetic Terrain while an ideal, rectified CADRE-like stereo pair (SPEC 11)
// looks ahead. Writes a sequence folder in the SPEC 2 layout, plus optional ground truth
// (SPEC 10), so the whole pipeline can be run and scored against known answers.
//
// Exactness: poses and calibration are rounded to 12 significant digits *before* they
// are used for rendering, so the files written are the exact truth of the images.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/core/types.hpp"
#include "hazmap/sim/renderer.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {

/// An ideal rectified stereo pair: both cameras share `camera` and orientation; the right
/// camera centre is at (+baseline_m, 0, 0) in the left camera frame, i.e.
/// x_right = x_left + T with T = (-baseline_m, 0, 0).
struct StereoRig {
  PinholeCamera camera;
  double baseline_m = 0.0;
  Pose3d T_B_CL = Pose3d::Identity();  ///< left camera in the body frame: p_B = T_B_CL p_CL

  /// Right camera in the body frame.
  Pose3d T_B_CR() const;
};

/// The CADRE rig of SPEC 11 at `scale` (image size relative to 1600 x 1300):
/// width = round(1600 scale), height = round(1300 scale), f = 671 scale px,
/// principal point at the image centre ((w-1)/2, (h-1)/2), baseline 0.05 m; left camera
/// at body (0, 0.025, 0.15) looking along body +x, pitched down so that the top edge of
/// the image (v = -0.5) looks 10 deg above the horizon. Numbers are rounded to 12
/// significant digits, as written to calibration.yaml. Throws Error if scale is outside
/// [0.05, 2].
StereoRig make_cadre_rig(double scale);

struct SimulationOptions {
  std::string scenario = "rocks";  ///< rocks | flat | ramp
  std::uint64_t seed = 1;
  int frames = 8;
  double scale = 0.4;    ///< image size relative to CADRE's 1600 x 1300, f = 671 px
  double step_m = 0.04;  ///< forward travel per frame along +x (1 Hz: 4 cm/s, SPEC 11)
  double ramp_deg = 15.0;
  /// Write gt_height.jdem / gt_hazard.jdem over the travelled area +- margin.
  bool write_ground_truth = false;
  double ground_truth_resolution_m = 0.01;
  double ground_truth_margin_m = 2.0;

  /// Square side of the terrain's detail grid, placed from 2.5 m behind the start
  /// (more if the ground-truth margin needs it) and extended to reach at least 5.5 m
  /// beyond the last pose. Beyond the grid the ground continues at its edge values.
  double terrain_size_m = 8.0;
  double terrain_resolution_m = 0.01;
  FractalNoiseOptions ground_noise;   ///< rocks scenario only
  RockFieldOptions rock_field;        ///< rocks scenario only
  std::vector<Rock> extra_rocks;      ///< added in every scenario
  RenderOptions render;
  int png_compression = 9;  ///< zlib level 0-9 for the PNG files
};

/// Throws Error naming the option if it is unusable (frames < 1, scale outside
/// [0.05, 2], negative or non-finite step, ...). Terrain options are checked by
/// make_simulation_terrain.
void validate(const SimulationOptions& options);

/// The terrain simulate_sequence renders (same options => same terrain).
Terrain make_simulation_terrain(const SimulationOptions& options);

/// Body poses T_W_B of the frames: x = k step_m, y = 0, z = ground height there (rocks
/// are ignored: the body origin follows the ground), identity rotation. Rounded as written
/// to poses.txt.
std::vector<Pose3d> simulation_path(const SimulationOptions& options, const Terrain& terrain);

/// Renders the sequence into `out_dir`:
///   left/<name>.png, right/<name>.png   8-bit grey, name = 6-digit frame index (000000)
///   poses.txt          '#' comment lines, then `name t x y z qx qy qz qw` (t = index s)
///   calibration.yaml   SPEC 2 format (rectified: identical K, zero D, R = I, T = (-B,0,0))
///   simulation.yaml    the options used and the rock list (for people and tools)
///   gt_height.jdem, gt_hazard.jdem   if write_ground_truth (SPEC 9/10)
/// Creates folders as needed; files of the same names are replaced atomically, other
/// files are left alone. Same options => byte-identical files, for any thread count.
/// Throws Error on invalid options or I/O failure.
void simulate_sequence(const SimulationOptions& options, const std::filesystem::path& out_dir);

}  // namespace hazmap::sim
