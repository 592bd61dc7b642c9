#pragma once
// Synthetic terrain for the simulator: a ground surface (an analytic plane and sine wave
// plus a detail heightfield sampled on a regular grid, which carries fractal noise and
// craters) with analytic spherical-cap rocks on top.
//
// The ground is what a rover drives on; rocks are obstacles. Ground truth for the
// evaluation (SPEC 10) is sampled from the same functions the renderer ray-casts, so the
// synthetic images and the ground-truth grids agree to the ray-casting tolerance.
//
// Everything here is in the world frame W (x forward at the start, y left, z up), metres.
// Randomness is seeded: the same options give bit-identical terrain on every platform
// (std::mt19937_64 is fully specified; we convert its output to numbers ourselves
// because the std distributions are implementation-defined).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hazmap/io/jdem.hpp"
#include "hazmap/sim/rock_grid.hpp"

namespace hazmap::sim {

// ---------------------------------------------------------------------------------------
// Noise primitives, shared by the terrain generator and the renderer's texture.

/// SplitMix64 finaliser: a fast, well-mixed 64-bit hash. Counter-based randomness built on
/// it does not depend on evaluation order or threading.
std::uint64_t mix64(std::uint64_t x);

/// Hash of a key and one more value, for deriving independent streams.
std::uint64_t hash_combine(std::uint64_t key, std::uint64_t value);

/// Uniform double in [0, 1) from the top 53 bits of a 64-bit value.
double unit_double(std::uint64_t bits);

/// Value noise on the unit integer lattice: random values in [-1, 1] at lattice points
/// (hashed from `key`), blended with a quintic fade, so the field is C2 and band-limited
/// to wavelengths of about one lattice unit and longer. Deterministic in (x, y, key).
double value_noise_2d(double x, double y, std::uint64_t key);

/// Same in 3-D (used to texture rocks without stretching on their steep sides).
double value_noise_3d(double x, double y, double z, std::uint64_t key);

// ---------------------------------------------------------------------------------------
// Terrain description.

/// A rock: a sphere of radius `radius_m` whose centre lies `buried_m` below the ground
/// height at (x_m, y_m). Only the part above the ground is solid, so on flat ground its
/// top stands radius_m - buried_m above the ground.
struct Rock {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.05;
  double buried_m = 0.0;
};

/// Heights at the nodes of a regular grid: node (ix, iy) sits at W position
/// (origin_x_m + ix * resolution_m, origin_y_m + iy * resolution_m).
/// An empty heightfield (0 nodes) stands for zero everywhere.
struct Heightfield {
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double resolution_m = 0.01;
  int nodes_x = 0;
  int nodes_y = 0;
  std::vector<float> heights_m;  ///< index iy * nodes_x + ix
};

/// The plane z = offset_m + slope_x * x + slope_y * y (slopes are dz/dx, dz/dy).
struct GroundPlane {
  double offset_m = 0.0;
  double slope_x = 0.0;
  double slope_y = 0.0;
};

/// A sine wave varying along one horizontal direction only (ridges run across it):
/// z = amplitude_m sin(2 pi s / wavelength_m), s = x cos(direction) + y sin(direction).
/// Its steepest slope is atan(2 pi amplitude_m / wavelength_m).
struct SineWave {
  double amplitude_m = 0.0;  ///< 0: no wave
  double wavelength_m = 1.0;
  double direction_rad = 0.0;  ///< of the wave vector, from W +x towards +y

