// `hazmap evaluate` on damaged runs (issue 37): a hazard grid holding a value that is no
// class, a corrupt second frame with --error-maps all, a layer whose height and hazard
// grids disagree in geometry. Each ends with exit 1, one line naming the file(s), and
// OUT exactly as it was.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>

#include "eval/oracle_run.hpp"
#include "hazmap/io/jdem.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::snapshot;

/// A two-frame oracle run RUN of a one-rock world, with its sequence SEQ, in `dir`.
void write_run(const fs::path& dir) {
  testing::TestWorld w;
  w.rocks = {{1.0, 0.3, 0.1}};
  const auto layers = std::vector<testing::OracleLayer>{
      testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
      testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)};
  testing::write_ground_truth(dir / "seq", w);
  testing::write_poses(dir / "seq" / "poses.txt", {"000000", "000001"}, {{0.0, 0.0}, {0.0, 0.0}});
  testing::write_oracle_run(dir / "run", testing::oracle_config(), {"000000", "000001"},
                            {layers, layers});
}

struct Outcome {
  int exit_code;
  std::string stderr_text;
};

/// Runs evaluate with --error-maps all into `out`, which must stay as it was.
Outcome evaluate_into(const fs::path& dir, const fs::path& out) {
  const auto before = snapshot(out);
  const bool existed = fs::exists(out);
  const testing::CommandResult r = testing::run_command(
      std::string(HAZMAP_CLI) + " evaluate --run " + (dir / "run").string() + " --sequence " +
      (dir / "seq").string() + " --out " + out.string() + " --error-maps all --quiet 2>&1 1>/dev/null");
  EXPECT_EQ(snapshot(out), before) << "OUT changed";
  EXPECT_EQ(fs::exists(out), existed) << "OUT created";
  // The oracle run records no poses fingerprint: evaluate warns about that first. The
  // error is the last line, and the only one.
  const std::string& text = r.output;
  const std::size_t last = text.rfind('\n', text.size() >= 2 ? text.size() - 2 : 0);
  const std::string error = last == std::string::npos ? text : text.substr(last + 1);
  EXPECT_EQ(text.find("hazmap: error:"), text.rfind("hazmap: error:")) << text;
  return {r.exit_code, error};
}

/// Replaces cell (row, col) of a JDEM file with `value`.
void set_cell(const fs::path& file, int row, int col, float value) {
  JdemGrid g = read_jdem(file);
  g.at(row, col) = value;
  write_jdem(file, g);
}

TEST(EvaluateBadInput, HazardValueThatIsNoClassIsNamedWithFileRowAndColumn) {
  testing::TempDir dir;
  write_run(dir.path());
  const fs::path hazard = dir / "run/frames/000001/L0_hazard.jdem";
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out/previous.txt") << "earlier evaluation\n";
  for (const auto& [value, text] :
       std::vector<std::pair<float, std::string>>{{-std::numeric_limits<float>::infinity(), "-inf"},
                                                  {3.0f, "3"},
                                                  {1.5f, "1.5"},
                                                  {-1.0f, "-1"},
                                                  {3e38f, "3.00000001e+38"}}) {
    SCOPED_TRACE(text);
    write_run(dir.path());
    set_cell(hazard, 2, 3, value);
    const Outcome o = evaluate_into(dir.path(), dir / "out");
    EXPECT_EQ(o.exit_code, 1);
    EXPECT_EQ(o.stderr_text, "hazmap: error: " + hazard.string() + ": row 2, column 3: value " +
                                 text + " is not a hazard class (0 unknown, 1 traversable, 2 "
                                        "hazard, or nodata)\n");
  }
  // The fused map is checked the same way.
  write_run(dir.path());
  const fs::path fused = dir / "run/frames/000000/fused_hazard.jdem";
  set_cell(fused, 0, 39, std::numeric_limits<float>::infinity());
  const Outcome o = evaluate_into(dir.path(), dir / "out");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, "hazmap: error: " + fused.string() + ": row 0, column 39: value inf "
                           "is not a hazard class (0 unknown, 1 traversable, 2 hazard, or nodata)\n");
}

TEST(EvaluateBadInput, NodataInAHazardGridReadsAsUnknown) {
  testing::TempDir dir;
  write_run(dir.path());
  set_cell(dir / "run/frames/000001/L0_hazard.jdem", 2, 3, std::nanf(""));
  const testing::CommandResult r = testing::run_command(
      std::string(HAZMAP_CLI) + " evaluate --run " + (dir / "run").string() + " --sequence " +
      (dir / "seq").string() + " --quiet 2>&1 1>/dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("error"), std::string::npos) << r.output;
}

TEST(EvaluateBadInput, CorruptSecondFrameLeavesOutUntouchedWithErrorMaps) {
  testing::TempDir dir;
  write_run(dir.path());
  const fs::path broken = dir / "run/frames/000001/L1_height.jdem";
  std::ofstream(broken, std::ios::trunc) << "JDEM 1\nrows: 20\n";
  const std::string message = "hazmap: error: " + broken.string() + ":2: missing 'data:' line\n";
  // OUT absent: not created.
  Outcome o = evaluate_into(dir.path(), dir / "fresh");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, message);
  // OUT holding an earlier evaluation: unchanged, no errors_000000.png added.
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out/metrics.csv") << "earlier\n";
  o = evaluate_into(dir.path(), dir / "out");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, message);
  EXPECT_FALSE(fs::exists(dir / "out/errors_000000.png"));
}

TEST(EvaluateBadInput, GeometryMismatchNamesBothFilesAndWhatDiffers) {
  testing::TempDir dir;
  write_run(dir.path());
  const fs::path frame = dir / "run/frames/000001";
  JdemGrid height = read_jdem(frame / "L0_height.jdem");
  height.center_x_m += 0.04;
  write_jdem(frame / "L0_height.jdem", height);
  Outcome o = evaluate_into(dir.path(), dir / "out");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, "hazmap: error: " + (frame / "L0_height.jdem").string() + " and " +
                               (frame / "L0_hazard.jdem").string() +
                               " differ in geometry: centre (1, 0) m against (0.96, 0) m\n");

  write_run(dir.path());
  JdemGrid variance = read_jdem(frame / "L1_variance.jdem");
  variance.reset(21, 20, 0.1, variance.center_x_m, variance.center_y_m, 0.0f);
  write_jdem(frame / "L1_variance.jdem", variance);
  o = evaluate_into(dir.path(), dir / "out");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, "hazmap: error: " + (frame / "L1_variance.jdem").string() + " and " +
                               (frame / "L1_hazard.jdem").string() +
                               " differ in geometry: size 21 x 20 cells against 20 x 20, "
                               "resolution 0.1 m against 0.08 m\n");
}

}  // namespace
}  // namespace hazmap
