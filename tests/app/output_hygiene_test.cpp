// Issue 22 item 6, output hygiene, through the real binary: `hazmap run` and `hazmap
// stereo` never mix two runs' frames in one OUT (a non-empty OUT needs --overwrite,
// which removes only hazmap's own outputs), summary.json records the sequence and a
// fingerprint of its poses, and `hazmap evaluate` refuses a run of another sequence.
// `hazmap simulate` and `hazmap import-euroc` follow the same rule for their folders.

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "eval/oracle_run.hpp"
#include "hazmap/io/sequence.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::snapshot;

/// Runs the CLI with `args`; stderr into `output`, stdout discarded.
const auto run_cli = testing::run_hazmap;

const std::string kTinySets =
    " --set stereo.num_disparities=16 --set stereo.block_size=5 --set map.layers.0.size=16"
    " --set map.layers.0.hazard.kernel=3 --set stereo.z_max=10 --quiet";

std::string config_path() { return (testing::source_dir() / "config/default.yaml").string(); }

std::string run_args(const fs::path& seq, const fs::path& out) {
  return "run --config " + config_path() + " --sequence " + seq.string() + " --out " +
         out.string() + kTinySets;
}

std::string stereo_args(const fs::path& seq, const fs::path& out) {
  return "stereo --config " + config_path() + " --sequence " + seq.string() + " --out " +
         out.string() + " --set stereo.num_disparities=16 --set stereo.block_size=5 --quiet";
}

int count_lines(const std::string& s) {
  return static_cast<int>(std::count(s.begin(), s.end(), '\n'));
}

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

/// Moves frame 000001 of a tiny sequence's poses.txt by 1 mm in x.
void move_one_pose(const fs::path& seq) {
  std::string poses = testing::read_text(seq / "poses.txt");
  const std::string from = "000001 1 0.04 ", to = "000001 1 0.041 ";
  const auto at = poses.find(from);
  ASSERT_NE(at, std::string::npos) << poses;
  poses.replace(at, from.size(), to);
  std::ofstream(seq / "poses.txt", std::ios::trunc) << poses;
}

YAML::Node summary_of(const fs::path& out) {
  return YAML::LoadFile((out / "summary.json").string());
}

TEST(OutputHygiene, RunRefusesANonEmptyOutAndLeavesItUntouched) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  ASSERT_EQ(run_cli(run_args(dir / "seq", dir / "out")).exit_code, 0);
  const auto before = snapshot(dir / "out");
  const CommandResult r = run_cli(run_args(dir / "seq", dir / "out") + " --frames 0:1");
  EXPECT_EQ(r.exit_code, 2) << r.output;  // a command-line mistake, like the other usage errors
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("hazmap: error: --out " + (dir / "out").string() + ": not empty (", 0), 0u)
      << r.output;
  EXPECT_NE(r.output.find("pass --overwrite to replace it"), std::string::npos) << r.output;
  EXPECT_EQ(snapshot(dir / "out"), before) << "OUT changed";  // byte for byte
}

TEST(OutputHygiene, OverwriteRemovesTheFramesOfALongerEarlierRun) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  ASSERT_EQ(run_cli(run_args(dir / "seq", dir / "out") + " --mosaic").exit_code, 0);
  fs::create_directories(dir / "out/eval");
  std::ofstream(dir / "out/eval/metrics.csv") << "of the earlier run\n";
  ASSERT_EQ(names_in(dir / "out/frames"), (std::set<std::string>{"000000", "000001", "000002"}));

  const CommandResult r = run_cli(run_args(dir / "seq", dir / "out") + " --frames 0:1 --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(names_in(dir / "out/frames"), std::set<std::string>{"000000"});  // no stale frame
  EXPECT_FALSE(fs::exists(dir / "out/mosaic"));                              // this run wrote none
  EXPECT_FALSE(fs::exists(dir / "out/eval"));  // it scored the earlier frames
  EXPECT_EQ(names_in(dir / "out"), (std::set<std::string>{"frames", "run.log", "summary.json"}));
  EXPECT_EQ(summary_of(dir / "out")["frames_processed"].as<int>(), 1);
  // run.log appends, but it went with the rest: it tells of this run alone.
  const std::string log = testing::read_text(dir / "out/run.log");
  EXPECT_EQ(log.find(" run: config "), log.rfind(" run: config ")) << log;
}

