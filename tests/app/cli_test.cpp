// Runs the real `hazmap` executable and checks exit codes, the one-line errors and the
// files it writes.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "hazmap/io/jdem.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

using testing::CommandResult;

/// Runs the CLI with `args`; captures stderr (stdout is discarded) into `output`.
const auto run_cli = testing::run_hazmap;

std::string tiny_run_args(const testing::TempDir& dir) {
  return "run --config " + (testing::source_dir() / "config/default.yaml").string() +
         " --sequence " + (dir / "seq").string() + " --out " + (dir / "out").string() +
         " --set stereo.num_disparities=16 --set stereo.block_size=5 --set "
         "map.layers.0.size=16 --set map.layers.0.hazard.kernel=3 --set stereo.z_max=10";
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(Cli, VersionAndHelpExitZero) {
  EXPECT_EQ(run_cli("--version").exit_code, 0);
  EXPECT_EQ(run_cli("--help").exit_code, 0);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run_cli("").exit_code, 2);
  EXPECT_EQ(run_cli("fly").exit_code, 2);
  EXPECT_EQ(run_cli("run --config x.yaml").exit_code, 2);  // missing --sequence/--out
  EXPECT_EQ(run_cli("run --bogus 1").exit_code, 2);
}

TEST(Cli, EmptyOutAndAFolderAsConfigStopWithOneLineAndWriteNothing) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 1);
  const std::string config = (testing::source_dir() / "config/default.yaml").string();
  const std::string seq = (dir / "seq").string();
  const CommandResult empty_out = run_cli("run --config " + config + " --sequence " + seq + " --out ''");
  EXPECT_EQ(empty_out.exit_code, 2) << empty_out.output;
  EXPECT_NE(empty_out.output.find("--out: empty value"), std::string::npos) << empty_out.output;
  EXPECT_EQ(count_lines(empty_out.output), 1) << empty_out.output;
  const CommandResult folder = run_cli("run --config " + dir.path().string() + " --sequence " + seq +
                                       " --out " + (dir / "out").string());
  EXPECT_NE(folder.exit_code, 0);
  EXPECT_NE(folder.output.find(dir.path().string() + ": is a folder, not a configuration file"),
            std::string::npos)
      << folder.output;
  EXPECT_EQ(count_lines(folder.output), 1) << folder.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(Cli, RunWritesEveryOutputOfEveryFrame) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  // The camera on a 0.6 m boom ahead of the body: the ground it sees starts 0.2 m ahead.
  std::string calibration = testing::read_text(dir / "seq/calibration.yaml");
  const std::string mount = "translation: [0, 0.025, 0.625]";
  ASSERT_NE(calibration.find(mount), std::string::npos);
  calibration.replace(calibration.find(mount), mount.size(), "translation: [0.6, 0.025, 0.625]");
  std::ofstream(dir / "seq/calibration.yaml") << calibration;
  const CommandResult r = run_cli(tiny_run_args(dir) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // --quiet: no progress, only the warning this tiny 16 cm layer earns (the cameras see
  // no ground within 8 cm of the body); a layer that gets points has none (EuRoC test).
  EXPECT_EQ(r.output.find("frame 1/3"), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("layer 0 (0.01 m cells, a 0.16 m window around the body) received no "
                           "point in 3 frames: every cell is unknown",
                           0),
            0u)
      << r.output;
  for (const char* frame : {"000000", "000001", "000002"}) {
    const auto f = dir / "out/frames" / frame;
    for (const char* file : {"L0_hazard.png", "L0_height.png", "L0_height.jdem", "L0_variance.jdem",
                             "L0_hazard.jdem", "fused_hazard.png", "fused_hazard.jdem"})
      EXPECT_TRUE(std::filesystem::is_regular_file(f / file)) << f / file;
    const JdemGrid h = read_jdem(f / "L0_height.jdem");
    EXPECT_EQ(h.rows, 16);
    EXPECT_EQ(h.meta("frame"), frame);
  }
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "out/summary.json"));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "out/run.log"));
}

TEST(Cli, ProgressShowsFrameCountPointsAndTime) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 2);
  const CommandResult r = run_cli(tiny_run_args(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("frame 1/2 000000: "), std::string::npos) << r.output;
  // Rate and time left after each frame, the total after the last.
  EXPECT_NE(r.output.find(" frames/s, "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" left\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" in all\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frame 2/2 000001: "), std::string::npos);
  EXPECT_NE(r.output.find(" points, "), std::string::npos);
  EXPECT_NE(r.output.find(" ms ("), std::string::npos);
}

TEST(Cli, MissingRightImageStopsWithOneLineNamingTheFile) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  std::filesystem::remove(dir / "seq/right/000002.png");
  const CommandResult r = run_cli(tiny_run_args(dir));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find((dir / "seq/right/000002.png").string()), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out/frames"));
}

TEST(Cli, PosesLackingAFrameStopWithOneLineNamingTheFile) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  std::ofstream(dir / "seq/poses.txt") << "000000 0 0 0 0 0 0 0 1\n000002 2 0 0 0 0 0 0 1\n";
  const CommandResult r = run_cli(tiny_run_args(dir));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find((dir / "seq/poses.txt").string() + ": no pose for frame '000001'"),
            std::string::npos)
      << r.output;
}

