// hazmap ground-truth: a cloud sampled densely from a simulated rocks terrain, run
// through the real binary, must give back the ground truth `hazmap simulate` computes
// from the terrain's functions on the same grid (independent: the simulator knows which
// part of the surface is rock). Plus the cloud readers and the bad-input contract.

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "hazmap/eval/cloud_ground_truth.hpp"
#include "hazmap/eval/ground_truth.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/point_cloud_file.hpp"
#include "hazmap/sim/simulate.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

using testing::run_command;
using testing::TempDir;

std::string cli() { return HAZMAP_CLI; }

/// Obstacle heights from the cloud are at most this far from the simulator's (measured
/// 1.7 mm with the default 3 mm ground tolerance: rim cells within the tolerance count as
/// ground and lift the interpolated ground under the rock a little).
constexpr double kObstacleTolerance = 0.002;

/// True when cell (row, col) lies within one cell of a change between ground
/// (obstacle 0) and rock (> 0) in the simulator's grid: the rock's rim, where the surface
/// has a near-vertical step inside a cell.
bool at_rock_border(const JdemGrid& sim_hazard, int row, int col) {
  bool rock = false, ground = false;
  for (int r = std::max(0, row - 1); r <= std::min(sim_hazard.rows - 1, row + 1); ++r)
    for (int c = std::max(0, col - 1); c <= std::min(sim_hazard.cols - 1, col + 1); ++c)
      (sim_hazard.at(r, c) > 0.0f ? rock : ground) = true;
  return rock && ground;
}