TEST(OutputHygiene, AFolderHoldingOtherFilesIsRefusedEvenWithOverwrite) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 2);
  ASSERT_EQ(run_cli(run_args(dir / "seq", dir / "out")).exit_code, 0);
  std::ofstream(dir / "out/notes.txt") << "mine\n";
  const auto before = snapshot(dir / "out");
  for (const char* overwrite : {"", " --overwrite"}) {
    const CommandResult r = run_cli(run_args(dir / "seq", dir / "out") + overwrite);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("--out " + (dir / "out").string() +
                            ": holds notes.txt, which hazmap did not write"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(snapshot(dir / "out"), before) << "OUT changed" << overwrite;
  }
  // OUT pointed at the sequence itself: refused, the sequence untouched.
  const auto sequence = snapshot(dir / "seq");
  const CommandResult r = run_cli(run_args(dir / "seq", dir / "seq") + " --overwrite");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds calibration.yaml, left, poses.txt, right, which"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(snapshot(dir / "seq"), sequence);
}

TEST(OutputHygiene, StereoFollowsTheSameRule) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 2);
  ASSERT_EQ(run_cli(stereo_args(dir / "seq", dir / "out")).exit_code, 0);
  const auto before = snapshot(dir / "out");
  CommandResult r = run_cli(stereo_args(dir / "seq", dir / "out") + " --frames 1:2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pass --overwrite"), std::string::npos) << r.output;
  EXPECT_EQ(snapshot(dir / "out"), before);
  r = run_cli(stereo_args(dir / "seq", dir / "out") + " --frames 1:2 --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(names_in(dir / "out/frames"), std::set<std::string>{"000001"});
}

TEST(OutputHygiene, SummaryRecordsTheSequenceAndAFingerprintOfAllItsPoses) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  // A relative --sequence is recorded as the absolute folder it named.
  const CommandResult r = testing::run_command(
      "cd " + dir.path().string() + " && " + HAZMAP_CLI + " run --config " + config_path() +
      " --sequence ./seq/ --out part --frames 1:3" + kTinySets + " 2>&1 1>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const YAML::Node part = summary_of(dir / "part");
  EXPECT_EQ(part["sequence"].as<std::string>(), (dir / "seq").string());
  const Sequence seq = load_sequence(dir / "seq");
  EXPECT_EQ(part["poses_fingerprint"].as<std::string>(), fingerprint_hex(*seq.poses_fingerprint));
  // The whole sequence's poses, not the frames run: a run of every frame records the same.
  ASSERT_EQ(run_cli(run_args(dir / "seq", dir / "all")).exit_code, 0);
  EXPECT_EQ(summary_of(dir / "all")["poses_fingerprint"].as<std::string>(),
            part["poses_fingerprint"].as<std::string>());
  // One pose moved by 1 mm: another fingerprint.
  fs::copy(dir / "seq", dir / "moved", fs::copy_options::recursive);
  move_one_pose(dir / "moved");
  ASSERT_EQ(run_cli(run_args(dir / "moved", dir / "moved_run")).exit_code, 0);
  EXPECT_NE(summary_of(dir / "moved_run")["poses_fingerprint"].as<std::string>(),
            part["poses_fingerprint"].as<std::string>());
}

TEST(OutputHygiene, EvaluateRefusesARunOfAnotherSequence) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  testing::write_ground_truth(dir / "seq", testing::TestWorld{});
  // A subset of the frames still evaluates against its sequence.
  ASSERT_EQ(run_cli(run_args(dir / "seq", dir / "run") + " --frames 1:3").exit_code, 0);
  const std::string evaluate = "evaluate --quiet --run " + (dir / "run").string() + " --sequence ";
  CommandResult r = run_cli(evaluate + (dir / "seq").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "");
  EXPECT_TRUE(fs::exists(dir / "run/eval/summary.csv"));

  // Another sequence (one pose 1 mm off): one line naming both folders, exit 1.
  fs::copy(dir / "seq", dir / "other", fs::copy_options::recursive);
  move_one_pose(dir / "other");
  r = run_cli(evaluate + (dir / "other").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  const std::string fp = summary_of(dir / "run")["poses_fingerprint"].as<std::string>();
  EXPECT_EQ(r.output, "hazmap: error: run " + (dir / "run").string() + " was made from sequence " +
                          (dir / "seq").string() + " (poses fingerprint " + fp + "), not from " +
                          (dir / "other").string() + " (" +
                          fingerprint_hex(read_poses_fingerprint(dir / "other")) +
                          "): evaluate it against the sequence it was run on\n");

  // The sequence itself changed since the run: said so.
  move_one_pose(dir / "seq");
  r = run_cli(evaluate + (dir / "seq").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("was made from " + (dir / "seq").string() + " (poses fingerprint " + fp +
                          "), whose poses.txt has changed since"),
            std::string::npos)
      << r.output;

  // A run from before the fingerprint: a warning, and it is scored.
  std::string summary = testing::read_text(dir / "run/summary.json");
  const auto at = summary.find("  \"poses_fingerprint\": ");
  ASSERT_NE(at, std::string::npos) << summary;
  summary.erase(at, summary.find('\n', at) + 1 - at);
  std::ofstream(dir / "run/summary.json", std::ios::trunc) << summary;
  r = run_cli(evaluate + (dir / "other").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("records no poses fingerprint"), std::string::npos) << r.output;
}

