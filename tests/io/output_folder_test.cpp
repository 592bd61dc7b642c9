// Issue 22: which OUT folders hazmap run and stereo may write into, and what
// --overwrite removes (hazmap's own entries only).

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

TEST(OutputFolder, AFileIsNotAFolder) {
  testing::TempDir dir;
  touch(dir / "file");
  EXPECT_EQ(output_folder_refusal(inspect_output_folder(dir / "file"), true),
            "--out " + (dir / "file").string() + ": exists and is not a folder");
}

}  // namespace
}  // namespace hazmap