TEST(CloudGroundTruth, ReproducesTheSimulatorsGroundTruthFromADenseCloud) {
  sim::SimulationOptions options;
  options.scenario = "rocks";
  options.seed = 11;
  const sim::Terrain terrain = sim::make_simulation_terrain(options);
  ASSERT_GE(terrain.rocks().size(), 3u);

  // Jittered samples, 4 x 4 per 1 cm cell, over x in [0, 1.16), y in [-0.6, 0.6): every
  // rock (centres x 0.25-0.9, |y| <= 0.35, radius <= 8 cm) lies at least the ground radius
  // (15 cm) inside. A 2.4 cm wide hole (filled) and a 10 cm square gap (not filled) are cut out.
  TempDir dir;
  const Eigen::Vector2d hole(0.055, 0.505), gap_lo(1.0, -0.55);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(0.0, 0.0025);
  {
    std::ofstream out(dir / "scan.xyz");
    out.precision(9);
    out << "# x y z [m], sampled from the rocks terrain\n";
    for (int i = 0; i < 464; ++i)
      for (int j = 0; j < 480; ++j) {
        const double x = i * 0.0025 + jitter(rng), y = -0.6 + j * 0.0025 + jitter(rng);
        if ((Eigen::Vector2d(x, y) - hole).norm() < 0.012) continue;
        if (x >= gap_lo.x() && x < gap_lo.x() + 0.1 && y >= gap_lo.y() && y < gap_lo.y() + 0.1)
          continue;
        out << x << ' ' << y << ' ' << terrain.height_m(x, y) << " 0.5\n";  // + intensity
      }
  }
  const auto result = run_command(cli() + " ground-truth --cloud " + (dir / "scan.xyz").string() +
                                  " --out " + (dir / "gt").string() + " 2>&1");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const JdemGrid height = read_jdem(dir / "gt" / "gt_height.jdem");
  const JdemGrid hazard = read_jdem(dir / "gt" / "gt_hazard.jdem");
  EXPECT_TRUE(std::filesystem::exists(dir / "gt" / "ground_truth.yaml"));
  // The aligned layout: 1 cm cells with borders on multiples of 1 cm, even size.
  EXPECT_EQ(height.cols, 116);
  EXPECT_EQ(height.rows, 120);
  EXPECT_NEAR(height.center_x_m, 0.58, 1e-12);
  EXPECT_NEAR(height.center_y_m, 0.0, 1e-12);

  const Eigen::Vector2d center(height.center_x_m, height.center_y_m);
  const JdemGrid sim_height = terrain.ground_truth_height(0.01, center, height.rows, height.cols);
  const JdemGrid sim_hazard = terrain.ground_truth_hazard(0.01, center, height.rows, height.cols);

  int compared = 0, border = 0, unknown_in_gap = 0, hole_filled = 0, rock_cells = 0;
  double worst_height = 0.0, worst_obstacle = 0.0;
  int class_differences = 0;
  const double thresholds[] = {0.0075, 0.01, 0.02, 0.03, 0.05};
  for (int r = 0; r < height.rows; ++r)
    for (int c = 0; c < height.cols; ++c) {
      const Eigen::Vector2d p = cell_center_W(height, r, c);
      const bool in_gap = p.x() > gap_lo.x() + 0.03 && p.x() < gap_lo.x() + 0.07 &&
                          p.y() > gap_lo.y() + 0.03 && p.y() < gap_lo.y() + 0.07;
      if (in_gap) {
        unknown_in_gap += std::isnan(height.at(r, c)) && std::isnan(hazard.at(r, c));
        continue;
      }
      if (p.x() >= gap_lo.x() && p.x() < gap_lo.x() + 0.1 && p.y() >= gap_lo.y() &&
          p.y() < gap_lo.y() + 0.1)
        continue;  // the gap's border cells: partly sampled
      if ((p - hole).norm() < 0.006) hole_filled += std::isfinite(height.at(r, c));
      rock_cells += sim_hazard.at(r, c) > 0.0f;
      if (at_rock_border(sim_hazard, r, c)) {
        ++border;
        continue;
      }
      ASSERT_TRUE(std::isfinite(height.at(r, c))) << r << "," << c;
      ++compared;
      worst_height = std::max(worst_height, std::abs(height.at(r, c) - double(sim_height.at(r, c))));
      const double obstacle = hazard.at(r, c), sim_obstacle = sim_hazard.at(r, c);
      worst_obstacle = std::max(worst_obstacle, std::abs(obstacle - sim_obstacle));
      for (double h : thresholds) {
        // Classes may differ only where the true height lies within the tolerance of h.
        if (std::abs(sim_obstacle - h) > kObstacleTolerance)
          class_differences += (obstacle >= h) != (sim_obstacle >= h);
      }
      // Ground is exactly ground (evaluate counts obstacle 0 as free).
      if (sim_obstacle == 0.0) {
        EXPECT_EQ(obstacle, 0.0) << r << "," << c;
      }
    }
  std::printf("compared %d cells (%d rock), %d at rock borders skipped; worst height %.2f mm, "
              "worst obstacle height %.2f mm\n",
              compared, rock_cells, border, worst_height * 1e3, worst_obstacle * 1e3);
  EXPECT_GT(compared, 13000);
  EXPECT_GT(rock_cells, 300);
  EXPECT_LT(worst_height, 1e-3);
  EXPECT_LT(worst_obstacle, kObstacleTolerance);
  EXPECT_EQ(class_differences, 0);
  EXPECT_EQ(unknown_in_gap, 16);  // the 4 x 4 cells deep inside the 10 cm gap
  EXPECT_GE(hole_filled, 1);
}

/// Column `name` of a CSV header line, -1 if absent.
int column(const std::string& header, const std::string& name) {
  std::istringstream in(header);
  int i = 0;
  for (std::string field; std::getline(in, field, ','); ++i)
    if (field == name) return i;
  return -1;
}

std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& path) {
  std::istringstream in(testing::read_text(path));
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    rows.emplace_back();
    for (std::string f; std::getline(fields, f, ',');) rows.back().push_back(f);
  }
  return rows;
}