// The same rule for the sequence writers: `hazmap simulate --out DIR` and `hazmap
// import-euroc SRC DST` refuse a non-empty folder, and --overwrite removes only what the
// command writes, so no file of an earlier sequence (poses_true.txt, a frame past the
// new end, depth/, gt_*.jdem) survives into the new one.

std::string simulate_args(const fs::path& out) {
  // The smallest images simulate renders, one ray per pixel: a fraction of a second.
  return "simulate --scenario rocks --scale 0.05 --samples 1 --quiet --out " + out.string();
}

TEST(OutputHygiene, SimulateRefusesANonEmptyOutAndOverwriteLeavesNoStaleFile) {
  testing::TempDir dir;
  const fs::path seq = dir / "seq";
  CommandResult r =
      run_cli(simulate_args(seq) + " --frames 3 --drift 0.05 --ground-truth --gt-margin 0.2 --depth");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(seq / "poses_true.txt"));
  const auto before = snapshot(seq);

  // Again without --overwrite: one line, exit 2 (as for run), the first sequence intact.
  r = run_cli(simulate_args(seq) + " --frames 2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("hazmap: error: --out " + seq.string() + ": not empty (an earlier output: ", 0),
            0u)
      << r.output;
  EXPECT_NE(r.output.find("pass --overwrite to replace it"), std::string::npos) << r.output;
  EXPECT_EQ(snapshot(seq), before) << "the first sequence changed";

  // --overwrite with a bad option: every option is checked before anything is removed.
  r = run_cli(simulate_args(seq) + " --frames 2 --path zigzag --overwrite");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("zigzag"), std::string::npos) << r.output;
  EXPECT_EQ(snapshot(seq), before) << "a refused simulation changed the earlier one";

  // --overwrite, no drift, fewer frames, no ground truth, no depth: nothing stale is left.
  r = run_cli(simulate_args(seq) + " --frames 2 --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(seq / "poses_true.txt"));  // evaluate would take it as the truth
  EXPECT_EQ(names_in(seq), (std::set<std::string>{"calibration.yaml", "left", "poses.txt", "right",
                                                  "simulation.yaml"}));
  EXPECT_EQ(names_in(seq / "left"), (std::set<std::string>{"000000.png", "000001.png"}));
  EXPECT_EQ(names_in(seq / "right"), (std::set<std::string>{"000000.png", "000001.png"}));
  // The same sequence as one simulated into a new folder, byte for byte.
  ASSERT_EQ(run_cli(simulate_args(dir / "fresh") + " --frames 2").exit_code, 0);
  const auto fresh = snapshot(dir / "fresh");
  auto now = snapshot(seq);
  ASSERT_EQ(now.size(), fresh.size());
  for (const auto& [name, bytes] : fresh) {
    if (name == "simulation.yaml") continue;  // it names OUT
    EXPECT_EQ(now[name], bytes) << name;
  }
}

TEST(OutputHygiene, SimulateRefusesAFolderHoldingOtherFilesEvenWithOverwrite) {
  testing::TempDir dir;
  const fs::path seq = dir / "seq";
  ASSERT_EQ(run_cli(simulate_args(seq) + " --frames 1").exit_code, 0);
  std::ofstream(seq / "notes.txt") << "mine\n";
  auto before = snapshot(seq);
  for (const char* overwrite : {"", " --overwrite"}) {
    const CommandResult r = run_cli(simulate_args(seq) + " --frames 1" + overwrite);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output.rfind("hazmap: error: --out " + seq.string() +
                                 ": holds notes.txt, which hazmap simulate did not write; "
                                 "refusing to write there, --overwrite included",
                             0),
              0u)
        << r.output;
    EXPECT_EQ(snapshot(seq), before) << "the folder changed" << overwrite;
  }
  EXPECT_EQ(testing::read_text(seq / "notes.txt"), "mine\n");

  // A sequence simulate did not make (no simulation.yaml: recorded, imported) looks like
  // its own output, and is still refused: --overwrite never removes someone's images.
  testing::write_tiny_sequence(dir / "recorded", 2);
  before = snapshot(dir / "recorded");
  const CommandResult r = run_cli(simulate_args(dir / "recorded") + " --frames 1 --overwrite");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(": holds calibration.yaml, left, poses.txt, right, which hazmap "
                          "simulate did not write (no simulation.yaml"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(snapshot(dir / "recorded"), before);
}