  double height_m(double x_m, double y_m) const {
    if (amplitude_m == 0.0) return 0.0;
    const double s_m = direction_rad == 0.0
                           ? x_m
                           : x_m * std::cos(direction_rad) + y_m * std::sin(direction_rad);
    return amplitude_m * std::sin(2.0 * 3.14159265358979323846 * s_m / wavelength_m);
  }
  /// Steepest slope dz/ds = 2 pi amplitude / wavelength (a tangent, not an angle).
  double max_slope() const;
};

/// A crater: a parabolic bowl inside the rim crest, a raised rim, and an ejecta blanket
/// that decays to nothing at three radii. Relief added to the ground at distance r from
/// the centre (R = radius_m, h = rim_height_m, D = depth_m):
///   r <= R:       -D + (h + D) (r / R)^2
///   R < r < 3R:   h ((R / r)^3 - 1/27) / (1 - 1/27)
///   r >= 3R:      0
/// Continuous everywhere; the slope jumps at the rim crest (a sharp rim). The inner wall
/// is steepest at the crest: 2 (h + D) / R.
struct Crater {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.5;      ///< rim crest radius
  double depth_m = 0.1;       ///< floor below the surrounding ground
  double rim_height_m = 0.02; ///< crest above the surrounding ground
};

/// The relief a crater adds at W position (x, y), metres (formula above).
double crater_relief_m(const Crater& crater, double x_m, double y_m);

/// Ground = plane + sine wave + bilinear interpolation of a detail heightfield (clamped
/// to its edge values outside the grid, so the ground is defined and continuous
/// everywhere), plus analytic rocks. Immutable after construction; all methods are
/// thread-safe.
class Terrain {
 public:
  /// Throws Error if the heightfield's size does not match nodes_x * nodes_y, if it has
  /// a single node along an axis, if a rock has a non-positive radius or buried_m
  /// outside [0, radius_m), or if the wave has a non-positive wavelength.
  Terrain(const GroundPlane& plane, const SineWave& wave, Heightfield detail,
          std::vector<Rock> rocks);
  /// Same without a wave.
  Terrain(const GroundPlane& plane, Heightfield detail, std::vector<Rock> rocks)
      : Terrain(plane, SineWave(), std::move(detail), std::move(rocks)) {}

  /// Ground height (rocks excluded) at W position (x, y), metres. Defined everywhere.
  /// Inline: the ray marcher calls it tens of times per ray.
  double ground_height_m(double x_m, double y_m) const {
    return plane_.offset_m + plane_.slope_x * x_m + plane_.slope_y * y_m +
           wave_.height_m(x_m, y_m) + detail_height_m(x_m, y_m);
  }

  /// Surface height at (x, y): the ground, or the top of a rock cap where that is higher.
  /// Exact (analytic rock caps on the bilinear ground).
  double height_m(double x_m, double y_m) const;

  /// Upward unit normal of the ground at (x, y), from central differences one detail
  /// cell wide (smooth enough for shading; exact for a plane).
  Eigen::Vector3d ground_normal_W(double x_m, double y_m) const;

  /// An upper bound G on |grad ground| over the whole plane. Ray marching relies on it:
  /// along a unit ray d, height above ground decreases at most at |d_z| + G |d_xy|.
  double max_ground_gradient() const { return max_ground_gradient_; }

  /// Largest ground height anywhere (an upper bound), metres; +inf for a sloped plane.
  double max_ground_height_m() const { return max_ground_height_m_; }

  const std::vector<Rock>& rocks() const { return rocks_; }

  /// W position of rock i's sphere centre: (x, y, ground(x, y) - buried).
  Eigen::Vector3d rock_center_W(std::size_t i) const { return rock_centers_W_[i]; }

  const GroundPlane& plane() const { return plane_; }
  const SineWave& wave() const { return wave_; }
  const Heightfield& detail() const { return detail_; }

  /// Spatial index of the rocks, for ray casting with many rocks.
  const RockGrid& rock_grid() const { return rock_grid_; }

  /// Ground-truth surface height (rocks included) at the centres of a rows x cols grid
  /// with cells of `resolution_m`, centred on `center_W` (JDEM layout, SPEC 9: row 0 =
  /// largest y, column 0 = smallest x, yaw 0). Choose the centre so that the cell borders
  /// fall on multiples of the resolution (SPEC 1). Throws Error on non-positive sizes.
  JdemGrid ground_truth_height(double resolution_m, const Eigen::Vector2d& center_W,
                               int rows, int cols) const;

  /// Ground-truth hazard on the same layout: obstacle height above the ground at each
  /// cell centre, height_m - ground_height_m (metres, 0 where there is no rock; SPEC 9).
  JdemGrid ground_truth_hazard(double resolution_m, const Eigen::Vector2d& center_W,
                               int rows, int cols) const;

