// hazmap view's page in a real browser: a run made by `hazmap run` on the embedded sample
// (and, for the evaluation, one on a simulated sequence with ground truth), its page opened
// from file:// in headless Chromium. The page loads with no console message, holds one
// canvas per layer plus the fused and footprint maps (and the metrics table when eval/
// exists), the script decoded the grids exactly (known-cell counts and the readout's
// values against the JDEMs), view.html#frame=N opens frame N, and two frames look
// different. Needs Debian's `chromium` (eval/browser.hpp).

#include <cstdio>
#include <cstdlib>
#include <regex>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/browser.hpp"
#include "hazmap/io/jdem.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using hazmap::testing::TempDir;

std::string cli(const std::string& args) { return std::string(HAZMAP_CLI) + " " + args; }

/// Runs a hazmap command; its messages go to `log`.
int run_hazmap(const std::string& args, const fs::path& log) {
  return std::system((cli(args) + " > " + log.string() + " 2>&1").c_str());
}

std::string url_of(const fs::path& page, const std::string& hash) {
  return "file://" + fs::absolute(page).string() + hash;
}

/// The `attribute` value of the first element after `from` that has it.
std::string attribute_after(const std::string& html, const std::string& from,
                            const std::string& attribute) {
  const size_t at = html.find(from);
  if (at == std::string::npos) return "<no " + from + ">";
  const std::string key = attribute + "=\"";
  const size_t a = html.find(key, at);
  if (a == std::string::npos) return "<no " + attribute + ">";
  return html.substr(a + key.size(), html.find('"', a + key.size()) - a - key.size());
}

size_t known_cells(const JdemGrid& hazard) {
  return static_cast<size_t>(std::count_if(hazard.values.begin(), hazard.values.end(),
                                           [](float v) { return v == 1.0f || v == 2.0f; }));
}

cv::Mat screenshot(const fs::path& dir, const std::string& name, const std::string& url) {
  const fs::path png = dir / (name + ".png");
  const auto r = hazmap::testing::run_chromium(
      dir, name, "--window-size=1400,1000 --screenshot=" + png.string(), url);
  EXPECT_EQ(r.exit_code, 0) << r.log;
  EXPECT_EQ(hazmap::testing::console_messages(r.log), std::vector<std::string>{}) << name;
  return cv::imread(png.string(), cv::IMREAD_COLOR);
}

TEST(ViewBrowser, SampleRunLoadsCleanlyShowsEveryMapAndReadsValuesExactly) {
  if (hazmap::testing::browser_tests_skipped()) GTEST_SKIP() << "HAZMAP_SKIP_BROWSER=1";
  ASSERT_TRUE(hazmap::testing::chromium_found()) << hazmap::testing::kNoChromium;
  TempDir dir;
  const fs::path src = hazmap::testing::source_dir(), run = dir / "run";
  ASSERT_EQ(run_hazmap("run --config " + (src / "config" / "cadre_flight.yaml").string() +
                           " --sequence " + (src / "data" / "sample").string() + " --out " +
                           run.string() + " --frames 0:4 --quiet",
                       dir / "run.txt"),
            0)
      << testing::read_text(dir / "run.txt");
  ASSERT_EQ(run_hazmap("view " + run.string(), dir / "view.txt"), 0)
      << testing::read_text(dir / "view.txt");
  const fs::path page = run / "view.html";

  // A known cell of the finest layer in frame 000001, to point at.
  const fs::path frame = run / "frames" / "000001";
  const JdemGrid height = read_jdem(frame / "L0_height.jdem");
  const JdemGrid variance = read_jdem(frame / "L0_variance.jdem");
  size_t cell = 0;
  while (cell < height.values.size() &&
         (std::isnan(height.values[cell]) || std::isnan(variance.values[cell])))
    ++cell;
  ASSERT_LT(cell, height.values.size()) << "L0 knows no height in frame 000001";
  const int row = static_cast<int>(cell) / height.cols, col = static_cast<int>(cell) % height.cols;
  char at[96];
  std::snprintf(at, sizeof at, "&at=%.17g,%.17g",
                height.center_x_m + (col + 0.5 - height.cols / 2.0) * height.resolution_m,
                height.center_y_m - (row + 0.5 - height.rows / 2.0) * height.resolution_m);

  const auto dom = hazmap::testing::run_chromium(dir.path(), "dom", "--dump-dom",
                                                 url_of(page, std::string("#frame=1") + at));
  ASSERT_EQ(dom.exit_code, 0) << dom.log;
  EXPECT_EQ(hazmap::testing::console_messages(dom.log), std::vector<std::string>{});
  const std::string& html = dom.output;
  EXPECT_NE(html.find("data-shown-frame=\"000001\""), std::string::npos) << html.substr(0, 3000);
  EXPECT_NE(html.find("frame 000001  (2 / 4)"), std::string::npos);
  EXPECT_EQ(html.find("id=\"status\" class=\"error\""), std::string::npos);
  // One canvas per map: the four layers of cadre_flight.yaml, fused, footprint.
  const std::regex canvas("<canvas class=\"view\"");
  EXPECT_EQ(std::distance(std::sregex_iterator(html.begin(), html.end(), canvas),
                          std::sregex_iterator()),
            6);
  const std::pair<const char*, const char*> maps[] = {
      {"L0", "L0_hazard.jdem"},       {"L1", "L1_hazard.jdem"},
      {"L2", "L2_hazard.jdem"},       {"L3", "L3_hazard.jdem"},
      {"fused", "fused_hazard.jdem"}, {"footprint", "footprint_hazard.jdem"}};
  for (const auto& [id, file] : maps) {
    const std::string section = std::string("<section class=\"map\" id=\"map-") + id + "\"";
    ASSERT_NE(html.find(section), std::string::npos) << id;
    // The page's count of known cells, from the grids it unpacked, is the file's.
    EXPECT_EQ(attribute_after(html, section, "data-known"),
              std::to_string(known_cells(read_jdem(frame / file))))
        << id;
  }
  EXPECT_EQ(html.find("<table id=\"metrics\">"), std::string::npos);  // no eval/
  // The readout under the pointer: the files' values exactly (shortest round-trip text of
  // each float, as the script prints it).
  const std::string l0_row = "<tr data-map=\"L0\"";
  EXPECT_EQ(std::strtof(attribute_after(html, l0_row + " title", "data-value").c_str(), nullptr),
            read_jdem(frame / "L0_hazard.jdem").values[cell]);
  const std::string h = attribute_after(html, "class=\"height\" data-value", "data-value");
  const std::string v = attribute_after(html, "class=\"sigma\" data-value", "data-value");
  EXPECT_EQ(static_cast<float>(std::strtod(h.c_str(), nullptr)), height.values[cell]) << h;
  EXPECT_EQ(std::strtod(h.c_str(), nullptr), static_cast<double>(height.values[cell])) << h;
  EXPECT_EQ(std::strtod(v.c_str(), nullptr), static_cast<double>(variance.values[cell])) << v;

  // Two frames, two pictures; neither blank.
  const cv::Mat first = screenshot(dir.path(), "frame0", url_of(page, "#frame=0&q=height"));
  const cv::Mat last = screenshot(dir.path(), "frame3", url_of(page, "#frame=000003&q=height"));
  ASSERT_FALSE(first.empty());
  ASSERT_FALSE(last.empty());
  EXPECT_EQ(first.size(), cv::Size(1400, 1000));
  cv::Mat grey, diff;
  for (const cv::Mat& shot : {first, last}) {
    cv::cvtColor(shot, grey, cv::COLOR_BGR2GRAY);
    cv::Scalar mean, stddev;
    cv::meanStdDev(grey, mean, stddev);
    EXPECT_GT(stddev[0], 15.0) << "screenshot looks blank";
  }
  cv::absdiff(first, last, diff);
  cv::cvtColor(diff, grey, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::countNonZero(grey > 40), 2000) << "frames 0 and 3 look the same";
}

