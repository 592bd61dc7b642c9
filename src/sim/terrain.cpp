#include "hazmap/sim/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Quintic fade 6t^5 - 15t^4 + 10t^3: zero first and second derivative at the lattice,
// so the noise has no visible grid creases in shading.
inline double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

inline double lerp(double a, double b, double t) { return a + (b - a) * t; }

// floor() as an integer without a libm call (baseline x86-64 has no inline roundsd).
inline std::int64_t floor_to_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i - static_cast<std::int64_t>(x < static_cast<double>(i));
}

// Random value in [-1, 1] at a lattice point. One finaliser over a linear combination of
// the coordinates (large odd multipliers, no collisions at any practical range) is enough:
// the texture is the renderer's hot spot.
inline double lattice_value(std::uint64_t key, std::int64_t ix, std::int64_t iy) {
  const std::uint64_t h = mix64(key + static_cast<std::uint64_t>(ix) * 0xD1B54A32D192ED03ULL +
                                static_cast<std::uint64_t>(iy) * 0xABC98388FB8FAC03ULL);
  return 2.0 * unit_double(h) - 1.0;
}

inline double lattice_value(std::uint64_t key, std::int64_t ix, std::int64_t iy,
                            std::int64_t iz) {
  const std::uint64_t h = mix64(key + static_cast<std::uint64_t>(ix) * 0xD1B54A32D192ED03ULL +
                                static_cast<std::uint64_t>(iy) * 0xABC98388FB8FAC03ULL +
                                static_cast<std::uint64_t>(iz) * 0x8CB92BA72F3D8DD7ULL);
  return 2.0 * unit_double(h) - 1.0;
}

// Uniform in [lo, hi) from the engine's raw output (portable, unlike the std distributions).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * unit_double(rng());
}

int uniform_int(std::mt19937_64& rng, int lo, int hi) {  // inclusive
  const auto span = static_cast<std::uint64_t>(hi - lo + 1);
  return lo + static_cast<int>(rng() % span);  // bias < 2^-60 for small spans
}

// Height of rock i's cap at (x, y), or -inf outside its footprint.
inline double rock_cap_height(const Rock& rock, const Eigen::Vector3d& center_W, double x_m,
                              double y_m) {
  const double dx = x_m - rock.x_m;
  const double dy = y_m - rock.y_m;
  const double r2 = rock.radius_m * rock.radius_m - dx * dx - dy * dy;
  if (r2 <= 0.0) return -std::numeric_limits<double>::infinity();
  return center_W.z() + std::sqrt(r2);
}

JdemGrid make_grid(const std::string& quantity, double resolution_m,
                   const Eigen::Vector2d& center_W, int rows, int cols) {
  check(resolution_m > 0.0 && std::isfinite(resolution_m),
        "ground truth: resolution must be positive");
  check(rows > 0 && cols > 0, "ground truth: rows and cols must be positive");
  JdemGrid grid;
  grid.quantity = quantity;
  grid.units = "m";
  grid.rows = rows;
  grid.cols = cols;
  grid.resolution_m = resolution_m;
  grid.center_x_m = center_W.x();
  grid.center_y_m = center_W.y();
  grid.yaw_rad = 0.0;
  grid.values.assign(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols), 0.0f);
  return grid;
}