TEST(Cli, FailedRunLeavesEarlierOutputsIntact) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 1);
  ASSERT_EQ(run_cli(tiny_run_args(dir) + " --quiet").exit_code, 0);
  const auto jdem = dir / "out/frames/000000/L0_height.jdem";
  const std::string before = testing::read_text(jdem);
  std::filesystem::remove(dir / "seq/calibration.yaml");
  // --overwrite: the earlier output goes only once every input has passed its check.
  const CommandResult r = run_cli(tiny_run_args(dir) + " --overwrite");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("calibration.yaml: cannot open calibration file"), std::string::npos);
  EXPECT_EQ(before, testing::read_text(jdem));
  EXPECT_NE(testing::read_text(dir / "out/run.log").find("done: 1 frames"),
            std::string::npos);  // first run's log kept
}

TEST(Cli, BadConfigKeyIsNamed) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 1);
  const CommandResult r = run_cli(tiny_run_args(dir) + " --set stereo.colour=1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1);
  EXPECT_NE(r.output.find("unknown key 'stereo.colour'"), std::string::npos) << r.output;
}

// Issue 24, class "crash" and "wrong map with exit 0": each of these inputs stops the run
// with one line naming the file and line or the key, exit 1, and no frame written.
TEST(Cli, OverflowingPosesResolutionsAndStridesStopWithOneLine) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 2);
  const auto poses = dir / "seq/poses.txt";
  std::ofstream(poses) << "000000 0 0 0 0 0 0 0 1\n000001 1 1e300 0 0 0 0 0 1\n";
  CommandResult r = run_cli(tiny_run_args(dir));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(poses.string() + ":2: frame '000001': position x = 1e+300 m is "
                                           "implausible"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out/frames"));

  // A plausible position that is still beyond 2^30 cells of a 1 mm layer: refused by the
  // map, not turned into an index.
  std::ofstream(poses) << "000000 0 9e6 0 0 0 0 0 1\n000001 1 9e6 0 0 0 0 0 1\n";
  r = run_cli(tiny_run_args(dir) + " --quiet --set map.layers.0.resolution=0.001");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find((dir / "seq/left/000000.png").string() +
                          ": map: robot position x = 9e+06 m is 9e+09 cells of a 0.001 m layer"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out/frames/000000/L0_height.jdem"));

  testing::write_tiny_sequence(dir / "seq", 2);
  // The run above got as far as OUT/run.log: the next ones replace it.
  r = run_cli(tiny_run_args(dir) + " --overwrite --set map.layers.0.resolution=1e-300");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("key 'map.layers.0.resolution': must be in [1e-4, 1000] m"),
            std::string::npos)
      << r.output;
  r = run_cli(tiny_run_args(dir) + " --overwrite --set stereo.stride=2147483647");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("key 'stereo.stride': must be in [1, 4096]"), std::string::npos)
      << r.output;
}

