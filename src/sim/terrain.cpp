#include "hazmap/sim/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "hazmap/core/error.hpp"
#include "hazmap/eval/ground_truth.hpp"

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
// Analytic ground features

double SineWave::max_slope() const { return 2.0 * kPi * std::abs(amplitude_m) / wavelength_m; }

double crater_relief_m(const Crater& crater, double x_m, double y_m) {
  const double R = crater.radius_m;
  const double r2 = (x_m - crater.x_m) * (x_m - crater.x_m) + (y_m - crater.y_m) * (y_m - crater.y_m);
  if (r2 <= R * R) return -crater.depth_m + (crater.rim_height_m + crater.depth_m) * r2 / (R * R);
  if (r2 >= 9.0 * R * R) return 0.0;
  const double q = R / std::sqrt(r2);
  return crater.rim_height_m * (q * q * q - 1.0 / 27.0) / (1.0 - 1.0 / 27.0);
}

// ---------------------------------------------------------------------------------------
// Terrain

Terrain::Terrain(const GroundPlane& plane, const SineWave& wave, Heightfield detail,
                 std::vector<Rock> rocks)
    : plane_(plane), wave_(wave), detail_(std::move(detail)), rocks_(std::move(rocks)) {
  check(wave_.wavelength_m > 0.0 && std::isfinite(wave_.wavelength_m) &&
            std::isfinite(wave_.amplitude_m),
        "terrain: the sine wave needs a positive wavelength and a finite amplitude");
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
  max_ground_gradient_ = (std::hypot(plane_.slope_x, plane_.slope_y) + wave_.max_slope() +
                          std::hypot(max_dx, max_dy)) *
                             (1.0 + 1e-9) +
                         1e-12;
  max_ground_height_m_ = (plane_.slope_x == 0.0 && plane_.slope_y == 0.0)
                             ? plane_.offset_m + std::abs(wave_.amplitude_m) + max_detail
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
  std::vector<double> radii_m;
  for (const Rock& rock : rocks_) radii_m.push_back(rock.radius_m);
  rock_grid_ = RockGrid(rock_centers_W_, radii_m);
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
  if (wave_.amplitude_m != 0.0) {
    const double c = std::cos(wave_.direction_rad);
    const double sn = std::sin(wave_.direction_rad);
    const double k = 2.0 * kPi / wave_.wavelength_m;
    const double dz_ds = wave_.amplitude_m * k * std::cos(k * (x_m * c + y_m * sn));
    gx += dz_ds * c;
    gy += dz_ds * sn;
  }
  if (!detail_.heights_m.empty()) {
    const double e = detail_.resolution_m;
    gx += (detail_height_m(x_m + e, y_m) - detail_height_m(x_m - e, y_m)) / (2.0 * e);
    gy += (detail_height_m(x_m, y_m + e) - detail_height_m(x_m, y_m - e)) / (2.0 * e);
  }
  return Eigen::Vector3d(-gx, -gy, 1.0).normalized();
}

JdemGrid Terrain::ground_truth_height(double resolution_m, const Eigen::Vector2d& center_W,
                                      int rows, int cols) const {
  JdemGrid grid = ground_truth_grid("height", resolution_m, center_W, rows, cols);
  for_each_cell_center(grid, [&](int row, int col, double x_m, double y_m) {
    grid.at(row, col) = static_cast<float>(height_m(x_m, y_m));
  });
  return grid;
}

JdemGrid Terrain::ground_truth_hazard(double resolution_m, const Eigen::Vector2d& center_W,
                                      int rows, int cols) const {
  JdemGrid grid = ground_truth_grid("hazard", resolution_m, center_W, rows, cols);
  for_each_cell_center(grid, [&](int row, int col, double x_m, double y_m) {
    grid.at(row, col) =
        static_cast<float>(obstacle_height_m(height_m(x_m, y_m), ground_height_m(x_m, y_m)));
  });
  return grid;
}

// ---------------------------------------------------------------------------------------
// Generators and scenarios

