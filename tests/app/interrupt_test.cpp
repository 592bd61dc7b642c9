// SIGTERM / SIGINT during `hazmap run` (issue 20): the real binary, signalled once its
// first frame folder appears, stops after the frame in flight with every frame folder
// complete, no hidden temporary left, one line naming the frame, exit 128 + signal.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <set>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr int kFrames = 400;  ///< far more than the run gets through before the signal
constexpr auto kPoll = std::chrono::milliseconds(2);
constexpr auto kGiveUp = std::chrono::seconds(120);

/// Starts `hazmap run` on `dir`/seq with stderr into `dir`/stderr.txt; returns its pid.
pid_t start_run(const testing::TempDir& dir) {
  const std::string config = (testing::source_dir() / "config/default.yaml").string();
  const std::string seq = (dir / "seq").string(), out = (dir / "out").string();
  const std::string err = (dir / "stderr.txt").string();
  // Big enough maps (PNG rendering of a 256-cell layer) that each frame takes a while.
  std::vector<std::string> args = {HAZMAP_CLI, "run", "--config", config, "--sequence", seq,
                                   "--out", out, "--quiet",
                                   "--set", "stereo.num_disparities=16",
                                   "--set", "stereo.block_size=5",
                                   "--set", "map.layers.0.size=256",
                                   "--set", "map.layers.0.hazard.kernel=3",
                                   "--set", "output.every_n=3",
                                   "--set", "output.format=both"};
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 2);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

void check_stopped_cleanly(int signal_number) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", kFrames);
  const pid_t pid = start_run(dir);
  ASSERT_GT(pid, 0);
  const auto first = dir / "out/frames/000000";
  const auto start = std::chrono::steady_clock::now();
  while (!std::filesystem::exists(first) && std::chrono::steady_clock::now() - start < kGiveUp)
    std::this_thread::sleep_for(kPoll);
  ASSERT_TRUE(std::filesystem::exists(first)) << "no frame folder appeared";
  kill(pid, signal_number);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed instead of stopping";
  EXPECT_EQ(WEXITSTATUS(status), 128 + signal_number);

  const std::string err = testing::read_text(dir / "stderr.txt");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  const std::string name = signal_number == SIGINT ? "SIGINT" : "SIGTERM";
  const auto at = err.find("stopped by " + name + " after frame ");
  ASSERT_NE(at, std::string::npos) << err;
  const std::string last = err.substr(at + ("stopped by " + name + " after frame ").size(), 6);

  // The frame it names was written although every_n = 3, like a whole run's last frame.
  EXPECT_TRUE(std::filesystem::is_directory(dir / "out/frames" / last)) << err;
  std::set<std::string> expected;
  for (const auto& e : std::filesystem::directory_iterator(first))
    expected.insert(e.path().filename().string());
  EXPECT_EQ(expected.size(), 18u);  // L0: 2 PNGs + 3 grids x 2 formats; 2 PNGs + 4 grids x 2
  int folders = 0;
  for (const auto& folder : std::filesystem::directory_iterator(dir / "out/frames")) {
    const std::string fname = folder.path().filename().string();
    ASSERT_NE(fname.front(), '.') << "staging folder left: " << fname;
    EXPECT_LT(fname, std::string("000") + std::to_string(kFrames - 1)) << "ran to the end";
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(folder.path()))
      names.insert(e.path().filename().string());
    EXPECT_EQ(names, expected) << fname;
    ++folders;
  }
  EXPECT_GE(folders, 1);
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir / "out")) {
    const std::string fname = e.path().filename().string();
    EXPECT_NE(fname.front(), '.') << e.path();
    EXPECT_EQ(fname.find(".tmp"), std::string::npos) << e.path();
  }
  const std::string summary = testing::read_text(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"finished\": false"), std::string::npos);
  EXPECT_NE(summary.find("\"stopped_after_frame\": \"" + last + "\""), std::string::npos) << summary;
}

TEST(Interrupt, SigtermStopsAfterTheFrameInFlightAndLeavesCompleteFolders) {
  check_stopped_cleanly(SIGTERM);
}

TEST(Interrupt, SigintExitsWith130) { check_stopped_cleanly(SIGINT); }

}  // namespace
}  // namespace hazmap
