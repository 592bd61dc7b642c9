// Terrain: analytic answers (rock caps, ramp), the gradient bound ray marching relies on,
// seeded determinism, rock-field placement and the ground-truth grid layout (SPEC 9).

#include "hazmap/sim/terrain.hpp"

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

}  // namespace
}  // namespace hazmap::sim