TEST(CloudGroundTruth, EvaluateScoresARunAgainstTheScanAsAgainstTheSimulator) {
  TempDir dir;
  sim::SimulationOptions options;
  options.scenario = "rocks";
  options.seed = 11;
  options.frames = 3;
  options.write_ground_truth = true;
  options.ground_truth_margin_m = 1.0;
  sim::simulate_sequence(options, dir / "sim");
  const sim::Terrain terrain = sim::make_simulation_terrain(options);
  const JdemGrid sim_height = read_jdem(dir / "sim" / "gt_height.jdem");

  // The scan: 3 x 3 jittered points per cell over the simulator's ground-truth area, as
  // binary PLY, into a copy of the sequence without the simulator's ground truth.
  const auto& g = sim_height;
  const double x0 = g.center_x_m - 0.5 * g.cols * g.resolution_m;
  const double y0 = g.center_y_m - 0.5 * g.rows * g.resolution_m;
  const int nx = 3 * g.cols, ny = 3 * g.rows;
  const double step = g.resolution_m / 3.0;
  {
    std::ofstream ply(dir / "scan.ply", std::ios::binary);
    ply << "ply\nformat binary_little_endian 1.0\nelement vertex "
        << static_cast<long long>(nx) * ny
        << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> jitter(0.05 * step, 0.95 * step);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) {
        const double x = x0 + i * step + jitter(rng), y = y0 + j * step + jitter(rng);
        const float p[3] = {static_cast<float>(x), static_cast<float>(y),
                            static_cast<float>(terrain.height_m(x, y))};
        ply.write(reinterpret_cast<const char*>(p), sizeof p);
      }
  }
  std::filesystem::create_directories(dir / "scanned");
  for (const char* f : {"poses.txt", "calibration.yaml"})
    std::filesystem::copy_file(dir / "sim" / f, dir / "scanned" / f);
  const std::string bin = cli();
  auto ok = [](const testing::CommandResult& r) {
    EXPECT_EQ(r.exit_code, 0) << r.output;
  };
  ok(run_command(bin + " ground-truth --cloud " + (dir / "scan.ply").string() + " --out " +
                 (dir / "scanned").string() + " 2>&1"));
  ok(run_command(bin + " run --config " + (testing::source_dir() / "config" / "default.yaml").string() +
                 " --sequence " + (dir / "sim").string() + " --out " + (dir / "run").string() +
                 " --quiet 2>&1"));
  for (const char* seq : {"sim", "scanned"})
    ok(run_command(bin + " evaluate --run " + (dir / "run").string() + " --sequence " +
                   (dir / seq).string() + " --out " + (dir / (std::string("eval_") + seq)).string() +
                   " 2>&1"));
  const auto a = read_csv(dir / "eval_sim" / "summary.csv");
  const auto b = read_csv(dir / "eval_scanned" / "summary.csv");
  ASSERT_GE(a.size(), 2u);
  ASSERT_EQ(a.size(), b.size());
  const std::string header = testing::read_text(dir / "eval_sim" / "summary.csv").substr(
      0, testing::read_text(dir / "eval_sim" / "summary.csv").find('\n'));
  const int rms = column(header, "height_rms_m"), hazard = column(header, "gt_hazard_m2");
  ASSERT_GE(rms, 0);
  ASSERT_GE(hazard, 0);
  for (size_t row = 1; row < a.size(); ++row) {
    const double rms_a = std::stod(a[row][rms]), rms_b = std::stod(b[row][rms]);
    const double hz_a = std::stod(a[row][hazard]), hz_b = std::stod(b[row][hazard]);
    std::printf("row %zu: height RMS %.3f / %.3f mm, GT hazard area %.5f / %.5f m^2\n", row,
                rms_a * 1e3, rms_b * 1e3, hz_a, hz_b);
    // The two ground truths differ at the rocks' rims only (the cells the first test
    // skips), where the map's errors are largest: RMS within 0.3 mm (measured 0.19).
    if (std::isfinite(rms_a) || std::isfinite(rms_b)) {
      EXPECT_NEAR(rms_a, rms_b, 3e-4);
    }
    EXPECT_NEAR(hz_a, hz_b, 0.05 * hz_a + 1e-4);
  }
}

