// Issue 22: which OUT folders hazmap run and stereo (and simulate, import-euroc) may
// write into, and what --overwrite removes (the command's own entries only).

#include "hazmap/io/output_folder.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;

void touch(const fs::path& path, const std::string& text = "x\n") {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

/// An earlier output of every kind: run (with --mosaic), evaluate, stereo, view, a
/// temporary left by a killed write, and a frame staged but not yet renamed.
void write_earlier_output(const fs::path& out) {
  touch(out / "frames/000000/L0_height.jdem");
  touch(out / "frames/.000001.tmp123_4/L0_height.jdem");
  touch(out / "mosaic/000000.png");
  touch(out / "eval/metrics.csv");
  touch(out / "summary.json", "{}\n");
  touch(out / "stereo_summary.json", "{}\n");
  touch(out / "run.log");
  touch(out / "view.html");
  touch(out / ".summary.json.tmp123_7");
}

TEST(OutputFolder, AbsentAndEmptyFoldersMayBeWritten) {
  testing::TempDir dir;
  const OutputFolder absent = inspect_output_folder(dir / "new");
  EXPECT_FALSE(absent.exists);
  EXPECT_EQ(output_folder_refusal(absent, false), "");
  const OutputFolder empty = inspect_output_folder(dir.path());
  EXPECT_TRUE(empty.exists && empty.is_folder && empty.empty());
  EXPECT_EQ(output_folder_refusal(empty, false), "");
  clear_output_folder(empty);  // nothing to do
  EXPECT_TRUE(fs::is_directory(dir.path()));
}

TEST(OutputFolder, AnEarlierOutputNeedsOverwriteWhichRemovesAllOfIt) {
  testing::TempDir dir;
  const fs::path out = dir / "out";
  write_earlier_output(out);
  const OutputFolder found = inspect_output_folder(out);
  EXPECT_TRUE(found.foreign.empty());
  EXPECT_EQ(found.ours.size(), 8u);  // frames, mosaic, eval, 4 files, the temporary
  EXPECT_EQ(output_folder_refusal(found, false),
            "--out " + out.string() +
                ": not empty (an earlier output: .summary.json.tmp123_7, eval, frames, mosaic "
                "and 4 more); pass --overwrite to replace it, or choose an empty or new folder");
  EXPECT_EQ(output_folder_refusal(found, true), "");
  clear_output_folder(found);
  EXPECT_TRUE(fs::is_directory(out));  // the folder stays, empty
  EXPECT_TRUE(fs::is_empty(out));
}

TEST(OutputFolder, ForeignEntriesAreRefusedEvenWithOverwriteAndKept) {
  testing::TempDir dir;
  // A folder of someone's own beside an earlier output; a sequence; files inside our
  // folders; a link named like ours.
  struct Case {
    std::string name;
    std::function<void(const fs::path&)> make;
    std::string listed;
  };
  const std::vector<Case> cases = {
      {"notes beside a run",
       [](const fs::path& o) { write_earlier_output(o), touch(o / "notes.txt"); },
       "holds notes.txt, which"},
      {"a sequence",
       [](const fs::path& o) {
         touch(o / "left/000000.png"), touch(o / "right/000000.png");
         touch(o / "poses.txt"), touch(o / "calibration.yaml");
       },
       "holds calibration.yaml, left, poses.txt, right, which"},
      {"a file in frames/", [](const fs::path& o) { touch(o / "frames/README"); },
       "holds frames/README, which"},
      {"a folder in eval/", [](const fs::path& o) { touch(o / "eval/mine/a.csv"); },
       "holds eval/mine, which"},
      {"summary.json a folder", [](const fs::path& o) { touch(o / "summary.json/x"); },
       "holds summary.json, which"},
      {"frames a link",
       [&](const fs::path& o) {
         touch(dir / "elsewhere/000000/keep.txt");
         fs::create_directories(o);
         fs::create_directory_symlink(dir / "elsewhere", o / "frames");
       },
       "holds frames, which"},
  };
  int n = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path out = dir / ("out" + std::to_string(++n));
    c.make(out);
    const OutputFolder found = inspect_output_folder(out);
    for (bool overwrite : {false, true}) {
      const std::string why = output_folder_refusal(found, overwrite);
      EXPECT_EQ(why.rfind("--out " + out.string() + ": " + c.listed, 0), 0u) << why;
      EXPECT_NE(why.find("--overwrite"), std::string::npos) << why;
      EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    }
  }
  EXPECT_TRUE(fs::exists(dir / "elsewhere/000000/keep.txt"));
  // Many foreign entries: four named, the rest counted.
  for (int i = 0; i < 6; ++i) touch(dir / "many" / ("f" + std::to_string(i)));
  EXPECT_NE(output_folder_refusal(inspect_output_folder(dir / "many"), true)
                .find("holds f0, f1, f2, f3 and 2 more, which"),
            std::string::npos);
}

TEST(OutputFolder, ClearingLeavesWhatAppearedSinceAlone) {
  testing::TempDir dir;
  write_earlier_output(dir / "out");
  const OutputFolder found = inspect_output_folder(dir / "out");
  touch(dir / "out/late.txt");  // not in the inspection: not removed
  clear_output_folder(found);
  EXPECT_TRUE(fs::exists(dir / "out/late.txt"));
  EXPECT_FALSE(fs::exists(dir / "out/frames"));
}

/// An earlier `hazmap simulate` output of every kind, and an earlier import.
void write_earlier_simulation(const fs::path& out) {
  for (const char* f : {"left/000000.png", "right/000000.png", "left/.000001.png.tmp12_3",
                        "depth/000000.tiff", "calibration.yaml", "simulation.yaml", "poses.txt",
                        "poses_true.txt", "gt_height.jdem", "gt_hazard.jdem",
                        ".gt_hazard.jdem.tmp12_4"})
    touch(out / f);
}