 private:
  /// Bilinear interpolation of the detail grid, clamped to its edge values.
  double detail_height_m(double x_m, double y_m) const {
    if (detail_.heights_m.empty()) return 0.0;
    const double gx = (x_m - detail_.origin_x_m) / detail_.resolution_m;
    const double gy = (y_m - detail_.origin_y_m) / detail_.resolution_m;
    const double cx = std::clamp(gx, 0.0, static_cast<double>(detail_.nodes_x - 1));
    const double cy = std::clamp(gy, 0.0, static_cast<double>(detail_.nodes_y - 1));
    const int ix = std::min(static_cast<int>(cx), detail_.nodes_x - 2);
    const int iy = std::min(static_cast<int>(cy), detail_.nodes_y - 2);
    const double tx = cx - ix;
    const double ty = cy - iy;
    const std::size_t i = static_cast<std::size_t>(iy) * detail_.nodes_x + ix;
    const float* h = detail_.heights_m.data();
    const double h0 = h[i] + (h[i + 1] - static_cast<double>(h[i])) * tx;
    const double h1 = h[i + detail_.nodes_x] +
                      (h[i + detail_.nodes_x + 1] - static_cast<double>(h[i + detail_.nodes_x])) * tx;
    return h0 + (h1 - h0) * ty;
  }

