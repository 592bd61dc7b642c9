// `hazmap view` from the command line: the page where asked, and one clear line with a
// non-zero exit on a bad command line or a folder that is not a complete run.

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "eval/oracle_run.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using hazmap::testing::TempDir;

int run_cli(const std::string& args, const fs::path& out, const fs::path& err) {
  const int status = std::system(
      (std::string(HAZMAP_CLI) + " " + args + " > " + out.string() + " 2> " + err.string()).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void write_run(const fs::path& run) {
  hazmap::testing::TestWorld w;
  w.rocks = {{1.0, 0.3, 0.1}};
  hazmap::testing::write_oracle_run(
      run, hazmap::testing::oracle_config(), {"000000"},
      {{hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
        hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)}});
}

TEST(ViewCli, WritesThePageInTheRunOrWhereAsked) {
  TempDir dir;
  write_run(dir / "run");
  ASSERT_EQ(run_cli("view " + (dir / "run").string(), dir / "out.txt", dir / "err.txt"), 0)
      << testing::read_text(dir / "err.txt");
  EXPECT_TRUE(fs::exists(dir / "run" / "view.html"));
  const std::string said = testing::read_text(dir / "out.txt");
  EXPECT_NE(said.find("wrote " + (dir / "run" / "view.html").string() + ": "), std::string::npos)
      << said;
  EXPECT_NE(said.find("1 frames"), std::string::npos) << said;
  ASSERT_EQ(run_cli("view --out " + (dir / "elsewhere.html").string() + " " +
                        (dir / "run").string(),
                    dir / "out.txt", dir / "err.txt"),
            0)
      << testing::read_text(dir / "err.txt");
  EXPECT_TRUE(fs::exists(dir / "elsewhere.html"));

  ASSERT_EQ(run_cli("view --help", dir / "help.txt", dir / "err.txt"), 0);
  EXPECT_NE(testing::read_text(dir / "help.txt").find("usage: hazmap view RUN [--out FILE]"),
            std::string::npos);
  ASSERT_EQ(run_cli("--help", dir / "help.txt", dir / "err.txt"), 0);
  EXPECT_NE(testing::read_text(dir / "help.txt").find("hazmap view "), std::string::npos);
}

TEST(ViewCli, BadInputIsOneLineAndANonZeroExit) {
  TempDir dir;
  write_run(dir / "run");
  // The command line: exit 2.
  for (const std::string args : {"view", "view a b", "view --frames 3 a", "view --out"}) {
    EXPECT_EQ(run_cli(args, dir / "out.txt", dir / "err.txt"), 2) << args;
    EXPECT_NE(testing::read_text(dir / "err.txt").find("(see hazmap view --help)"), std::string::npos)
        << args;
  }
  // Not a run, or a damaged one: exit 1, one line naming the file, no page.
  fs::create_directories(dir / "notarun");
  std::ofstream(dir / "run" / "frames" / "000000" / "L1_hazard.jdem", std::ios::trunc)
      << "JDEM 1\nrows: 2\n";
  for (const fs::path& run : {dir / "notarun", dir / "run"}) {
    EXPECT_EQ(run_cli("view " + run.string(), dir / "out.txt", dir / "err.txt"), 1) << run;
    const std::string err = testing::read_text(dir / "err.txt");
    EXPECT_EQ(err.rfind("hazmap: error: ", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(run == dir / "run" ? "L1_hazard.jdem" : "summary.json"), std::string::npos)
        << err;
    EXPECT_FALSE(fs::exists(run / "view.html")) << run;
  }
}

}  // namespace
}  // namespace hazmap