void write_earlier_import(const fs::path& out) {
  for (const char* f : {"left/1403715273262142976.png", "right/1403715273262142976.png",
                        "calibration.yaml"})
    touch(out / f);
  touch(out / "poses.txt", "# name t x y z qx qy qz qw   (T_W_B; imported from EuRoC /d/mav0)\n");
}

TEST(OutputFolder, EachSequenceWriterOwnsWhatItWrites) {
  testing::TempDir dir;
  const fs::path sim = dir / "sim", imp = dir / "import";
  write_earlier_simulation(sim);
  write_earlier_import(imp);
  OutputFolder found = inspect_output_folder(sim, OutputOwner::simulate);
  EXPECT_TRUE(found.foreign.empty()) << found.foreign.front();
  EXPECT_EQ(found.ours.size(), 10u);  // 3 folders, 6 files, the temporary
  EXPECT_EQ(output_folder_refusal(found, false),
            "--out " + sim.string() +
                ": not empty (an earlier output: .gt_hazard.jdem.tmp12_4, calibration.yaml, "
                "depth, gt_hazard.jdem and 6 more); pass --overwrite to replace it, or choose "
                "an empty or new folder");
  EXPECT_EQ(output_folder_refusal(found, true), "");
  found = inspect_output_folder(imp, OutputOwner::import_euroc);
  EXPECT_EQ(found.ours.size(), 4u);
  EXPECT_EQ(output_folder_refusal(found, true), "");
  EXPECT_EQ(output_folder_refusal(found, false).rfind("DST " + imp.string() + ": not empty", 0), 0u);

  // Each is foreign to the others: a simulation is not an import, nor a run's OUT.
  EXPECT_EQ(output_folder_refusal(inspect_output_folder(sim, OutputOwner::import_euroc), true)
                .rfind("DST " + sim.string() + ": holds .gt_hazard.jdem.tmp12_4, calibration.yaml, "
                       "depth, gt_hazard.jdem and 6 more, which hazmap import-euroc did not write",
                       0),
            0u);
  EXPECT_NE(output_folder_refusal(inspect_output_folder(imp, OutputOwner::simulate), true)
                .find("holds calibration.yaml, left, poses.txt, right, which hazmap simulate did "
                      "not write (no simulation.yaml, so not a sequence it simulated)"),
            std::string::npos);
  EXPECT_NE(output_folder_refusal(inspect_output_folder(sim, OutputOwner::run), true)
                .find("which hazmap did not write"),
            std::string::npos);
  // A run's OUT is foreign to simulate.
  write_earlier_output(dir / "run");
  EXPECT_NE(output_folder_refusal(inspect_output_folder(dir / "run", OutputOwner::simulate), true)
                .find("holds .summary.json.tmp123_7, eval, frames, mosaic and 4 more, which hazmap "
                      "simulate did not write;"),
            std::string::npos);

  clear_output_folder(inspect_output_folder(sim, OutputOwner::simulate));
  EXPECT_TRUE(fs::is_directory(sim) && fs::is_empty(sim));
  clear_output_folder(inspect_output_folder(imp, OutputOwner::import_euroc));
  EXPECT_TRUE(fs::is_directory(imp) && fs::is_empty(imp));
}

TEST(OutputFolder, ASequenceWithoutTheWritersMarkIsForeign) {
  testing::TempDir dir;
  // A recorded sequence: named like simulate's and import-euroc's outputs, made by neither.
  const fs::path rec = dir / "recorded";
  touch(rec / "left/000000.png"), touch(rec / "right/000000.png");
  touch(rec / "calibration.yaml"), touch(rec / "poses.txt", "# name t x y z qx qy qz qw\n");
  for (OutputOwner owner : {OutputOwner::simulate, OutputOwner::import_euroc}) {
    const OutputFolder found = inspect_output_folder(rec, owner);
    EXPECT_TRUE(found.ours.empty());
    EXPECT_EQ(found.foreign,
              (std::vector<std::string>{"calibration.yaml", "left", "poses.txt", "right"}));
    EXPECT_FALSE(found.unmarked.empty());
    EXPECT_NE(output_folder_refusal(found, true).find(" (" + found.unmarked + "); refusing"),
              std::string::npos);
  }
  // A simulation.yaml that is a folder, or a link, is no mark.
  fs::create_directories(rec / "simulation.yaml");
  EXPECT_FALSE(inspect_output_folder(rec, OutputOwner::simulate).foreign.empty());
  // Files inside left/ must be files, as in mosaic/.
  write_earlier_simulation(dir / "sim");
  touch(dir / "sim/left/sub/x.png");
  EXPECT_EQ(inspect_output_folder(dir / "sim", OutputOwner::simulate).foreign,
            std::vector<std::string>{"left/sub"});
  // Only a temporary left by a simulation killed in its first write: its own, no mark needed.
  touch(dir / "killed/.simulation.yaml.tmp9_1");
  const OutputFolder killed = inspect_output_folder(dir / "killed", OutputOwner::simulate);
  EXPECT_TRUE(killed.foreign.empty());
  EXPECT_EQ(killed.ours.size(), 1u);
  EXPECT_EQ(output_folder_refusal(killed, true), "");
}

TEST(OutputFolder, AFileIsNotAFolder) {
  testing::TempDir dir;
  touch(dir / "file");
  EXPECT_EQ(output_folder_refusal(inspect_output_folder(dir / "file"), true),
            "--out " + (dir / "file").string() + ": exists and is not a folder");
}

}  // namespace
}  // namespace hazmap
