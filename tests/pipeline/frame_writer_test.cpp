// The writer thread (issue 20, SPEC 9): the same files as writing on the frame loop's
// thread, byte for byte; write errors stop the run naming frame and file; no partial
// frame folder or temporary file is left.

#include "hazmap/pipeline/frame_writer.hpp"

#include <algorithm>
#include <map>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/sequence_runner.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// Every file under `root` (relative path -> bytes), except the run's summary, whose
/// timings differ from run to run.
std::map<std::string, std::string> files_under(const std::filesystem::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
    const std::string rel = std::filesystem::relative(e.path(), root).string();
    if (e.is_regular_file() && rel != "summary.json") files[rel] = testing::read_text(e.path());
  }
  return files;
}

bool hidden_entry_under(const std::filesystem::path& root) {
  for (const auto& e : std::filesystem::recursive_directory_iterator(root))
    if (e.path().filename().string().front() == '.') return true;
  return false;
}

Config writer_config(const std::string& format, int queue_frames) {
  Config c = load_config(testing::source_dir() / "config/default.yaml");
  c.map.layers.front().size = 96;
  LayerConfig ccm = c.map.layers.front();  // a CCM layer: slope grids too
  ccm.rule = RuleKind::ccm;
  ccm.resolution_m = 0.04;
  ccm.size = 32;
  c.map.layers.push_back(ccm);
  c.output.format = *enum_value<GridFormat>(format);
  c.output.queue_frames = queue_frames;
  c.output.mosaic = true;
  return c;
}

RunResult run(const Config& config, const std::filesystem::path& out, const std::string& frames) {
  const auto seq_dir = testing::source_dir() / "data/sample";
  RunOptions options;
  options.sequence_dir = seq_dir;
  options.out_dir = out;
  options.frames = frames;
  return run_sequence(config, load_sequence(seq_dir), options);
}

TEST(FrameWriter, WriterThreadWritesTheSameBytesAsTheFrameLoop) {
  testing::TempDir dir;
  // A one-frame queue makes the loop wait for the writer on most frames.
  run(writer_config("both", 0), dir / "sync", "0:4");
  run(writer_config("both", 1), dir / "queue1", "0:4");
  const RunResult threaded = run(writer_config("both", 2), dir / "queue2", "0:4");
  EXPECT_EQ(threaded.frames_written, 4);
  const auto sync = files_under(dir / "sync");
  // 4 frames x (2 layers x 2 PNGs + 2 PNGs + (3 + 5 + 4) grids x 2 formats) + 4 mosaics
  EXPECT_EQ(sync.size(), 4u * (4 + 2 + 24) + 4) << "file set changed";
  EXPECT_EQ(sync.count("frames/000000/L1_slope_y.tif"), 1u);
  EXPECT_EQ(sync.count("mosaic/000003.png"), 1u);
  for (const char* other : {"queue1", "queue2"}) {
    const auto files = files_under(dir / other);
    ASSERT_EQ(files.size(), sync.size()) << other;
    for (const auto& [name, bytes] : sync) {
      const auto it = files.find(name);
      ASSERT_NE(it, files.end()) << other << ": " << name << " missing";
      EXPECT_TRUE(it->second == bytes) << other << ": " << name << " differs";
    }
    EXPECT_FALSE(hidden_entry_under(dir / other)) << other;
  }
}

TEST(FrameWriter, RewritingAFrameFolderReplacesItWhole) {
  testing::TempDir dir;
  Config config = writer_config("jdem", 2);
  config.output.mosaic = false;
  run(config, dir / "out", "0:1");
  const auto stale = dir / "out/frames/000000/stale.txt";
  testing::run_command("touch " + stale.string());
  ASSERT_TRUE(std::filesystem::exists(stale));
  run(config, dir / "out", "0:1");
  EXPECT_FALSE(std::filesystem::exists(stale));  // the folder is the new one, not a mix
  EXPECT_TRUE(std::filesystem::exists(dir / "out/frames/000000/L0_height.jdem"));
  EXPECT_FALSE(hidden_entry_under(dir / "out"));
}

TEST(FrameWriter, AWriteErrorStopsTheRunNamingFrameAndFile) {
  for (int queue : {0, 2}) {
    testing::TempDir dir;
    Config config = writer_config("geotiff", queue);
    std::filesystem::create_directories(dir / "out");
    {  // OUT/mosaic is a file: the first frame's mosaic cannot be written
      std::ofstream blocker(dir / "out/mosaic");
    }
    try {
      run(config, dir / "out", "0:4");
      FAIL() << "queue " << queue << ": no error";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("frame 000000"), std::string::npos) << what;
      EXPECT_NE(what.find((dir / "out/mosaic").string()), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_FALSE(hidden_entry_under(dir / "out")) << "queue " << queue;
  }
}

TEST(FrameWriter, AFailedFrameFolderIsNotLeftHalfWritten) {
  testing::TempDir dir;
  Config config = writer_config("jdem", 2);
  config.output.mosaic = false;
  std::filesystem::create_directories(dir / "out");
  {  // OUT/frames is a file: no frame folder can be staged
    std::ofstream blocker(dir / "out/frames");
  }
  try {
    run(config, dir / "out", "0:2");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("frame 000000"), std::string::npos) << what;
    // Named as the user sees it: the frame's folder, not the hidden staging name.
    EXPECT_NE(what.find((dir / "out/frames/000000").string()), std::string::npos) << what;
  }
  EXPECT_FALSE(hidden_entry_under(dir / "out"));
}

}  // namespace
}  // namespace hazmap