// Calls f(row, col, x, y) for each cell centre in JDEM order.
template <typename F>
void for_each_cell_center(const JdemGrid& grid, F&& f) {
  for (int row = 0; row < grid.rows; ++row) {
    const double y_m = grid.center_y_m + (0.5 * (grid.rows - 1) - row) * grid.resolution_m;
    for (int col = 0; col < grid.cols; ++col) {
      const double x_m = grid.center_x_m + (col - 0.5 * (grid.cols - 1)) * grid.resolution_m;
      f(row, col, x_m, y_m);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Noise primitives

std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

std::uint64_t hash_combine(std::uint64_t key, std::uint64_t value) {
  return mix64(key ^ mix64(value));
}

double unit_double(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * (1.0 / 9007199254740992.0);  // 2^-53
}

double value_noise_2d(double x, double y, std::uint64_t key) {
  const std::int64_t ix = floor_to_int(x);
  const std::int64_t iy = floor_to_int(y);
  const double tx = fade(x - static_cast<double>(ix));
  const double ty = fade(y - static_cast<double>(iy));
  const double v00 = lattice_value(key, ix, iy);
  const double v10 = lattice_value(key, ix + 1, iy);
  const double v01 = lattice_value(key, ix, iy + 1);
  const double v11 = lattice_value(key, ix + 1, iy + 1);
  return lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty);
}

double value_noise_3d(double x, double y, double z, std::uint64_t key) {
  const std::int64_t ix = floor_to_int(x);
  const std::int64_t iy = floor_to_int(y);
  const std::int64_t iz = floor_to_int(z);
  const double tx = fade(x - static_cast<double>(ix));
  const double ty = fade(y - static_cast<double>(iy));
  const double tz = fade(z - static_cast<double>(iz));
  double layer[2];
  for (int k = 0; k < 2; ++k) {
    const double v00 = lattice_value(key, ix, iy, iz + k);
    const double v10 = lattice_value(key, ix + 1, iy, iz + k);
    const double v01 = lattice_value(key, ix, iy + 1, iz + k);
    const double v11 = lattice_value(key, ix + 1, iy + 1, iz + k);
    layer[k] = lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty);
  }
  return lerp(layer[0], layer[1], tz);
}

// ---------------------------------------------------------------------------------------
// Terrain

Terrain::Terrain(const GroundPlane& plane, Heightfield detail, std::vector<Rock> rocks)
    : plane_(plane), detail_(std::move(detail)), rocks_(std::move(rocks)) {
  const bool empty = detail_.nodes_x == 0 && detail_.nodes_y == 0 && detail_.heights_m.empty();
  if (!empty) {
    check(detail_.nodes_x >= 2 && detail_.nodes_y >= 2,
          "terrain: a heightfield needs at least 2 x 2 nodes");
    check(detail_.resolution_m > 0.0, "terrain: heightfield resolution must be positive");
    check(detail_.heights_m.size() == static_cast<std::size_t>(detail_.nodes_x) *
                                          static_cast<std::size_t>(detail_.nodes_y),
          "terrain: heightfield has " + std::to_string(detail_.heights_m.size()) +
              " values, expected nodes_x * nodes_y");
  }

  // Bilinear interpolation: within a cell, dh/dx is a blend of the two x-differences on
  // the cell's edges, so the largest |x-difference| bounds |dh/dx| (same for y), and the
  // clamped continuation outside the grid only repeats edge gradients.
  double max_dx = 0.0;
  double max_dy = 0.0;
  double max_detail = 0.0;
  if (!empty) {
    const int nx = detail_.nodes_x;
    const int ny = detail_.nodes_y;
    const auto& h = detail_.heights_m;
    max_detail = -std::numeric_limits<double>::infinity();
    for (int iy = 0; iy < ny; ++iy) {
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        max_detail = std::max(max_detail, static_cast<double>(h[i]));
        if (ix + 1 < nx) max_dx = std::max(max_dx, std::abs(static_cast<double>(h[i + 1]) - h[i]));
        if (iy + 1 < ny) max_dy = std::max(max_dy, std::abs(static_cast<double>(h[i + nx]) - h[i]));
      }
    }
    max_dx /= detail_.resolution_m;
    max_dy /= detail_.resolution_m;
  }
  // Small relative margin: the bound must hold for the rounded arithmetic too.
  max_ground_gradient_ =
      (std::hypot(plane_.slope_x, plane_.slope_y) + std::hypot(max_dx, max_dy)) * (1.0 + 1e-9) +
      1e-12;
  max_ground_height_m_ = (plane_.slope_x == 0.0 && plane_.slope_y == 0.0)
                             ? plane_.offset_m + max_detail
                             : std::numeric_limits<double>::infinity();

  rock_centers_W_.reserve(rocks_.size());
  for (std::size_t i = 0; i < rocks_.size(); ++i) {
    const Rock& rock = rocks_[i];
    check(rock.radius_m > 0.0 && std::isfinite(rock.radius_m),
          "terrain: rock " + std::to_string(i) + " needs a positive radius");
    check(rock.buried_m >= 0.0 && rock.buried_m < rock.radius_m,
          "terrain: rock " + std::to_string(i) + " needs 0 <= buried < radius");
    rock_centers_W_.emplace_back(rock.x_m, rock.y_m,
                                 ground_height_m(rock.x_m, rock.y_m) - rock.buried_m);
  }
}

