// Terrain: analytic answers (rock caps, ramp, sine, crater profile), the gradient bound
// ray marching relies on, seeded determinism, rock and crater placement (counts,
// densities, size distributions) and the ground-truth grid layout (SPEC 9).

#include "hazmap/sim/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kExactM = 1e-12;       // analytic formulas evaluated twice
constexpr double kRampToleranceM = 1e-6;

TerrainOptions rocks_options(std::uint64_t seed) {
  TerrainOptions options;
  options.scenario = "rocks";
  options.seed = seed;
  options.size_x_m = 4.0;  // small grid: fast tests
  options.size_y_m = 3.0;
  options.center_W = Eigen::Vector2d(1.0, 0.0);
  return options;
}

TEST(Terrain, RockTopIsGroundPlusRadiusMinusBuried) {
  const Terrain terrain = make_terrain(rocks_options(3));
  ASSERT_FALSE(terrain.rocks().empty());
  for (const Rock& rock : terrain.rocks()) {
    const double ground_m = terrain.ground_height_m(rock.x_m, rock.y_m);
    EXPECT_NEAR(terrain.height_m(rock.x_m, rock.y_m),
                ground_m + rock.radius_m - rock.buried_m, kExactM);
  }
}

TEST(Terrain, RockOnFlatGroundIsASphericalCap) {
  TerrainOptions options;
  options.scenario = "flat";
  options.extra_rocks = {{1.0, 0.5, 0.1, 0.04}};
  const Terrain terrain = make_terrain(options);
  EXPECT_NEAR(terrain.height_m(1.0, 0.5), 0.06, kExactM);
  // 3 cm off-centre: z = -0.04 + sqrt(0.1^2 - 0.03^2).
  EXPECT_NEAR(terrain.height_m(1.03, 0.5), -0.04 + std::sqrt(0.01 - 0.0009), kExactM);
  // Where the sphere is below the ground, the ground shows.
  EXPECT_EQ(terrain.height_m(1.095, 0.5), 0.0);
  EXPECT_EQ(terrain.height_m(1.2, 0.5), 0.0);
}

TEST(Terrain, RampIsXTanAngleEverywhere) {
  TerrainOptions options;
  options.scenario = "ramp";
  options.ramp_deg = 15.0;
  const Terrain terrain = make_terrain(options);
  const double slope = std::tan(15.0 * kPi / 180.0);
  for (double x_m : {-30.0, -2.0, 0.0, 0.37, 1.0, 4.2, 55.0}) {
    for (double y_m : {-7.0, 0.0, 0.3}) {
      EXPECT_NEAR(terrain.height_m(x_m, y_m), x_m * slope, kRampToleranceM) << x_m << " " << y_m;
    }
  }
  const Eigen::Vector3d n = terrain.ground_normal_W(0.5, 0.2);
  EXPECT_NEAR(n.x(), -std::sin(15.0 * kPi / 180.0), 1e-12);
  EXPECT_NEAR(n.z(), std::cos(15.0 * kPi / 180.0), 1e-12);
  EXPECT_NEAR(terrain.max_ground_gradient(), slope, 1e-6);
}

TEST(Terrain, FlatIsZero) {
  TerrainOptions options;
  options.scenario = "flat";
  const Terrain terrain = make_terrain(options);
  EXPECT_EQ(terrain.height_m(3.0, -1.0), 0.0);
  EXPECT_TRUE(terrain.rocks().empty());
}

