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
// Issue 33: light, regolith and camera flags reach simulation.yaml; bad ones are named and
// nothing is written.
TEST(SimulateCli, LowSunAndCameraFlags) {
  testing::TempDir dir;
  const CommandResult r = simulate(
      "--scenario rocks --frames 1 --scale 0.05 --terrain-size 4 --rig polar --lunar-polar-light "
      "--sun-elevation-deg 5 --sun-azimuth-deg -150 --ambient 0.02 --albedo-contrast 0.03 "
      "--albedo-correlation 0.1 --opposition-width-deg 4 --gain 1,1.2 --exposure 0.8 "
      "--offset-dn 4,5 --electrons-per-dn 20 --vignetting 0.1 --bits 12 --row-offset-px 1.5 "
      "--noise-octaves 7 --noise-gain 0.6 --quiet --out " +
      (dir / "seq").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const YAML::Node sim = YAML::LoadFile((dir / "seq/simulation.yaml").string());
  EXPECT_EQ(sim["rig"].as<std::string>(), "polar");
  EXPECT_EQ(sim["sun"]["elevation_deg"].as<double>(), 5.0);
  EXPECT_EQ(sim["sun"]["azimuth_deg"].as<double>(), -150.0);
  EXPECT_TRUE(sim["lighting"]["terrain_shadows"].as<bool>());
  EXPECT_EQ(sim["lighting"]["ambient"].as<double>(), 0.02);
  EXPECT_EQ(sim["lighting"]["opposition_surge"].as<double>(), 0.3);
  EXPECT_EQ(sim["lighting"]["opposition_width_deg"].as<double>(), 4.0);
  EXPECT_EQ(sim["albedo"]["model"].as<std::string>(), "regolith");
  EXPECT_EQ(sim["albedo"]["contrast"].as<double>(), 0.03);
  EXPECT_EQ(sim["albedo"]["correlation_m"].as<double>(), 0.1);
  EXPECT_EQ(sim["cameras"]["row_offset_px"].as<double>(), 1.5);
  EXPECT_EQ(sim["cameras"]["left"]["gain"].as<double>(), 1.0);
  EXPECT_EQ(sim["cameras"]["right"]["gain"].as<double>(), 1.2);
  EXPECT_EQ(sim["cameras"]["right"]["offset_dn"].as<double>(), 5.0);
  EXPECT_EQ(sim["cameras"]["left"]["exposure"].as<double>(), 0.8);
  EXPECT_EQ(sim["cameras"]["left"]["electrons_per_dn"].as<double>(), 20.0);
  EXPECT_EQ(sim["cameras"]["left"]["vignetting"].as<double>(), 0.1);
  EXPECT_EQ(sim["cameras"]["left"]["bits"].as<int>(), 12);
  EXPECT_EQ(sim["ground_noise"]["octaves"].as<int>(), 7);
  const YAML::Node calib = YAML::LoadFile((dir / "seq/calibration.yaml").string());
  EXPECT_EQ(calib["image_width"].as<int>(), 102);  // 2048 x 0.05

  const std::string out = " --out " + (dir / "bad").string();
  const struct {
    const char* args;
    const char* named;
  } cases[] = {{"--rig mars", "mars"},
               {"--vignetting 1.5", "vignetting"},
               {"--gain 0", "gain"},
               {"--bits 10", "--bits"},
               {"--albedo chalk", "--albedo"},
               {"--gain 1,2,3", "--gain"},
               {"--row-offset-px 99", "row_offset_px"},
               {"--sun-elevation-deg 0", "sun_elevation_deg"}};
  for (const auto& c : cases) {
    const CommandResult bad = simulate(std::string(c.args) + " --quiet" + out);
    EXPECT_NE(bad.exit_code, 0) << c.args;
    EXPECT_NE(bad.output.find(c.named), std::string::npos) << c.args << ": " << bad.output;
    EXPECT_FALSE(fs::exists(dir / "bad")) << c.args;
  }
}

}  // namespace hazmap