double Terrain::detail_height_m(double x_m, double y_m) const {
  if (detail_.heights_m.empty()) return 0.0;
  const double gx = (x_m - detail_.origin_x_m) / detail_.resolution_m;
  const double gy = (y_m - detail_.origin_y_m) / detail_.resolution_m;
  // Clamp to the grid: outside, the edge values continue.
  const double cx = std::clamp(gx, 0.0, static_cast<double>(detail_.nodes_x - 1));
  const double cy = std::clamp(gy, 0.0, static_cast<double>(detail_.nodes_y - 1));
  const int ix = std::min(static_cast<int>(cx), detail_.nodes_x - 2);
  const int iy = std::min(static_cast<int>(cy), detail_.nodes_y - 2);
  const double tx = cx - ix;
  const double ty = cy - iy;
  const std::size_t i = static_cast<std::size_t>(iy) * detail_.nodes_x + ix;
  const float* h = detail_.heights_m.data();
  const double h0 = lerp(h[i], h[i + 1], tx);
  const double h1 = lerp(h[i + detail_.nodes_x], h[i + detail_.nodes_x + 1], tx);
  return lerp(h0, h1, ty);
}

double Terrain::ground_height_m(double x_m, double y_m) const {
  return plane_.offset_m + plane_.slope_x * x_m + plane_.slope_y * y_m +
         detail_height_m(x_m, y_m);
}

double Terrain::height_m(double x_m, double y_m) const {
  double z = ground_height_m(x_m, y_m);
  for (std::size_t i = 0; i < rocks_.size(); ++i) {
    z = std::max(z, rock_cap_height(rocks_[i], rock_centers_W_[i], x_m, y_m));
  }
  return z;
}

Eigen::Vector3d Terrain::ground_normal_W(double x_m, double y_m) const {
  double gx = plane_.slope_x;
  double gy = plane_.slope_y;
  if (!detail_.heights_m.empty()) {
    const double e = detail_.resolution_m;
    gx += (detail_height_m(x_m + e, y_m) - detail_height_m(x_m - e, y_m)) / (2.0 * e);
    gy += (detail_height_m(x_m, y_m + e) - detail_height_m(x_m, y_m - e)) / (2.0 * e);
  }
  return Eigen::Vector3d(-gx, -gy, 1.0).normalized();
}

JdemGrid Terrain::ground_truth_height(double resolution_m, const Eigen::Vector2d& center_W,
                                      int rows, int cols) const {
  JdemGrid grid = make_grid("height", resolution_m, center_W, rows, cols);
  for_each_cell_center(grid, [&](int row, int col, double x_m, double y_m) {
    grid.at(row, col) = static_cast<float>(height_m(x_m, y_m));
  });
  return grid;
}

JdemGrid Terrain::ground_truth_hazard(double resolution_m, const Eigen::Vector2d& center_W,
                                      int rows, int cols) const {
  JdemGrid grid = make_grid("hazard", resolution_m, center_W, rows, cols);
  for_each_cell_center(grid, [&](int row, int col, double x_m, double y_m) {
    grid.at(row, col) =
        static_cast<float>(std::max(0.0, height_m(x_m, y_m) - ground_height_m(x_m, y_m)));
  });
  return grid;
}

// ---------------------------------------------------------------------------------------
// Generators and scenarios

const std::vector<std::string>& terrain_scenarios() {
  static const std::vector<std::string> names = {"flat", "ramp", "rocks"};
  return names;
}

void validate(const TerrainOptions& options) {
  const auto& names = terrain_scenarios();
  check(std::find(names.begin(), names.end(), options.scenario) != names.end(),
        "terrain: unknown scenario '" + options.scenario + "' (flat | ramp | rocks)");
  check(options.center_W.allFinite(), "terrain: center_W must be finite");
  check(options.size_x_m > 0.0 && options.size_y_m > 0.0,
        "terrain: size_x_m and size_y_m must be positive");
  check(options.resolution_m > 0.0, "terrain: resolution_m must be positive");
  check(options.size_x_m / options.resolution_m <= 20000.0 &&
            options.size_y_m / options.resolution_m <= 20000.0,
        "terrain: more than 20000 nodes along an axis; increase resolution_m");
  check(std::abs(options.ramp_deg) < 80.0, "terrain: |ramp_deg| must be below 80");
  const FractalNoiseOptions& n = options.noise;
  check(n.amplitude_m >= 0.0, "terrain: noise.amplitude_m must be >= 0");
  check(n.wavelength_m > 0.0, "terrain: noise.wavelength_m must be positive");
  check(n.octaves >= 0 && n.octaves <= 16, "terrain: noise.octaves must be in [0, 16]");
  check(n.gain >= 0.0 && n.gain < 1.0, "terrain: noise.gain must be in [0, 1)");
  const RockFieldOptions& r = options.rock_field;
  check(r.min_count >= 0 && r.max_count >= r.min_count,
        "terrain: rock_field needs 0 <= min_count <= max_count");
  check(r.min_radius_m > 0.0 && r.max_radius_m >= r.min_radius_m,
        "terrain: rock_field needs 0 < min_radius_m <= max_radius_m");
  check(r.max_x_m >= r.min_x_m, "terrain: rock_field needs min_x_m <= max_x_m");
  check(r.max_abs_y_m >= 0.0, "terrain: rock_field.max_abs_y_m must be >= 0");
  check(r.max_buried_fraction >= 0.0 && r.max_buried_fraction < 1.0,
        "terrain: rock_field.max_buried_fraction must be in [0, 1)");
  check(r.min_gap_m >= 0.0, "terrain: rock_field.min_gap_m must be >= 0");
}

