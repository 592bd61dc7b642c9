// Sweep summaries from hand-written per-run summaries: tables, detectable sizes, claims.

#include "hazmap/eval/sweep_summary.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap::eval {
namespace {

using hazmap::testing::TempDir;

const char* kHeader =
    "frames,layer,resolution_m,rule,h_min_m,extent_m2,known_m2,unknown_fraction,height_rms_m,"
    "height_samples,gt_hazard_m2,gt_hazard_known_m2,missed_m2,missed_fraction,missed_of_hazard,"
    "false_alarm_m2,false_alarm_fraction,variance_violation\n";

// One evaluated run: per layer (name, resolution, rule, h_min, rms, missed share).
struct FakeLayer {
  std::string name;
  double res, h_min, rms, missed_share;
  std::string rule = "ccm";
};

void write_run(const std::filesystem::path& run, const std::vector<FakeLayer>& layers) {
  std::filesystem::create_directories(run / "eval");
  std::ofstream out(run / "eval" / "summary.csv");
  out << kHeader;
  for (const FakeLayer& l : layers) {
    const double hazard_known = 0.1, known = 2.0;
    out << "4," << l.name << ',' << l.res << ',' << l.rule << ',' << l.h_min << ",4," << known
        << ",0.5," << l.rms << ",1000,0.12," << hazard_known << ',' << l.missed_share * hazard_known
        << ",0," << l.missed_share << ",0.02,0.01,0.1\n";
  }
}

TEST(SweepSummary, TablesHeatMapsAndDetectableSizes) {
  TempDir dir;
  std::ofstream tsv(dir / "sweep.tsv");
  tsv << "experiment\tmap\tscenario\tradius_m\tdrift\trun_dir\n";
  // CCM: L0 finds 3 cm and up; L1 misses 3 cm, finds 6 cm and 12 cm.
  const double radii[] = {0.03, 0.06, 0.12};
  const double l1_missed[] = {0.9, 0.02, 0.0};
  for (int i = 0; i < 3; ++i) {
    const std::string run = "runs/ccm_" + std::to_string(i);
    write_run(dir / run, {{"L0", 0.04, 0.03, 0.004, 0.0}, {"L1", 0.08, 0.06, 0.006, l1_missed[i]}});
    tsv << "sizes\tthesis_ccm\trocks\t" << radii[i] << "\t-\t" << run << "\n";
  }
  // Craters: PWC 4 cm RMS 5 mm vs CCM 8 cm RMS 4 mm (claim met).
  write_run(dir / "runs/cr_pwc", {{"L0", 0.01, 0.025, 0.003, 0.0, "omg"},
                                  {"L1", 0.04, 0.073, 0.005, 0.0, "omg"}});
  write_run(dir / "runs/cr_ccm", {{"L0", 0.04, 0.03, 0.0035, 0.0}, {"L1", 0.08, 0.06, 0.004, 0.0}});
  tsv << "craters\tthesis_pwc\tcraters\t-\t-\truns/cr_pwc\n";
  tsv << "craters\tthesis_ccm\tcraters\t-\t-\truns/cr_ccm\n";
  tsv << "drift\tthesis_ccm\tsine\t-\t0.1\truns/missing\n";  // a failed job
  tsv.close();

  const std::filesystem::path out = dir / "summary";
  EXPECT_EQ(summarize_sweep(dir.path(), out), 5);
  for (const char* f : {"missed_by_size_thesis_ccm.csv", "missed_by_size_thesis_ccm.png",
                        "false_alarm_by_size_thesis_ccm.png", "detectable_size.csv",
                        "craters_rms.csv", "craters_rms.png", "tables.md", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  const std::string missed_csv = testing::read_text(out / "missed_by_size_thesis_ccm.csv");
  EXPECT_NE(missed_csv.find("L1 8 cm,6,0.90,0.02,0.00"), std::string::npos) << missed_csv;
  const std::string detect = testing::read_text(out / "detectable_size.csv");
  EXPECT_NE(detect.find("thesis_ccm,L0 4 cm ccm,3,3"), std::string::npos) << detect;
  EXPECT_NE(detect.find("thesis_ccm,L1 8 cm ccm,6,6"), std::string::npos) << detect;
  const std::string md = testing::read_text(out / "tables.md");
  EXPECT_NE(md.find("| 4 cm thesis_pwc | 0.500 | 8 cm thesis_ccm | 0.400 | yes |"), std::string::npos)
      << md;
  const cv::Mat heat = cv::imread((out / "missed_by_size_thesis_ccm.png").string());
  ASSERT_FALSE(heat.empty());
  EXPECT_GT(heat.cols, 3 * 44);
  const std::string html = testing::read_text(out / "report.html");
  EXPECT_NE(html.find("missing"), std::string::npos);  // the failed job is listed
  EXPECT_NE(html.find("<a href=\"../runs/ccm_0/eval/report.html\">"), std::string::npos);
}

TEST(SweepSummary, RejectsAMalformedManifest) {
  TempDir dir;
  std::ofstream(dir / "sweep.tsv") << "experiment\tmap\n";
  EXPECT_THROW(summarize_sweep(dir.path(), dir / "out"), Error);
}

}  // namespace
}  // namespace hazmap::eval
