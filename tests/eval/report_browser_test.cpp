// The run report opens in a real browser: headless Chromium renders report.html from
// file://, its DOM holds the summary table with the evaluation's numbers, the frame
// viewer's script ran, and the screenshot is not blank.
// Needs Debian's `chromium` (eval/browser.hpp).

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/browser.hpp"
#include "eval/oracle_run.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "test_support.hpp"

namespace hazmap::eval {
namespace {

using hazmap::testing::chromium_command;
using hazmap::testing::TempDir;

TEST(ReportBrowser, ChromiumShowsTheSummaryTable) {
  if (hazmap::testing::browser_tests_skipped()) GTEST_SKIP() << "HAZMAP_SKIP_BROWSER=1";
  ASSERT_TRUE(hazmap::testing::chromium_found()) << hazmap::testing::kNoChromium;

  TempDir dir;
  hazmap::testing::TestWorld w;
  w.rocks = {{0.6, 0.3, 0.10}, {1.3, -0.35, 0.12}};
  const Config config = hazmap::testing::oracle_config();
  const std::vector<std::string> frames = {"000000", "000001", "000002"};
  std::vector<hazmap::testing::OracleLayer> layers = {
      hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96, 0.0, 0.03, true, 1e-4),
      hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 1e-4)};
  hazmap::testing::write_ground_truth(dir / "seq", w);
  hazmap::testing::write_poses(dir / "seq" / "poses.txt", frames, {{0, 0}, {0.04, 0}, {0.08, 0}});
  hazmap::testing::write_oracle_run(dir / "run", config, frames, {layers, layers, layers});
  EvaluationOptions o;
  o.run_dir = dir / "run";
  o.sequence_dir = dir / "seq";
  const RunEvaluation ev = evaluate_run(o);
  const std::filesystem::path report = dir / "run" / "eval" / "report.html";
  ASSERT_TRUE(std::filesystem::exists(report));

  const std::string url = "file://" + std::filesystem::absolute(report).string();
  const std::filesystem::path dom = dir / "dom.html", shot = dir / "shot.png";
  ASSERT_EQ(std::system((chromium_command(dir / "profile_dom") + " --dump-dom '" + url + "' > " +
                         dom.string() + " 2> " + (dir / "dom.err").string())
                            .c_str()),
            0)
      << testing::read_text(dir / "dom.err");
  ASSERT_EQ(std::system((chromium_command(dir / "profile_shot") + " --window-size=1200,900 "
                         "--screenshot=" + shot.string() + " '" + url + "' > /dev/null 2> " +
                         (dir / "shot.err").string())
                            .c_str()),
            0)
      << testing::read_text(dir / "shot.err");

  const std::string html = testing::read_text(dom);
  EXPECT_NE(html.find("<table id=\"summary\">"), std::string::npos) << html.substr(0, 2000);
  // The Kalman layer's height RMS as the table prints it (cm, 3 decimals).
  char rms[32];
  std::snprintf(rms, sizeof rms, "<td>%.3f</td>", derive_metrics(ev.pooled[1]).height_rms_m * 100);
  EXPECT_NE(html.find(rms), std::string::npos) << "no cell " << rms;
  EXPECT_NE(html.find("<td>kalman</td>"), std::string::npos);
  // The viewer script ran: it labels the last frame.
  EXPECT_NE(html.find("frame 000002  (3 / 3)"), std::string::npos);

  const cv::Mat png = cv::imread(shot.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(png.empty()) << "no screenshot at " << shot;
  EXPECT_EQ(png.cols, 1200);
  EXPECT_EQ(png.rows, 900);
  // Not blank: white page with dark text and table borders.
  cv::Mat grey;
  cv::cvtColor(png, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev);
  EXPECT_GT(stddev[0], 15.0) << "screenshot looks blank";
  EXPECT_GT(cv::countNonZero(grey < 100), 2000) << "too little dark (text) in the screenshot";
}

}  // namespace
}  // namespace hazmap::eval