// Issue 24, class "memory errors": parse_board read strtol's end pointers after the
// substrings they pointed into were destroyed (ASan: stack-use-after-scope). The board is
// parsed before the images are looked at, so a missing images folder shows how far it got.
TEST(Cli, CalibrateBoardIsParsedFromLiveStrings) {
  testing::TempDir dir;
  const std::string rest = " --square 0.025 --out " + (dir / "c.yaml").string() +
                           " --images " + (dir / "none").string();
  for (const char* board : {"9x6", "00000000000000000000009x00000000000000000000006", "100x2"}) {
    const CommandResult r = run_cli(std::string("calibrate --board ") + board + rest);
    EXPECT_EQ(r.exit_code, 1) << board << ": " << r.output;  // past the board, at the images
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output.find("--board"), std::string::npos) << r.output;
  }
  for (const char* board : {"9x6junk", "9junkx6", "x6", "9x", "9", "1x6", "9x101", "9x6x2",
                            "00000000000000000000009x0000000000000000000000junk"}) {
    const CommandResult r = run_cli(std::string("calibrate --board ") + board + rest);
    EXPECT_EQ(r.exit_code, 2) << board << ": " << r.output;
    EXPECT_EQ(r.output, std::string("hazmap: error: --board ") + board +
                            ": expected inner corners as WxH, e.g. 9x6 (see hazmap calibrate --help)\n");
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

TEST(CliBench, OneSampleFramePrintsStagesAndTheRatio) {
  // The subcommand end to end on one 640 x 520 sample frame with its own config (the
  // full-resolution default would render frames for ~25 s). No timing is checked.
  const std::string cmd = std::string(HAZMAP_CLI) + " bench --config " +
                          (testing::source_dir() / "config/cadre_flight.yaml").string() +
                          " --sequence " + (testing::source_dir() / "data/sample").string() +
                          " --frames 1 --repetitions 1 2>&1";
  const CommandResult r = testing::run_command(cmd);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* line : {"rectify", "disparity", "points", "map", "hazard", "frame",
                           "StereoBM", "frame / StereoBM", "640 x 520"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << " missing in\n" << r.output;

  EXPECT_EQ(testing::run_command(std::string(HAZMAP_CLI) + " bench --repetitions 0 2>&1")
                .exit_code,
            2);
}


std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Cli, RunReadsAnEurocFolderInPlaceAsImportEurocThenRunWould) {
  const std::filesystem::path euroc = testing::source_dir() / "../shared/data/euroc_v1_01_micro";
  if (!std::filesystem::exists(euroc / "mav0"))
    GTEST_SKIP() << euroc.string() << " is absent (shared real data)";
  testing::TempDir dir;
  // A 5 m layer of 4 cm cells: the floor lies 1-4 m ahead of the cameras.
  const std::string config = (testing::source_dir() / "config/default.yaml").string() +
                             " --set map.layers.0.resolution=0.04 --set map.layers.0.size=128"
                             " --set stereo.z_max=5";
  const std::string poses = " --poses " + (euroc / "poses_leftcam_gt.csv").string() +
                            " --pose-frame left_camera";
  // In place, two frames.
  CommandResult r = run_cli("run --config " + config + " --sequence " + euroc.string() + poses +
                            " --frames 0:2 --quiet --out " + (dir / "direct").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "");  // --quiet: not even the EuRoC loader's line
  // The independent path: convert, then run on our layout.
  r = run_cli("import-euroc " + euroc.string() + " " + (dir / "seq").string() + poses);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli("run --config " + config + " --sequence " + (dir / "seq").string() +
              " --frames 0:2 --quiet --out " + (dir / "imported").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int frames = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "imported/frames")) {
    ++frames;
    const auto name = e.path().filename();
    for (const char* file : {"L0_height.jdem", "L0_variance.jdem", "L0_hazard.jdem"})
      EXPECT_EQ(file_text(dir / "direct/frames" / name / file), file_text(e.path() / file))
          << name << "/" << file;
    // Not an empty map compared with an empty one: the floor is in it.
    const JdemGrid h = read_jdem(e.path() / "L0_height.jdem");
    int known = 0;
    for (float v : h.values) known += std::isfinite(v);
    EXPECT_GT(known, 1000) << name;
  }
  EXPECT_EQ(frames, 2);
  // Both runs record the same poses fingerprint (issue 22): the poses used in place are
  // the ones import-euroc wrote.
  const auto fingerprint = [&](const char* run) {
    const std::string summary = file_text(dir / run / "summary.json");
    const auto at = summary.find("\"poses_fingerprint\": \"");
    return at == std::string::npos ? std::string("none") : summary.substr(at + 22, 16);
  };
  EXPECT_EQ(fingerprint("direct"), fingerprint("imported"));
  EXPECT_NE(fingerprint("direct"), "none");
  // The EuRoC options belong to EuRoC folders only.
  testing::write_tiny_sequence(dir / "tiny", 1);
  r = run_cli("run --config " + config + " --sequence " + (dir / "tiny").string() + poses +
              " --out " + (dir / "bad").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--poses applies to ASL/EuRoC folders"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

// --quiet is accepted by every subcommand: with an unknown flag after it, the complaint
// is about that flag, never about --quiet.
TEST(Cli, EverySubcommandTakesQuiet) {
  for (const char* command : {"run", "check", "stereo", "simulate", "evaluate", "calibrate",
                              "ground-truth", "bench", "import-euroc a b"}) {
    const auto r = testing::run_command(std::string(HAZMAP_CLI) + " " + command +
                                        " --quiet --bogus 2>&1");
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.output;
    EXPECT_NE(r.output.find("unknown option --bogus"), std::string::npos) << command << ": " << r.output;
    EXPECT_EQ(r.output.find("--quiet"), std::string::npos) << command << ": " << r.output;
  }
}

}  // namespace
}  // namespace hazmap