// Ray marching is only safe if no two points differ in ground height by more than
// G times their horizontal distance, including outside the detail grid.
TEST(Terrain, GroundGradientBoundHolds) {
  const Terrain terrain = make_terrain(rocks_options(5));
  const double G = terrain.max_ground_gradient();
  EXPECT_GT(G, 0.0);
  EXPECT_LT(G, 0.5);  // gentle, traversable ground
  std::mt19937_64 rng(11);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit_double(rng()); };
  for (int i = 0; i < 20000; ++i) {
    const double x_m = uniform(-2.0, 4.0);  // beyond the grid's [-1, 3] too
    const double y_m = uniform(-2.0, 2.0);
    const double dx_m = uniform(-0.02, 0.02);
    const double dy_m = uniform(-0.02, 0.02);
    const double dh_m =
        terrain.ground_height_m(x_m + dx_m, y_m + dy_m) - terrain.ground_height_m(x_m, y_m);
    ASSERT_LE(std::abs(dh_m), G * std::hypot(dx_m, dy_m) + 1e-9);
  }
}

TEST(Terrain, NoiseGroundIsGentle) {
  const Terrain terrain = make_terrain(rocks_options(5));
  const FractalNoiseOptions noise;
  const double bound_m = noise.amplitude_m / (1.0 - noise.gain);
  for (double x_m = -1.0; x_m <= 3.0; x_m += 0.1) {
    for (double y_m = -1.5; y_m <= 1.5; y_m += 0.1) {
      ASSERT_LE(std::abs(terrain.ground_height_m(x_m, y_m)), bound_m);
    }
  }
}

TEST(Terrain, SameSeedSameTerrainOtherSeedOtherTerrain) {
  const Terrain a = make_terrain(rocks_options(7));
  const Terrain b = make_terrain(rocks_options(7));
  const Terrain c = make_terrain(rocks_options(8));
  EXPECT_EQ(a.detail().heights_m, b.detail().heights_m);
  ASSERT_EQ(a.rocks().size(), b.rocks().size());
  for (std::size_t i = 0; i < a.rocks().size(); ++i) {
    EXPECT_EQ(a.rocks()[i].x_m, b.rocks()[i].x_m);
    EXPECT_EQ(a.rocks()[i].radius_m, b.rocks()[i].radius_m);
  }
  EXPECT_NE(a.detail().heights_m, c.detail().heights_m);
}

TEST(Terrain, GridsOfDifferentExtentHoldTheSameWorld) {
  // A longer sequence grows the detail grid; where the grids overlap the ground (noise,
  // craters) and the rocks are the same, so a seed names one world. Node heights are
  // identical; between nodes the interpolation weights differ in the last bit.
  TerrainOptions small = rocks_options(4);
  small.scenario = "craters";
  small.scatter_rocks = true;
  TerrainOptions large = small;
  large.center_W = Eigen::Vector2d(2.337, -0.41);
  large.size_x_m = 7.3;
  large.size_y_m = 5.1;
  const Terrain a = make_terrain(small);
  const Terrain b = make_terrain(large);
  EXPECT_NE(a.detail().nodes_x, b.detail().nodes_x);
  std::mt19937_64 rng(2);
  for (int i = 0; i < 5000; ++i) {
    const double x_m = -0.9 + 3.8 * unit_double(rng());
    const double y_m = -1.4 + 2.8 * unit_double(rng());
    ASSERT_NEAR(a.height_m(x_m, y_m), b.height_m(x_m, y_m), 1e-15) << x_m << " " << y_m;
  }
  const Heightfield& ga = a.detail();
  const Heightfield& gb = b.detail();
  for (int iy = 10; iy < ga.nodes_y - 10; iy += 7) {
    for (int ix = 10; ix < ga.nodes_x - 10; ix += 7) {
      const long jx = std::lround((ga.origin_x_m - gb.origin_x_m) / gb.resolution_m) + ix;
      const long jy = std::lround((ga.origin_y_m - gb.origin_y_m) / gb.resolution_m) + iy;
      ASSERT_EQ(ga.heights_m[static_cast<std::size_t>(iy) * ga.nodes_x + ix],
                gb.heights_m[static_cast<std::size_t>(jy) * gb.nodes_x + jx]);
    }
  }
}