TEST(ViewBrowser, EvaluatedRunShowsTheMetricsAndTheFramesErrorMap) {
  if (hazmap::testing::browser_tests_skipped()) GTEST_SKIP() << "HAZMAP_SKIP_BROWSER=1";
  ASSERT_TRUE(hazmap::testing::chromium_found()) << hazmap::testing::kNoChromium;
  TempDir dir;
  const fs::path src = hazmap::testing::source_dir(), seq = dir / "seq", run = dir / "run";
  // A small sequence with ground truth (one ray per pixel: rendering is the slow part).
  ASSERT_EQ(run_hazmap("simulate --scenario rocks --frames 3 --scale 0.4 --samples 1 "
                       "--ground-truth --gt-margin 1 --quiet --out " + seq.string(),
                       dir / "log.txt"),
            0)
      << testing::read_text(dir / "log.txt");
  ASSERT_EQ(run_hazmap("run --config " + (src / "config" / "cadre_flight.yaml").string() +
                           " --sequence " + seq.string() + " --out " + run.string() + " --quiet",
                       dir / "log.txt"),
            0)
      << testing::read_text(dir / "log.txt");
  ASSERT_EQ(run_hazmap("evaluate --run " + run.string() + " --sequence " + seq.string() +
                           " --error-maps all --quiet",
                       dir / "log.txt"),
            0)
      << testing::read_text(dir / "log.txt");
  ASSERT_EQ(run_hazmap("view " + run.string(), dir / "log.txt"), 0)
      << testing::read_text(dir / "log.txt");

  const auto dom = hazmap::testing::run_chromium(dir.path(), "dom", "--dump-dom",
                                                 url_of(run / "view.html", "#frame=1"));
  ASSERT_EQ(dom.exit_code, 0) << dom.log;
  EXPECT_EQ(hazmap::testing::console_messages(dom.log), std::vector<std::string>{});
  const std::string& html = dom.output;
  EXPECT_NE(html.find("data-shown-frame=\"000001\""), std::string::npos);
  EXPECT_NE(html.find("<table id=\"metrics\">"), std::string::npos);
  for (const char* layer : {"L0", "L1", "L2", "L3", "fused", "footprint"})
    EXPECT_NE(html.find(std::string("<tr><td>") + layer + "</td>"), std::string::npos) << layer;
  // The shown frame's error map is the one on view.
  EXPECT_NE(html.find("<figure class=\"error-map current\" data-frame=\"000001\">"),
            std::string::npos);
  EXPECT_NE(html.find("<figure class=\"error-map\" data-frame=\"000002\">"), std::string::npos);
  const std::regex plot("<canvas class=\"plot\"");
  const size_t eval_at = html.find("id=\"eval-plots\"");
  ASSERT_NE(eval_at, std::string::npos);
  EXPECT_EQ(std::distance(std::sregex_iterator(html.begin() + static_cast<std::ptrdiff_t>(eval_at),
                                               html.end(), plot),
                          std::sregex_iterator()),
            5);  // height RMS, recall, missed, false alarm, unknown
}

}  // namespace
}  // namespace hazmap