SizeDistribution parse_size_distribution(const std::string& name, const std::string& what) {
  if (name == "uniform") return SizeDistribution::uniform;
  if (name == "power_law" || name == "power") return SizeDistribution::power_law;
  throw Error(what + ": unknown size distribution '" + name + "' (uniform | power_law)");
}

const char* size_distribution_name(SizeDistribution distribution) {
  return distribution == SizeDistribution::uniform ? "uniform" : "power_law";
}

double draw_radius_m(SizeDistribution distribution, double exponent, double min_m,
                     double max_m, double u) {
  if (distribution == SizeDistribution::uniform || max_m <= min_m) {
    return min_m + (max_m - min_m) * u;
  }
  // Truncated Pareto: P(R > r) = ((min/r)^q - (min/max)^q) / (1 - (min/max)^q).
  const double tail = std::pow(min_m / max_m, exponent);
  return min_m * std::pow(1.0 - u * (1.0 - tail), -1.0 / exponent);
}

const std::vector<std::string>& terrain_scenarios() {
  static const std::vector<std::string> names = {"flat", "ramp", "sine", "rocks", "craters"};
  return names;
}

namespace {

void validate_field_box(double min_x, double max_x, double max_abs_y, const std::string& what) {
  check(std::isfinite(min_x) && std::isfinite(max_x) && max_x >= min_x,
        "terrain: " + what + " needs min_x_m <= max_x_m");
  check(std::isfinite(max_abs_y) && max_abs_y >= 0.0, "terrain: " + what + ".max_abs_y_m must be >= 0");
}

void validate_counts(int min_count, int max_count, double density, const std::string& what) {
  check(min_count >= 0 && max_count >= min_count,
        "terrain: " + what + " needs 0 <= min_count <= max_count");
  check(std::isfinite(density) && density >= 0.0, "terrain: " + what + ".density_per_m2 must be >= 0");
}

void validate_sizes(double min_m, double max_m, SizeDistribution distribution, double exponent,
                    const std::string& what) {
  check(min_m > 0.0 && std::isfinite(max_m) && max_m >= min_m,
        "terrain: " + what + " needs 0 < min_radius_m <= max_radius_m");
  check(distribution == SizeDistribution::uniform || (exponent > 0.0 && std::isfinite(exponent)),
        "terrain: " + what + ".power_law_exponent must be positive");
}

// Object count: from the density over the box, or a draw in [min, max]. Always consumes
// one draw so that switching modes does not shift the rest of the stream.
int draw_count(std::mt19937_64& rng, int min_count, int max_count, double density_per_m2,
               double box_area_m2, const std::string& what) {
  const int drawn = uniform_int(rng, min_count, max_count);
  if (density_per_m2 <= 0.0) return drawn;
  const double count = std::round(density_per_m2 * box_area_m2);
  check(count <= 100000.0, "terrain: " + what + " density gives more than 100000 objects");
  return static_cast<int>(count);
}

// Squared distance from p to the nearest of `points` (+inf if none).
double nearest_squared_m2(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& q : points) best = std::min(best, (q - p).squaredNorm());
  return best;
}

}  // namespace