TEST(Terrain, RockFieldStaysInItsBoxWithoutOverlap) {
  const RockFieldOptions field;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    const std::vector<Rock> rocks = place_random_rocks(field, seed);
    ASSERT_GE(static_cast<int>(rocks.size()), field.min_count);
    ASSERT_LE(static_cast<int>(rocks.size()), field.max_count);
    for (std::size_t i = 0; i < rocks.size(); ++i) {
      const Rock& r = rocks[i];
      EXPECT_GE(r.radius_m, field.min_radius_m);
      EXPECT_LE(r.radius_m, field.max_radius_m);
      EXPECT_GE(r.x_m, field.min_x_m);
      EXPECT_LE(r.x_m, field.max_x_m);
      EXPECT_LE(std::abs(r.y_m), field.max_abs_y_m);
      EXPECT_GE(r.buried_m, 0.0);
      EXPECT_LT(r.buried_m, field.max_buried_fraction * r.radius_m);
      for (std::size_t j = 0; j < i; ++j) {
        EXPECT_GE(std::hypot(r.x_m - rocks[j].x_m, r.y_m - rocks[j].y_m),
                  r.radius_m + rocks[j].radius_m + field.min_gap_m);
      }
    }
  }
}

TEST(Terrain, GroundTruthGridsUseJdemLayout) {
  TerrainOptions options;
  options.scenario = "ramp";
  options.ramp_deg = 10.0;
  options.extra_rocks = {{0.205, -0.105, 0.05, 0.01}};  // centred on a cell centre
  const Terrain terrain = make_terrain(options);
  const double resolution_m = 0.01;
  const Eigen::Vector2d center_W(0.3, -0.2);
  const int rows = 40;
  const int cols = 60;
  const JdemGrid height = terrain.ground_truth_height(resolution_m, center_W, rows, cols);
  const JdemGrid hazard = terrain.ground_truth_hazard(resolution_m, center_W, rows, cols);
  ASSERT_EQ(height.values.size(), static_cast<std::size_t>(rows * cols));
  EXPECT_EQ(height.quantity, "height");
  EXPECT_EQ(hazard.quantity, "hazard");
  EXPECT_EQ(height.rows, rows);
  EXPECT_EQ(height.cols, cols);
  EXPECT_DOUBLE_EQ(height.center_x_m, 0.3);

  // Row 0 = largest y, column 0 = smallest x: cell (0, 0) is centred at
  // (0.3 - 0.295, -0.2 + 0.195).
  const double slope = std::tan(10.0 * kPi / 180.0);
  EXPECT_NEAR(height.at(0, 0), 0.005 * slope, 1e-6);
  EXPECT_NEAR(height.at(rows - 1, cols - 1), 0.595 * slope, 1e-6);
  EXPECT_EQ(hazard.at(0, 0), 0.0f);

  // The rock centre (0.205, -0.105) is the centre of column 20, row 10.
  EXPECT_NEAR(hazard.at(10, 20), 0.04, 1e-6);
  EXPECT_NEAR(height.at(10, 20), 0.205 * slope + 0.04, 1e-6);
  int hazard_cells = 0;
  for (float v : hazard.values) hazard_cells += v > 0.0f;
  // Footprint of the cap: radius sqrt(0.05^2 - 0.01^2) = 4.9 cm, ~75 cells of 1 cm^2.
  EXPECT_NEAR(hazard_cells, kPi * (0.0025 - 0.0001) / 1e-4, 8);
}

TEST(Terrain, InvalidOptionsThrow) {
  TerrainOptions options;
  options.scenario = "crater";
  EXPECT_THROW(make_terrain(options), Error);
  options = TerrainOptions();
  options.resolution_m = 0.0;
  EXPECT_THROW(make_terrain(options), Error);
  options = TerrainOptions();
  options.rock_field.min_count = 200;  // cannot fit
  options.rock_field.max_count = 200;
  EXPECT_THROW(make_terrain(options), Error);
  EXPECT_THROW(Terrain(GroundPlane(), Heightfield(), {{0.0, 0.0, 0.05, 0.05}}), Error);
}

// ---------------------------------------------------------------------------------------
// Sine