fs::path euroc_dir() { return testing::source_dir() / "../shared/data/euroc_v1_01_micro"; }

/// A small ASL/EuRoC folder: the first `pairs` image pairs of the shared micro set and
/// its sensor.yaml files (imported with --identity-poses).
void write_small_euroc(const fs::path& dir, int pairs) {
  for (const char* cam : {"cam0", "cam1"}) {
    const fs::path from = euroc_dir() / "mav0" / cam, to = dir / "mav0" / cam;
    fs::create_directories(to / "data");
    fs::copy_file(from / "sensor.yaml", to / "sensor.yaml");
    std::vector<fs::path> images;
    for (const auto& e : fs::directory_iterator(from / "data")) images.push_back(e.path());
    std::sort(images.begin(), images.end());
    for (int i = 0; i < pairs; ++i) fs::copy_file(images.at(i), to / "data" / images[i].filename());
  }
}

std::string import_args(const fs::path& src, const fs::path& dst) {
  return "import-euroc " + src.string() + " " + dst.string() + " --identity-poses --quiet";
}

TEST(OutputHygiene, ImportEurocFollowsTheSameRule) {
  if (!fs::is_directory(euroc_dir() / "mav0"))
    GTEST_SKIP() << euroc_dir().string() << " is absent (shared real data)";
  testing::TempDir dir;
  write_small_euroc(dir / "three", 3);
  write_small_euroc(dir / "two", 2);
  const fs::path seq = dir / "seq";
  CommandResult r = run_cli(import_args(dir / "three", seq));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(names_in(seq / "left").size(), 3u);
  const auto before = snapshot(seq);

  // Again without --overwrite: one line naming DST, exit 2, the first import intact.
  r = run_cli(import_args(dir / "two", seq));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("hazmap: error: DST " + seq.string() + ": not empty (an earlier output: ", 0),
            0u)
      << r.output;
  EXPECT_NE(r.output.find("pass --overwrite"), std::string::npos) << r.output;
  EXPECT_EQ(snapshot(seq), before);

  // --overwrite with a bad SRC: nothing removed.
  r = run_cli(import_args(dir / "nowhere", seq) + " --overwrite");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(snapshot(seq), before);

  // --overwrite from a shorter sequence: the third frame does not survive.
  r = run_cli(import_args(dir / "two", seq) + " --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(names_in(seq), (std::set<std::string>{"calibration.yaml", "left", "poses.txt", "right"}));
  EXPECT_EQ(names_in(seq / "left"), names_in(dir / "two/mav0/cam0/data"));
  EXPECT_EQ(names_in(seq / "right"), names_in(dir / "two/mav0/cam1/data"));
  EXPECT_EQ(load_sequence(seq).frames.size(), 2u);

  // A foreign file: refused with or without --overwrite, and it survives.
  std::ofstream(seq / "notes.txt") << "mine\n";
  const auto with_notes = snapshot(seq);
  for (const char* overwrite : {"", " --overwrite"}) {
    r = run_cli(import_args(dir / "two", seq) + overwrite);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("DST " + seq.string() +
                            ": holds notes.txt, which hazmap import-euroc did not write"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(snapshot(seq), with_notes) << overwrite;
  }

  // A sequence it did not import (no "imported from EuRoC" in poses.txt): refused.
  testing::write_tiny_sequence(dir / "recorded", 2);
  const auto recorded = snapshot(dir / "recorded");
  r = run_cli(import_args(dir / "two", dir / "recorded") + " --overwrite");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds calibration.yaml, left, poses.txt, right, which hazmap "
                          "import-euroc did not write (no poses.txt saying 'imported from EuRoC'"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(snapshot(dir / "recorded"), recorded);
}

}  // namespace
}  // namespace hazmap