void validate(const TerrainOptions& options) {
  const auto& names = terrain_scenarios();
  check(std::find(names.begin(), names.end(), options.scenario) != names.end(),
        "terrain: unknown scenario '" + options.scenario + "' (flat | ramp | sine | rocks | craters)");
  check(options.center_W.allFinite(), "terrain: center_W must be finite");
  check(options.size_x_m > 0.0 && options.size_y_m > 0.0,
        "terrain: size_x_m and size_y_m must be positive");
  check(options.resolution_m > 0.0, "terrain: resolution_m must be positive");
  check(options.size_x_m / options.resolution_m <= 20000.0 &&
            options.size_y_m / options.resolution_m <= 20000.0,
        "terrain: more than 20000 nodes along an axis; increase resolution_m");
  check(std::abs(options.ramp_deg) < 80.0, "terrain: |ramp_deg| must be below 80");
  check(std::isfinite(options.sine.amplitude_m) && options.sine.amplitude_m >= 0.0,
        "terrain: sine.amplitude_m must be >= 0");
  check(options.sine.wavelength_m > 0.0 && std::isfinite(options.sine.wavelength_m),
        "terrain: sine.wavelength_m must be positive");
  check(std::isfinite(options.sine.direction_rad), "terrain: sine.direction_rad must be finite");
  const FractalNoiseOptions& n = options.noise;
  check(n.amplitude_m >= 0.0, "terrain: noise.amplitude_m must be >= 0");
  check(n.wavelength_m > 0.0, "terrain: noise.wavelength_m must be positive");
  check(n.octaves >= 0 && n.octaves <= 16, "terrain: noise.octaves must be in [0, 16]");
  check(n.gain >= 0.0 && n.gain < 1.0, "terrain: noise.gain must be in [0, 1)");
  const RockFieldOptions& r = options.rock_field;
  validate_counts(r.min_count, r.max_count, r.density_per_m2, "rock_field");
  validate_sizes(r.min_radius_m, r.max_radius_m, r.size_distribution, r.power_law_exponent,
                 "rock_field");
  validate_field_box(r.min_x_m, r.max_x_m, r.max_abs_y_m, "rock_field");
  check(r.max_buried_fraction >= 0.0 && r.max_buried_fraction < 1.0,
        "terrain: rock_field.max_buried_fraction must be in [0, 1)");
  check(r.min_gap_m >= 0.0, "terrain: rock_field.min_gap_m must be >= 0");
  const CraterFieldOptions& c = options.crater_field;
  validate_counts(c.min_count, c.max_count, c.density_per_m2, "crater_field");
  validate_sizes(c.min_radius_m, c.max_radius_m, c.size_distribution, c.power_law_exponent,
                 "crater_field");
  validate_field_box(c.min_x_m, c.max_x_m, c.max_abs_y_m, "crater_field");
  check(c.depth_ratio >= 0.0 && c.depth_ratio <= 1.0, "terrain: crater_field.depth_ratio must be in [0, 1]");
  check(c.rim_ratio >= 0.0 && c.rim_ratio <= 1.0, "terrain: crater_field.rim_ratio must be in [0, 1]");
  check(c.clear_radius_m >= 0.0, "terrain: crater_field.clear_radius_m must be >= 0");
  for (const Crater& crater : options.extra_craters) {
    check(crater.radius_m > 0.0 && crater.depth_m >= 0.0 && crater.rim_height_m >= 0.0,
          "terrain: extra craters need a positive radius and non-negative depth and rim height");
  }
  check(options.keep_clear_m >= 0.0 && std::isfinite(options.keep_clear_m),
        "terrain: keep_clear_m must be >= 0");
}