TEST(Terrain, SineIsAnalyticAndUnderTwentyDegrees) {
  TerrainOptions options;
  options.scenario = "sine";  // defaults: 5 cm amplitude, 1 m wavelength, along +x
  const Terrain terrain = make_terrain(options);
  const SineWave& wave = options.sine;
  for (double x_m : {-3.0, 0.0, 0.25, 0.6, 1.1, 7.3}) {
    for (double y_m : {-2.0, 0.0, 1.5}) {
      EXPECT_NEAR(terrain.ground_height_m(x_m, y_m), 0.05 * std::sin(2.0 * kPi * x_m), kExactM);
    }
  }
  // Steepest slope 2 pi A / lambda = 17.4 deg: below the 20 deg traversability limit.
  EXPECT_NEAR(std::atan(wave.max_slope()) * 180.0 / kPi, 17.44, 0.01);
  EXPECT_LT(std::atan(wave.max_slope()), 20.0 * kPi / 180.0);
  // Measured on the terrain: finite differences never exceed it, and reach it at x = 0.
  double steepest = 0.0;
  for (double x_m = -1.0; x_m <= 1.0; x_m += 0.001) {
    const double slope = (terrain.ground_height_m(x_m + 1e-6, 0.3) -
                          terrain.ground_height_m(x_m - 1e-6, 0.3)) / 2e-6;
    steepest = std::max(steepest, std::abs(slope));
  }
  EXPECT_NEAR(steepest, wave.max_slope(), 1e-6);
  EXPECT_LE(steepest, terrain.max_ground_gradient());
  // The normal follows the analytic gradient, along the wave direction only.
  const Eigen::Vector3d n = terrain.ground_normal_W(0.0, 0.0);
  EXPECT_TRUE(n.isApprox(Eigen::Vector3d(-wave.max_slope(), 0.0, 1.0).normalized(), 1e-12));

  // A wave along another direction varies only along it.
  options.sine.direction_rad = kPi / 2;
  const Terrain across = make_terrain(options);
  EXPECT_NEAR(across.ground_height_m(3.0, 0.25), 0.05, kExactM);
  EXPECT_NEAR(across.ground_height_m(-1.0, 0.25), 0.05, kExactM);
}

// ---------------------------------------------------------------------------------------
// Craters

TEST(Terrain, CraterProfileMatchesItsFormula) {
  const Crater c{1.0, -0.5, 0.4, 0.08, 0.016};
  const double R = c.radius_m;
  EXPECT_NEAR(crater_relief_m(c, 1.0, -0.5), -0.08, kExactM);      // floor
  EXPECT_NEAR(crater_relief_m(c, 1.0 + R, -0.5), 0.016, kExactM);  // rim crest
  EXPECT_NEAR(crater_relief_m(c, 1.0, -0.5 + 0.5 * R), -0.08 + 0.096 * 0.25, kExactM);
  EXPECT_NEAR(crater_relief_m(c, 1.0 + 2.0 * R, -0.5), 0.016 * (0.125 - 1.0 / 27) / (26.0 / 27),
              kExactM);
  EXPECT_EQ(crater_relief_m(c, 1.0 + 3.0 * R, -0.5), 0.0);
  EXPECT_EQ(crater_relief_m(c, 5.0, 5.0), 0.0);
  // Continuous at the crest and at the edge of the ejecta.
  for (double r : {R, 3.0 * R}) {
    EXPECT_NEAR(crater_relief_m(c, 1.0 + r - 1e-9, -0.5), crater_relief_m(c, 1.0 + r + 1e-9, -0.5),
                1e-9);
  }
  // Inner wall slope at the crest: 2 (h + D) / R.
  const double inner = (crater_relief_m(c, 1.0 + R, -0.5) - crater_relief_m(c, 1.0 + R - 1e-7, -0.5)) / 1e-7;
  EXPECT_NEAR(inner, 2.0 * (0.016 + 0.08) / R, 1e-5);
}

