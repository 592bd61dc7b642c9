// `hazmap evaluate` from the command line: outputs, and one clear line on bad input.

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "eval/oracle_run.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

using hazmap::testing::TempDir;

int run_cli(const std::string& args, const std::filesystem::path& err) {
  const int status = std::system((std::string(HAZMAP_CLI) + " " + args + " > /dev/null 2> " +
                                  err.string())
                                     .c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(EvaluateCli, WritesItsOutputsAndSummarisesASweep) {
  TempDir dir;
  hazmap::testing::TestWorld w;
  w.rocks = {{1.0, 0.3, 0.1}};
  const auto layers = std::vector<hazmap::testing::OracleLayer>{
      hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
      hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)};
  hazmap::testing::write_ground_truth(dir / "seq", w);
  hazmap::testing::write_poses(dir / "seq" / "poses.txt", {"000000"}, {{0.0, 0.0}});
  hazmap::testing::write_oracle_run(dir / "runs" / "a", hazmap::testing::oracle_config(),
                                    {"000000"}, {layers});
  ASSERT_EQ(run_cli("evaluate --run " + (dir / "runs" / "a").string() + " --sequence " +
                        (dir / "seq").string() + " --error-maps all --quiet",
                    dir / "err.txt"),
            0)
      << testing::read_text(dir / "err.txt");
  EXPECT_TRUE(std::filesystem::exists(dir / "runs" / "a" / "eval" / "errors_000000.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "runs" / "a" / "eval" / "metrics.json"));

  std::ofstream(dir / "sweep.tsv") << "experiment\tmap\tscenario\tradius_m\tdrift\trun_dir\n"
                                   << "sizes\toracle\trocks\t0.1\t-\truns/a\n";
  ASSERT_EQ(run_cli("evaluate --sweep " + dir.path().string() + " --quiet", dir / "err.txt"), 0)
      << testing::read_text(dir / "err.txt");
  const std::string md = testing::read_text(dir / "summary" / "tables.md");
  // Layer L0 (h_min 3 cm) flags the whole 10 cm rock: nothing missed.
  EXPECT_NE(md.find("| L0 4 cm | 3 | 0.00 |"), std::string::npos) << md;
}

TEST(EvaluateCli, NearAddsNearColumnsAndRejectsABadRadius) {
  TempDir dir;
  hazmap::testing::TestWorld w;
  w.rocks = {{1.0, 0.3, 0.1}};
  hazmap::testing::write_ground_truth(dir / "seq", w);
  hazmap::testing::write_poses(dir / "seq" / "poses.txt", {"000000"}, {{0.0, 0.0}});
  hazmap::testing::write_oracle_run(
      dir / "run", hazmap::testing::oracle_config(), {"000000"},
      {{hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
        hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)}});
  const std::string base =
      "evaluate --run " + (dir / "run").string() + " --sequence " + (dir / "seq").string();
  ASSERT_EQ(run_cli(base + " --near 1.5 --quiet", dir / "err.txt"), 0)
      << testing::read_text(dir / "err.txt");
  const std::string csv = testing::read_text(dir / "run" / "eval" / "summary.csv");
  EXPECT_NE(csv.find(",near_hazard_recall,"), std::string::npos) << csv;
  for (const char* bad : {"0", "-1", "x"}) {
    EXPECT_EQ(run_cli(base + " --near " + bad, dir / "err.txt"), 2) << bad;
    EXPECT_NE(testing::read_text(dir / "err.txt").find("--near"), std::string::npos) << bad;
  }
  ASSERT_EQ(std::system((std::string(HAZMAP_CLI) + " evaluate --help > " +
                         (dir / "help.txt").string())
                            .c_str()),
            0);
  const std::string help = testing::read_text(dir / "help.txt");
  for (const char* k : {"--near R", "near_hazard_recall", "footprint", "hazard recall"})
    EXPECT_NE(help.find(k), std::string::npos) << k;
}

TEST(EvaluateCli, BadInputGivesOneLineAndExitCode) {
  TempDir dir;
  EXPECT_EQ(run_cli("evaluate --run " + (dir / "nothing").string(), dir / "err.txt"), 2);
  EXPECT_NE(testing::read_text(dir / "err.txt").find("--sequence"), std::string::npos);
  EXPECT_EQ(run_cli("evaluate --run " + (dir / "nothing").string() + " --sequence " +
                        dir.path().string(),
                    dir / "err.txt"),
            1);
  const std::string err = testing::read_text(dir / "err.txt");
  EXPECT_NE(err.find("summary.json"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

}  // namespace
}  // namespace hazmap