Heightfield make_fractal_heightfield(const Eigen::Vector2d& center_W, double size_x_m,
                                     double size_y_m, double resolution_m,
                                     const FractalNoiseOptions& noise, std::uint64_t key) {
  // Nodes on the global lattice (integer multiples of the resolution), so that two grids
  // of different extent hold the same heights where they overlap.
  const double k0x = std::floor((center_W.x() - 0.5 * size_x_m) / resolution_m + 1e-9);
  const double k1x = std::ceil((center_W.x() + 0.5 * size_x_m) / resolution_m - 1e-9);
  const double k0y = std::floor((center_W.y() - 0.5 * size_y_m) / resolution_m + 1e-9);
  const double k1y = std::ceil((center_W.y() + 0.5 * size_y_m) / resolution_m - 1e-9);
  Heightfield field;
  field.resolution_m = resolution_m;
  field.nodes_x = static_cast<int>(k1x - k0x) + 1;
  field.nodes_y = static_cast<int>(k1y - k0y) + 1;
  field.origin_x_m = k0x * resolution_m;
  field.origin_y_m = k0y * resolution_m;
  field.heights_m.assign(static_cast<std::size_t>(field.nodes_x) * field.nodes_y, 0.0f);

  std::vector<std::uint64_t> octave_keys;
  for (int k = 0; k < noise.octaves; ++k) octave_keys.push_back(hash_combine(key, k));
  for (int iy = 0; iy < field.nodes_y; ++iy) {
    const double y_m = (k0y + iy) * resolution_m;
    for (int ix = 0; ix < field.nodes_x; ++ix) {
      const double x_m = (k0x + ix) * resolution_m;
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

void add_crater(const Crater& crater, Heightfield& field) {
  // Only nodes within the ejecta radius (3 R) change.
  const double reach_m = 3.0 * crater.radius_m;
  const int ix0 = std::max(0, static_cast<int>(std::floor((crater.x_m - reach_m - field.origin_x_m) /
                                                          field.resolution_m)));
  const int ix1 = std::min(field.nodes_x - 1,
                           static_cast<int>(std::ceil((crater.x_m + reach_m - field.origin_x_m) /
                                                      field.resolution_m)));
  const int iy0 = std::max(0, static_cast<int>(std::floor((crater.y_m - reach_m - field.origin_y_m) /
                                                          field.resolution_m)));
  const int iy1 = std::min(field.nodes_y - 1,
                           static_cast<int>(std::ceil((crater.y_m + reach_m - field.origin_y_m) /
                                                      field.resolution_m)));
  // Node positions exactly as make_fractal_heightfield computes them.
  const double k0x = std::round(field.origin_x_m / field.resolution_m);
  const double k0y = std::round(field.origin_y_m / field.resolution_m);
  for (int iy = iy0; iy <= iy1; ++iy) {
    const double y_m = (k0y + iy) * field.resolution_m;
    for (int ix = ix0; ix <= ix1; ++ix) {
      const double x_m = (k0x + ix) * field.resolution_m;
      float& h = field.heights_m[static_cast<std::size_t>(iy) * field.nodes_x + ix];
      h = static_cast<float>(h + crater_relief_m(crater, x_m, y_m));
    }
  }
}

std::vector<Rock> place_random_rocks(const RockFieldOptions& field, std::uint64_t seed,
                                     const std::vector<Eigen::Vector2d>& keep_clear_W,
                                     double keep_clear_m) {
  std::mt19937_64 rng(seed);
  const double box_area_m2 = (field.max_x_m - field.min_x_m) * 2.0 * field.max_abs_y_m;
  const int count = draw_count(rng, field.min_count, field.max_count, field.density_per_m2,
                               box_area_m2, "rock_field");
  std::vector<Rock> rocks;
  const int max_attempts = std::max(10000, 100 * count);
  for (int attempt = 0; attempt < max_attempts && static_cast<int>(rocks.size()) < count;
       ++attempt) {
    Rock rock;
    rock.radius_m = draw_radius_m(field.size_distribution, field.power_law_exponent,
                                  field.min_radius_m, field.max_radius_m, unit_double(rng()));
    rock.x_m = uniform(rng, field.min_x_m, field.max_x_m);
    rock.y_m = uniform(rng, -field.max_abs_y_m, field.max_abs_y_m);
    rock.buried_m = uniform(rng, 0.0, field.max_buried_fraction) * rock.radius_m;
    const bool overlaps = std::any_of(rocks.begin(), rocks.end(), [&](const Rock& other) {
      return std::hypot(rock.x_m - other.x_m, rock.y_m - other.y_m) <
             rock.radius_m + other.radius_m + field.min_gap_m;
    });
    if (overlaps) continue;
    if (keep_clear_m > 0.0) {
      const double reach_m = rock.radius_m + keep_clear_m;
      if (nearest_squared_m2(keep_clear_W, Eigen::Vector2d(rock.x_m, rock.y_m)) < reach_m * reach_m)
        continue;
    }
    rocks.push_back(rock);
  }
  check(static_cast<int>(rocks.size()) == count,
        "terrain: cannot place " + std::to_string(count) +
            " non-overlapping rocks in the rock_field box; enlarge it or lower the count");
  return rocks;
}

std::vector<Crater> place_random_craters(const CraterFieldOptions& field, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double box_area_m2 = (field.max_x_m - field.min_x_m) * 2.0 * field.max_abs_y_m;
  const int count = draw_count(rng, field.min_count, field.max_count, field.density_per_m2,
                               box_area_m2, "crater_field");
  std::vector<Crater> craters;
  const int max_attempts = std::max(10000, 100 * count);
  for (int attempt = 0; attempt < max_attempts && static_cast<int>(craters.size()) < count;
       ++attempt) {
    Crater crater;
    crater.radius_m = draw_radius_m(field.size_distribution, field.power_law_exponent,
                                    field.min_radius_m, field.max_radius_m, unit_double(rng()));
    crater.x_m = uniform(rng, field.min_x_m, field.max_x_m);
    crater.y_m = uniform(rng, -field.max_abs_y_m, field.max_abs_y_m);
    crater.depth_m = field.depth_ratio * 2.0 * crater.radius_m;
    crater.rim_height_m = field.rim_ratio * 2.0 * crater.radius_m;
    if (std::hypot(crater.x_m, crater.y_m) - crater.radius_m < field.clear_radius_m) continue;
    craters.push_back(crater);
  }
  check(static_cast<int>(craters.size()) == count,
        "terrain: cannot place " + std::to_string(count) +
            " craters outside crater_field.clear_radius_m; enlarge the box");
  return craters;
}

namespace {

// Independent random streams of make_terrain (each component takes its own key so that
// changing, say, the rock count does not reshuffle the ground).
struct TerrainSeeds {
  std::uint64_t ground = 0;
  std::uint64_t rocks = 0;
  std::uint64_t craters = 0;
};

TerrainSeeds terrain_seeds(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  TerrainSeeds seeds;
  seeds.ground = rng();
  seeds.rocks = rng();
  seeds.craters = rng();
  return seeds;
}

}  // namespace

std::vector<Crater> terrain_craters(const TerrainOptions& options) {
  std::vector<Crater> craters;
  if (options.scenario == "craters") {
    craters = place_random_craters(options.crater_field, terrain_seeds(options.seed).craters);
  }
  craters.insert(craters.end(), options.extra_craters.begin(), options.extra_craters.end());
  return craters;
}

Terrain make_terrain(const TerrainOptions& options) {
  validate(options);
  const TerrainSeeds seeds = terrain_seeds(options.seed);

  GroundPlane plane;
  SineWave wave;
  Heightfield detail;
  std::vector<Rock> rocks;
  if (options.scenario == "rocks" || options.scatter_rocks) {
    rocks = place_random_rocks(options.rock_field, seeds.rocks, options.keep_clear_W,
                               options.keep_clear_m);  // may throw: do it first
  }
  const std::vector<Crater> craters = terrain_craters(options);
  if (options.scenario == "ramp") {
    plane.slope_x = std::tan(options.ramp_deg * kPi / 180.0);
  } else if (options.scenario == "sine") {
    wave = options.sine;
  } else if (options.scenario == "rocks" || options.scenario == "craters") {
    detail = make_fractal_heightfield(options.center_W, options.size_x_m, options.size_y_m,
                                      options.resolution_m, options.noise, seeds.ground);
  }
  if (!craters.empty()) {
    if (detail.heights_m.empty()) {  // a flat detail grid to carry the craters
      FractalNoiseOptions none;
      none.octaves = 0;
      detail = make_fractal_heightfield(options.center_W, options.size_x_m, options.size_y_m,
                                        options.resolution_m, none, 0);
    }
    for (const Crater& crater : craters) add_crater(crater, detail);
  }
  rocks.insert(rocks.end(), options.extra_rocks.begin(), options.extra_rocks.end());
  return Terrain(plane, wave, std::move(detail), std::move(rocks));
}

}  // namespace hazmap::sim