TEST(Terrain, CraterIsBakedIntoTheGroundExactlyAtTheNodes) {
  TerrainOptions options;
  options.scenario = "flat";
  options.center_W = Eigen::Vector2d(1.0, 0.0);
  options.size_x_m = 3.0;
  options.size_y_m = 3.0;
  const Crater crater{1.003, 0.2, 0.5, 0.1, 0.02};
  options.extra_craters = {crater};
  const Terrain terrain = make_terrain(options);
  const Heightfield& grid = terrain.detail();
  ASSERT_FALSE(grid.heights_m.empty());
  double worst_node_m = 0.0;
  double worst_between_m = 0.0;
  for (double x_m = 0.0; x_m <= 2.0; x_m += 0.01) {
    for (double y_m = -0.8; y_m <= 1.2; y_m += 0.01) {
      const double nx = grid.origin_x_m + std::round((x_m - grid.origin_x_m) / grid.resolution_m) *
                                              grid.resolution_m;
      const double ny = grid.origin_y_m + std::round((y_m - grid.origin_y_m) / grid.resolution_m) *
                                              grid.resolution_m;
      worst_node_m = std::max(worst_node_m, std::abs(terrain.ground_height_m(nx, ny) -
                                                     crater_relief_m(crater, nx, ny)));
      worst_between_m =
          std::max(worst_between_m, std::abs(terrain.ground_height_m(nx + 0.005, ny + 0.003) -
                                             crater_relief_m(crater, nx + 0.005, ny + 0.003)));
    }
  }
  EXPECT_LT(worst_node_m, 1e-7);  // float32 storage of heights below 0.1 m
  // Between nodes the bilinear surface departs from the profile by at most curvature x
  // spacing^2 / 8 in the bowl (0.48 / m: 6e-6 m), but by up to the slope jump x
  // spacing / 4 across the sharp crest (0.48 + 0.12: 1.5 mm).
  EXPECT_LT(worst_between_m, 1.6e-3);
  EXPECT_GT(terrain.max_ground_gradient(), 0.45);  // the inner wall at the crest
}

TEST(Terrain, CraterFieldRespectsBoxCountAndClearing) {
  CraterFieldOptions field;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const std::vector<Crater> craters = place_random_craters(field, seed);
    ASSERT_GE(static_cast<int>(craters.size()), field.min_count);
    ASSERT_LE(static_cast<int>(craters.size()), field.max_count);
    for (const Crater& c : craters) {
      EXPECT_GE(c.radius_m, field.min_radius_m);
      EXPECT_LE(c.radius_m, field.max_radius_m);
      EXPECT_GE(c.x_m, field.min_x_m);
      EXPECT_LE(c.x_m, field.max_x_m);
      EXPECT_LE(std::abs(c.y_m), field.max_abs_y_m);
      EXPECT_GE(std::hypot(c.x_m, c.y_m) - c.radius_m, field.clear_radius_m);
      EXPECT_NEAR(c.depth_m, 0.1 * 2.0 * c.radius_m, kExactM);
      EXPECT_NEAR(c.rim_height_m, 0.02 * 2.0 * c.radius_m, kExactM);
    }
  }
  field.density_per_m2 = 0.5;  // 5.5 m x 5 m box
  EXPECT_EQ(place_random_craters(field, 1).size(), 14u);

  TerrainOptions options;
  options.scenario = "craters";
  options.size_x_m = 10.0;
  const Terrain terrain = make_terrain(options);
  const std::vector<Crater> craters = terrain_craters(options);
  ASSERT_FALSE(craters.empty());
  // The ground at each crater's centre is its floor (plus fractal noise of at most
  // 0.015 / (1 - 0.5) m), unless another crater's relief reaches it.
  int checked = 0;
  for (const Crater& c : craters) {
    const bool alone = std::none_of(craters.begin(), craters.end(), [&](const Crater& o) {
      return &o != &c && std::hypot(o.x_m - c.x_m, o.y_m - c.y_m) < 3.0 * o.radius_m;
    });
    if (!alone) continue;
    EXPECT_NEAR(terrain.ground_height_m(c.x_m, c.y_m), -c.depth_m, 0.03 + 1e-6);
    ++checked;
  }
  EXPECT_GE(checked, 1);
}