Heightfield make_fractal_heightfield(const Eigen::Vector2d& center_W, double size_x_m,
                                     double size_y_m, double resolution_m,
                                     const FractalNoiseOptions& noise, std::uint64_t key) {
  Heightfield field;
  field.resolution_m = resolution_m;
  field.nodes_x = static_cast<int>(std::ceil(size_x_m / resolution_m)) + 1;
  field.nodes_y = static_cast<int>(std::ceil(size_y_m / resolution_m)) + 1;
  field.origin_x_m = center_W.x() - 0.5 * (field.nodes_x - 1) * resolution_m;
  field.origin_y_m = center_W.y() - 0.5 * (field.nodes_y - 1) * resolution_m;
  field.heights_m.assign(static_cast<std::size_t>(field.nodes_x) * field.nodes_y, 0.0f);

  std::vector<std::uint64_t> octave_keys;
  for (int k = 0; k < noise.octaves; ++k) octave_keys.push_back(hash_combine(key, k));
  for (int iy = 0; iy < field.nodes_y; ++iy) {
    const double y_m = field.origin_y_m + iy * resolution_m;
    for (int ix = 0; ix < field.nodes_x; ++ix) {
      const double x_m = field.origin_x_m + ix * resolution_m;
      double z = 0.0;
      double amplitude = noise.amplitude_m;
      double wavelength = noise.wavelength_m;
      for (int k = 0; k < noise.octaves; ++k) {
        z += amplitude * value_noise_2d(x_m / wavelength, y_m / wavelength, octave_keys[k]);
        amplitude *= noise.gain;
        wavelength *= 0.5;
      }
      field.heights_m[static_cast<std::size_t>(iy) * field.nodes_x + ix] = static_cast<float>(z);
    }
  }
  return field;
}

std::vector<Rock> place_random_rocks(const RockFieldOptions& field, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int count = uniform_int(rng, field.min_count, field.max_count);
  std::vector<Rock> rocks;
  constexpr int kMaxAttempts = 10000;
  for (int attempt = 0; attempt < kMaxAttempts && static_cast<int>(rocks.size()) < count;
       ++attempt) {
    Rock rock;
    rock.radius_m = uniform(rng, field.min_radius_m, field.max_radius_m);
    rock.x_m = uniform(rng, field.min_x_m, field.max_x_m);
    rock.y_m = uniform(rng, -field.max_abs_y_m, field.max_abs_y_m);
    rock.buried_m = uniform(rng, 0.0, field.max_buried_fraction) * rock.radius_m;
    const bool overlaps = std::any_of(rocks.begin(), rocks.end(), [&](const Rock& other) {
      return std::hypot(rock.x_m - other.x_m, rock.y_m - other.y_m) <
             rock.radius_m + other.radius_m + field.min_gap_m;
    });
    if (!overlaps) rocks.push_back(rock);
  }
  check(static_cast<int>(rocks.size()) == count,
        "terrain: cannot place " + std::to_string(count) +
            " non-overlapping rocks in the rock_field box; enlarge it or lower the count");
  return rocks;
}

Terrain make_terrain(const TerrainOptions& options) {
  validate(options);
  // One master engine; each component takes its own key so that changing, say, the
  // rock count does not reshuffle the ground.
  std::mt19937_64 rng(options.seed);
  const std::uint64_t ground_key = rng();
  const std::uint64_t rock_seed = rng();

  GroundPlane plane;
  Heightfield detail;
  std::vector<Rock> rocks;
  if (options.scenario == "ramp") {
    plane.slope_x = std::tan(options.ramp_deg * kPi / 180.0);
  } else if (options.scenario == "rocks") {
    rocks = place_random_rocks(options.rock_field, rock_seed);  // may throw: do it first
    detail = make_fractal_heightfield(options.center_W, options.size_x_m, options.size_y_m,
                                      options.resolution_m, options.noise, ground_key);
  }
  rocks.insert(rocks.end(), options.extra_rocks.begin(), options.extra_rocks.end());
  return Terrain(plane, std::move(detail), std::move(rocks));
}

}  // namespace hazmap::sim