  GroundPlane plane_;
  SineWave wave_;
  Heightfield detail_;
  std::vector<Rock> rocks_;
  std::vector<Eigen::Vector3d> rock_centers_W_;
  double max_ground_gradient_ = 0.0;
  double max_ground_height_m_ = 0.0;
  RockGrid rock_grid_;
};

// ---------------------------------------------------------------------------------------
// Generators and scenarios.

/// Fractal (multi-octave) value noise: octave k has wavelength wavelength_m / 2^k and
/// amplitude amplitude_m * gain^k. The sum stays within +-amplitude_m / (1 - gain).
struct FractalNoiseOptions {
  double amplitude_m = 0.015;  ///< amplitude of the longest octave
  double wavelength_m = 2.0;   ///< wavelength of the longest octave
  int octaves = 5;
  double gain = 0.5;  ///< amplitude ratio between successive octaves
};

/// How object sizes (rock or crater radii) are drawn between a minimum and a maximum.
///   uniform   : radius uniform in [min, max);
///   power_law : cumulative N(> r) proportional to r^-exponent, truncated to [min, max)
///               (small objects far more common than large ones, as on the Moon).
enum class SizeDistribution { uniform, power_law };

/// "uniform" | "power_law" -> enum; throws Error naming `what` otherwise.
SizeDistribution parse_size_distribution(const std::string& name, const std::string& what);
const char* size_distribution_name(SizeDistribution distribution);

/// Draws a radius in [min_m, max_m) from one uniform u in [0, 1) (inverse CDF).
double draw_radius_m(SizeDistribution distribution, double exponent, double min_m,
                     double max_m, double u);

/// Random, non-overlapping rocks in a box (rocks scenario; by default just ahead of the
/// start, so a short sequence drives up to them).
struct RockFieldOptions {
  int min_count = 3;
  int max_count = 5;
  /// > 0: the count is round(density * box area) instead of a draw in [min, max].
  double density_per_m2 = 0.0;
  double min_radius_m = 0.03;
  double max_radius_m = 0.08;  ///< equal to min_radius_m: every rock has that radius
  SizeDistribution size_distribution = SizeDistribution::uniform;
  double power_law_exponent = 2.5;  ///< cumulative exponent (power_law only)
  double min_x_m = 0.25;  ///< range of rock centres along W x
  double max_x_m = 0.9;
  double max_abs_y_m = 0.35;  ///< |y| of rock centres
  double max_buried_fraction = 0.3;  ///< buried_m is uniform in [0, this * radius)
  double min_gap_m = 0.02;  ///< free space between neighbouring rocks
};

/// Random craters in a box (craters scenario). Craters may overlap (their relief adds up).
struct CraterFieldOptions {
  int min_count = 5;
  int max_count = 8;
  double density_per_m2 = 0.0;  ///< > 0: count = round(density * box area)
  double min_radius_m = 0.15;
  double max_radius_m = 0.8;
  SizeDistribution size_distribution = SizeDistribution::power_law;
  double power_law_exponent = 2.0;
  /// Depth below the surrounding ground and rim height, as fractions of the diameter.
  /// 0.1 and 0.02 make inner walls of 2 (0.02 + 0.1) 2R / R = 0.48, i.e. 26 deg at the
  /// crest: a hazard at the rim, traversable floors (fresh lunar craters reach 0.2).
  double depth_ratio = 0.1;
  double rim_ratio = 0.02;
  double min_x_m = 0.5;  ///< range of crater centres along W x
  double max_x_m = 6.0;
  double max_abs_y_m = 2.5;
  /// No rim comes closer than this to the W origin (the start), so the rover starts on
  /// undisturbed ground.
  double clear_radius_m = 0.4;
};

/// Everything that defines a terrain. Scenarios (SPEC 13 `hazmap simulate --scenario`):
///   flat    : z = 0;
///   ramp    : z = x tan(ramp_deg), rising along +x;
///   sine    : the sine wave `sine` alone (default 5 cm amplitude, 1 m wavelength along
///             +x: steepest slope 17.4 deg), for drift tests;
///   rocks   : fractal-noise ground (gentle, traversable) plus a random rock field;
///   craters : fractal-noise ground plus a random crater field.
/// `extra_rocks` and `extra_craters` are added in every scenario; `scatter_rocks` adds the
/// random rock field to scenarios other than rocks.
struct TerrainOptions {
  std::string scenario = "rocks";
  std::uint64_t seed = 1;
  Eigen::Vector2d center_W = Eigen::Vector2d(1.5, 0.0);  ///< centre of the detail grid
  double size_x_m = 8.0;        ///< extent of the detail grid (ground beyond is clamped)
  double size_y_m = 8.0;
  double resolution_m = 0.01;   ///< node spacing of the detail grid
  double ramp_deg = 15.0;
  SineWave sine{0.05, 1.0, 0.0};
  FractalNoiseOptions noise;
  RockFieldOptions rock_field;
  bool scatter_rocks = false;
  CraterFieldOptions crater_field;
  std::vector<Rock> extra_rocks;
  std::vector<Crater> extra_craters;
  /// Random rocks whose footprint comes closer than keep_clear_m to any of these points
  /// are drawn again (a path the rover can drive without touching a rock). Extra rocks
  /// are kept regardless.
  std::vector<Eigen::Vector2d> keep_clear_W;
  double keep_clear_m = 0.0;
};

/// The scenario names make_terrain accepts.
const std::vector<std::string>& terrain_scenarios();

/// Throws Error naming the offending field if the options are unusable (unknown
/// scenario, non-positive sizes or resolution, |ramp_deg| >= 80, negative noise, ...).
void validate(const TerrainOptions& options);

/// Fills a heightfield covering at least size_x_m x size_y_m around center_W with fractal
/// value noise. Its nodes lie on the global lattice (integer multiples of resolution_m),
/// so the height at a node depends only on its position, the noise options and the key:
/// grids of different extent agree where they overlap.
Heightfield make_fractal_heightfield(const Eigen::Vector2d& center_W, double size_x_m,
                                     double size_y_m, double resolution_m,
                                     const FractalNoiseOptions& noise, std::uint64_t key);

/// Adds crater_relief_m to every node of `field` (exact at the nodes; the terrain
/// interpolates bilinearly between them).
void add_crater(const Crater& crater, Heightfield& field);

/// Draws a rock field: rejection sampling of centres and radii until the count (drawn in
/// [min_count, max_count], or from the density) is reached. `keep_clear_W` and
/// `keep_clear_m` as in TerrainOptions. Throws Error if the box cannot hold the rocks.
std::vector<Rock> place_random_rocks(const RockFieldOptions& field, std::uint64_t seed,
                                     const std::vector<Eigen::Vector2d>& keep_clear_W = {},
                                     double keep_clear_m = 0.0);

/// Draws a crater field (count from [min_count, max_count] or the density; centres
/// uniform in the box, outside clear_radius_m of the origin). Throws Error if the clear
/// zone leaves no room.
std::vector<Crater> place_random_craters(const CraterFieldOptions& field, std::uint64_t seed);

/// The craters make_terrain bakes into the ground for these options (random field, then
/// extra_craters), e.g. to list them beside a sequence.
std::vector<Crater> terrain_craters(const TerrainOptions& options);

/// Builds the terrain for `options` (validated first). Same options => identical terrain.
Terrain make_terrain(const TerrainOptions& options);

}  // namespace hazmap::sim