TEST(CloudGroundTruth, ReadsAsciiAndBinaryPly) {
  TempDir dir;
  // A tilted plane z = 0.1 + 0.2 x - 0.1 y sampled on a 2 mm lattice.
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 40; ++j) {
      const double x = 0.001 + 0.002 * i, y = 0.001 + 0.002 * j;
      pts.emplace_back(x, y, 0.1 + 0.2 * x - 0.1 * y);
    }
  {
    std::ofstream a(dir / "a.ply");
    a << "ply\nformat ascii 1.0\ncomment test\nelement vertex " << pts.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\n"
         "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
    a.precision(17);
    for (const auto& p : pts) a << p.x() << ' ' << p.y() << ' ' << p.z() << " 7\n";
    std::ofstream b(dir / "b.ply", std::ios::binary);
    b << "ply\nformat binary_little_endian 1.0\nelement vertex " << pts.size()
      << "\nproperty uchar grey\nproperty float x\nproperty float y\nproperty double z\nend_header\n";
    for (const auto& p : pts) {
      const unsigned char g = 9;
      const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y());
      b.write(reinterpret_cast<const char*>(&g), 1);
      b.write(reinterpret_cast<const char*>(&x), 4);
      b.write(reinterpret_cast<const char*>(&y), 4);
      b.write(reinterpret_cast<const char*>(&p.z()), 8);
    }
  }
  const auto a = read_point_cloud(dir / "a.ply");
  const auto b = read_point_cloud(dir / "b.ply");
  ASSERT_EQ(a.size(), pts.size());
  ASSERT_EQ(b.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_LT((a[i] - pts[i]).norm(), 1e-15);
    EXPECT_LT((b[i] - pts[i]).norm(), 1e-7);  // float x, y
  }
  // The plane is reproduced exactly at the cell centres; nothing stands on it.
  const CloudGroundTruth gt = cloud_ground_truth(a, CloudGroundTruthOptions());
  for (int r = 0; r < gt.height.rows; ++r)
    for (int c = 0; c < gt.height.cols; ++c) {
      const Eigen::Vector2d p = cell_center_W(gt.height, r, c);
      EXPECT_NEAR(gt.height.at(r, c), 0.1 + 0.2 * p.x() - 0.1 * p.y(), 1e-6);
      EXPECT_EQ(gt.hazard.at(r, c), 0.0f);
    }
}

TEST(CloudGroundTruth, BadInputIsOneLineNamingFileAndLine) {
  TempDir dir;
  {
    std::ofstream(dir / "bad.xyz") << "0 0 0\n1 1 1\n0.5 zero 0\n";
    std::ofstream(dir / "short.xyz") << "0 0 0\n\n1 1\n";
    std::ofstream(dir / "nan.xyz") << "# header\n0 0 0\n1 nan 0\n";
    std::ofstream(dir / "empty.xyz") << "# nothing here\n\n";
    std::ofstream(dir / "far.xyz") << "0 0 0\n1 1 0\n1e6 1e6 0\n";
    std::ofstream(dir / "trunc.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex 5\n"
                                        "property float x\nproperty float y\nproperty float z\n"
                                        "end_header\n0123456789";
  }
  const struct {
    const char* file;
    const char* expect;
  } cases[] = {{"missing.xyz", "missing.xyz: cannot open"},
               {"bad.xyz", "bad.xyz:3: field 2 is not a number: 'zero'"},
               {"short.xyz", "short.xyz:3: expected x y z"},
               {"nan.xyz", "nan.xyz:3: coordinates must be finite"},
               {"empty.xyz", "empty.xyz: no points"},
               {"far.xyz", "far.xyz: ground truth: the grid would have 1e+16 cells"},
               {"trunc.ply", "trunc.ply: ends after 0 of 5 vertices"}};
  for (const auto& c : cases) {
    const auto r = run_command(cli() + " ground-truth --cloud " + (dir / c.file).string() +
                               " --out " + (dir / "out").string() + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << c.file;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "gt_height.jdem"));
  const auto usage = run_command(cli() + " ground-truth --cloud x.xyz --out o --resolution 0 2>&1");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
}

}  // namespace
}  // namespace hazmap
