#pragma once
// Helpers shared by the tests: unique temporary folders that clean up after themselves,
// and a ParallelFor on plain threads.

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "hazmap/core/parallel_for.hpp"

namespace hazmap::testing {

/// A ParallelFor on std::threads: part k of `threads` on its own thread, all at once.
class ThreadsFor final : public ParallelFor {
 public:
  explicit ThreadsFor(int threads) : threads_(threads) {}
  void run(int n, const RangeTask& task) const override {
    std::vector<std::thread> pool;
    for (int k = 0; k < threads_; ++k) {
      const EvenPart part = even_part(n, threads_, k);
      if (part.begin < part.end) pool.emplace_back([&task, part] { task(part.begin, part.end); });
    }
    for (std::thread& t : pool) t.join();
  }
  int threads() const override { return threads_; }

 private:
  int threads_;
};

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("hazmap_" + std::string(info ? info->name() : "test") + "_" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline std::filesystem::path source_dir() { return HAZMAP_SOURCE_DIR; }

}  // namespace hazmap::testing

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/core/base.hpp>

namespace hazmap::testing {

/// The whole content of a file, bytes as they are ("" if it cannot be opened).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

/// Writes `text` to `path` byte for byte, replacing the file.
inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

/// `text` with its first `from` replaced by `to`; a test failure when `from` is absent.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// Every file under `root` with its bytes (folders as "<folder>"; empty for a missing
/// root): compare two to tell that a command left an output folder exactly as it was.
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& root) {
  std::map<std::string, std::string> files;
  if (!std::filesystem::exists(root)) return files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root))
    files[std::filesystem::relative(e.path(), root).string()] =
        e.is_regular_file() ? read_text(e.path()) : std::string("<folder>");
  return files;
}

/// What a shell command printed (as its own redirections direct) and its exit code.
struct CommandResult {
  int exit_code = -1;
  std::string output;
};

/// Runs `command` through the shell and captures its standard output.
inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

#ifdef HAZMAP_CLI
/// `hazmap ARGS` through the shell: its stderr (stdout discarded) and exit code.
inline CommandResult run_hazmap(const std::string& args) {
  return run_command(std::string(HAZMAP_CLI) + " " + args + " 2>&1 1>/dev/null");
}
#endif

/// An earlier run's OUT (summary.json, run.log and one frame's layer, all small text)
/// for tests that check a refused command leaves OUT exactly as it was.
inline void write_previous_out(const std::filesystem::path& out) {
  std::filesystem::create_directories(out / "frames/000000");
  write_text(out / "summary.json", "{\"finished\": true, \"previous\": 1}\n");
  write_text(out / "run.log", "previous run\n");
  write_text(out / "frames/000000/L0_height.jdem", "previous\n");
}

/// A config for write_tiny_sequence's 64 x 48 pairs: 16 disparities, one 16-cell layer.
inline const char* const kTinyConfig =
    "stereo: {num_disparities: 16, block_size: 5, z_max: 10}\n"
    "map:\n  layers:\n    - {resolution: 0.01, size: 16, rule: kalman, hazard: {kernel: 3}}\n";

/// Writes a tiny but complete sequence (random-texture 64 x 48 PNG pairs of level ground
/// seen from above, a rectified calibration and straight-line poses) for input-handling
/// tests.
inline void write_tiny_sequence(const std::filesystem::path& dir, int frames) {
  std::filesystem::create_directories(dir / "left");
  std::filesystem::create_directories(dir / "right");
  cv::RNG rng(12345);
  std::ofstream poses(dir / "poses.txt");
  poses << "# name t x y z qx qy qz qw\n";
  for (int i = 0; i < frames; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d", i);
    cv::Mat img(48, 64, CV_8UC1);
    rng.fill(img, cv::RNG::UNIFORM, 0, 255);
    cv::imwrite((dir / "left" / (std::string(name) + ".png")).string(), img);
    // The right view sees the same texture 4 px to the left: disparity 4 everywhere.
    cv::Mat right;
    cv::copyMakeBorder(img.colRange(4, img.cols), right, 0, 0, 0, 4, cv::BORDER_REPLICATE);
    cv::imwrite((dir / "right" / (std::string(name) + ".png")).string(), right);
    poses << name << " " << i << " " << 0.04 * i << " 0 0 0 0 0 1\n";
  }
  std::ofstream calib(dir / "calibration.yaml");
  calib << "image_width: 64\nimage_height: 48\nrectified: true\n"
           "left:  {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\n"
           "right: {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\n"
           "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-0.05, 0, 0]\n"
           // Looking straight down from 0.625 m: the constant disparity 4 is level ground
           // at z_B = 0 (f B / d = 50 * 0.05 / 4), as a rover's camera would see it.
           "T_body_left: {translation: [0, 0.025, 0.625], "
           "quaternion: [0.70710678118654752, -0.70710678118654752, 0, 0]}\n";
}

}  // namespace hazmap::testing