// ---------------------------------------------------------------------------------------
// Size distributions and densities

TEST(Terrain, PowerLawRadiiFollowTheTruncatedParetoLaw) {
  const double lo = 0.02, hi = 0.2, q = 2.5;
  EXPECT_NEAR(draw_radius_m(SizeDistribution::power_law, q, lo, hi, 0.0), lo, kExactM);
  EXPECT_NEAR(draw_radius_m(SizeDistribution::power_law, q, lo, hi, 1.0 - 1e-16), hi, 1e-12);
  // Inverse CDF: P(R > r) = ((lo/r)^q - (lo/hi)^q) / (1 - (lo/hi)^q).
  for (double u : {0.1, 0.5, 0.9, 0.99}) {
    const double r = draw_radius_m(SizeDistribution::power_law, q, lo, hi, u);
    const double tail = std::pow(lo / hi, q);
    EXPECT_NEAR((std::pow(lo / r, q) - tail) / (1.0 - tail), 1.0 - u, 1e-12);
  }
  EXPECT_NEAR(draw_radius_m(SizeDistribution::uniform, q, lo, hi, 0.5), 0.11, kExactM);
  EXPECT_EQ(parse_size_distribution("power_law", "test"), SizeDistribution::power_law);
  EXPECT_THROW(parse_size_distribution("lognormal", "test"), Error);
}

TEST(Terrain, RockDensityAndFixedRadius) {
  RockFieldOptions field;
  field.density_per_m2 = 8.0;  // box 0.65 m x 0.7 m = 0.455 m^2 -> 4 rocks
  field.min_radius_m = field.max_radius_m = 0.04;
  field.max_buried_fraction = 0.0;
  const std::vector<Rock> rocks = place_random_rocks(field, 9);
  ASSERT_EQ(rocks.size(), 4u);
  for (const Rock& r : rocks) {
    EXPECT_EQ(r.radius_m, 0.04);
    EXPECT_EQ(r.buried_m, 0.0);
  }
  // A power-law field: many small rocks, few large ones, all within range.
  field.density_per_m2 = 0.0;
  field.min_count = field.max_count = 40;
  field.min_x_m = 0.0;
  field.max_x_m = 4.0;
  field.max_abs_y_m = 2.0;
  field.min_radius_m = 0.02;
  field.max_radius_m = 0.2;
  field.size_distribution = SizeDistribution::power_law;
  const std::vector<Rock> many = place_random_rocks(field, 4);
  ASSERT_EQ(many.size(), 40u);
  int small = 0;
  for (const Rock& r : many) small += r.radius_m < 0.04;
  EXPECT_GT(small, 20);  // P(r < 2 lo) = 1 - 2^-2.5 = 82 %
}

TEST(Terrain, RocksKeepClearOfAPath) {
  RockFieldOptions field;
  field.min_count = field.max_count = 12;
  field.min_x_m = 0.0;
  field.max_x_m = 3.0;
  field.max_abs_y_m = 1.0;
  std::vector<Eigen::Vector2d> path;
  for (int k = 0; k <= 75; ++k) path.emplace_back(0.04 * k, 0.0);
  const std::vector<Rock> rocks = place_random_rocks(field, 2, path, 0.2);
  ASSERT_EQ(rocks.size(), 12u);
  for (const Rock& r : rocks) {
    double nearest_m = 1e9;
    for (const Eigen::Vector2d& p : path) nearest_m = std::min(nearest_m, std::hypot(p.x() - r.x_m, p.y() - r.y_m));
    EXPECT_GE(nearest_m, r.radius_m + 0.2);
  }
}

}  // namespace
}  // namespace hazmap::sim
