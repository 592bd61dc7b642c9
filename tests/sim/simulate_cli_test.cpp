// `hazmap simulate` on the command line: the new flags reach the simulator, and bad
// values stop with one line naming the flag or option (exit 2 for usage, 1 for values).

#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;

using hazmap::testing::CommandResult;

/// Runs `hazmap simulate ARGS`; captures stdout and stderr.
CommandResult simulate(const std::string& args) {
  return hazmap::testing::run_command(std::string(HAZMAP_CLI) + " simulate " + args + " 2>&1");
}

TEST(SimulateCli, EveryFeatureFromTheCommandLine) {
  testing::TempDir dir;
  const CommandResult r = simulate(
      "--scenario craters --frames 3 --scale 0.05 --path spline --max-turn-deg 20 "
      "--drift 0.05 --drift-direction-deg 90 --distort --misalign --depth --ground-truth "
      "--gt-margin 0.2 --scatter-rocks --rock-count 6 --rock-radius 0.05 --rock-box 1,3,1 "
      "--crater-count 2 --crater-radius 0.3:0.5 --terrain-size 6 --quiet --out " +
      (dir / "seq").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"left/000002.png", "right/000002.png", "depth/000002.tiff",
                           "poses.txt", "poses_true.txt", "gt_height.jdem", "gt_hazard.jdem"}) {
    EXPECT_TRUE(fs::is_regular_file(dir / "seq" / name)) << name;
  }
  const YAML::Node sim = YAML::LoadFile((dir / "seq/simulation.yaml").string());
  EXPECT_EQ(sim["scenario"].as<std::string>(), "craters");
  EXPECT_EQ(sim["path"]["kind"].as<std::string>(), "spline");
  EXPECT_EQ(sim["path"]["max_turn_deg"].as<double>(), 20.0);
  EXPECT_EQ(sim["drift"]["direction_deg"].as<double>(), 90.0);
  EXPECT_EQ(sim["craters"].size(), 2u);
  ASSERT_EQ(sim["rocks"].size(), 6u);
  EXPECT_EQ(sim["rocks"][0]["radius"].as<double>(), 0.05);
  EXPECT_EQ(sim["rig_errors"]["distortion"][0].as<double>(), -0.08);
  const YAML::Node calib = YAML::LoadFile((dir / "seq/calibration.yaml").string());
  EXPECT_FALSE(calib["rectified"].as<bool>());
}

TEST(SimulateCli, BadValuesAreNamed) {
  testing::TempDir dir;
  const std::string out = " --out " + (dir / "seq").string();
  CommandResult r = simulate("--distortion 1,2" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--distortion"), std::string::npos) << r.output;
  r = simulate("--rock-count 3:x" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rock-count"), std::string::npos) << r.output;
  r = simulate("--scenario moon" + out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("moon"), std::string::npos) << r.output;
  r = simulate("--rock-sizes lognormal" + out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--rock-sizes"), std::string::npos) << r.output;
  r = simulate("--path zigzag" + out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("zigzag"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

// Issue 24: --frames, --seed and --samples were cast to int / uint64 unchecked (undefined
// for 1e300 or -1); each is now a whole number in its range, named on one line, exit 2.
TEST(SimulateCli, IntegerFlagsAreRangeCheckedBeforeTheCast) {
  testing::TempDir dir;
  const std::string out = " --out " + (dir / "seq").string();
  const struct {
    const char* args;
    const char* message;
  } cases[] = {
      {"--frames 1e300", "--frames: '1e300' is not a whole number in [1, 100000]"},
      {"--frames -5", "--frames: '-5' is not a whole number in [1, 100000]"},
      {"--frames 2.5", "--frames: '2.5' is not a whole number in [1, 100000]"},
      {"--frames nan", "--frames: 'nan' is not a whole number in [1, 100000]"},
      {"--seed -1", "--seed: '-1' is not a whole number in [0, 9007199254740992]"},
      {"--seed 1e300", "--seed: '1e300' is not a whole number in [0, 9007199254740992]"},
      {"--samples 1e10", "--samples: '1e10' is not a whole number in [1, 8]"},
  };
  for (const auto& c : cases) {
    const CommandResult r = simulate(std::string(c.args) + out);
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.output;
    EXPECT_EQ(r.output, std::string("hazmap: error: ") + c.message + " (see hazmap simulate --help)\n");
  }
  const CommandResult r = simulate("--terrain-size 1e300 --quiet" + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output,
            "hazmap: error: simulate: terrain_size_m (--terrain-size) must be in (0, 1000] m\n");
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

}  // namespace
}  // namespace hazmap
