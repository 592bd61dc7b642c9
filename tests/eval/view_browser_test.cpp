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
#include <sstream>

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

/// The box in W [x0, y0, x1, y1] of the cells of `grid` that `known` accepts, from the
/// JDEM's layout (row 0 the largest y): empty if none.
std::vector<double> known_box(const JdemGrid& grid, bool (*known)(float)) {
  int r0 = grid.rows, r1 = -1, c0 = grid.cols, c1 = -1;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (known(grid.values[static_cast<size_t>(r * grid.cols + c)])) {
        r0 = std::min(r0, r);
        r1 = std::max(r1, r);
        c0 = std::min(c0, c);
        c1 = std::max(c1, c);
      }
  if (r1 < 0) return {};
  const double res = grid.resolution_m;
  const double x_min = grid.center_x_m - grid.cols * res / 2, y_max = grid.center_y_m + grid.rows * res / 2;
  return {x_min + c0 * res, y_max - (r1 + 1) * res, x_min + (c1 + 1) * res, y_max - r0 * res};
}

std::vector<double> numbers(const std::string& csv) {
  std::vector<double> out;
  std::istringstream in(csv);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::strtod(item.c_str(), nullptr));
  return out;
}

/// The part of W a map's canvas shows is the box `want` centred and fitted: centres equal,
/// the box inside the view, touching it on one axis.
void expect_fitted(const std::string& html, const std::string& id, const std::vector<double>& want) {
  const std::string section = "<section class=\"map\" id=\"map-" + id + "\"";
  const std::vector<double> view = numbers(attribute_after(html, section, "data-view-box"));
  ASSERT_EQ(view.size(), 4u) << id << ": " << attribute_after(html, section, "data-view-box");
  const double tol = 1e-9 * std::max(1.0, want[2] - want[0]);
  EXPECT_NEAR((view[0] + view[2]) / 2, (want[0] + want[2]) / 2, tol) << id;
  EXPECT_NEAR((view[1] + view[3]) / 2, (want[1] + want[3]) / 2, tol) << id;
  const double fx = (want[2] - want[0]) / (view[2] - view[0]), fy = (want[3] - want[1]) / (view[3] - view[1]);
  EXPECT_NEAR(std::max(fx, fy), 1.0, 1e-9) << id << ": the box fills the view on one axis";
  EXPECT_LE(std::min(fx, fy), 1.0 + 1e-9) << id;
}

/// A known-cell box grown as the page documents: by 5 % of its larger side each way, at
/// least two cells.
std::vector<double> with_margin(std::vector<double> box, double resolution_m) {
  const double pad = std::max(0.05 * std::max(box[2] - box[0], box[3] - box[1]), 2 * resolution_m);
  return {box[0] - pad, box[1] - pad, box[2] + pad, box[3] + pad};
}

TEST(ViewBrowser, MapsOpenFittedToTheirKnownCells) {
  if (hazmap::testing::browser_tests_skipped()) GTEST_SKIP() << "HAZMAP_SKIP_BROWSER=1";
  ASSERT_TRUE(hazmap::testing::chromium_found()) << hazmap::testing::kNoChromium;
  TempDir dir;
  const fs::path src = hazmap::testing::source_dir(), run = dir / "run";
  ASSERT_EQ(run_hazmap("run --config " + (src / "config" / "cadre_flight.yaml").string() +
                           " --sequence " + (src / "data" / "sample").string() + " --out " +
                           run.string() + " --frames 0:2 --quiet",
                       dir / "run.txt"),
            0)
      << testing::read_text(dir / "run.txt");
  // Frame 000000's footprint map knows nothing: its view falls back to the whole window.
  const fs::path frame0 = run / "frames" / "000000", frame1 = run / "frames" / "000001";
  JdemGrid blank = read_jdem(frame0 / "footprint_hazard.jdem");
  std::fill(blank.values.begin(), blank.values.end(), 0.0f);
  write_jdem(frame0 / "footprint_hazard.jdem", blank);
  ASSERT_EQ(run_hazmap("view " + run.string(), dir / "view.txt"), 0)
      << testing::read_text(dir / "view.txt");

  const auto hazard_known = [](float v) { return v == 1.0f || v == 2.0f; };
  const auto height_known = [](float v) { return !std::isnan(v); };
  for (const std::string q : {"hazard", "height"}) {
    const auto dom = hazmap::testing::run_chromium(dir.path(), "dom_" + q, "--dump-dom",
                                                   url_of(run / "view.html", "#frame=1&q=" + q));
    ASSERT_EQ(dom.exit_code, 0) << dom.log;
    EXPECT_EQ(hazmap::testing::console_messages(dom.log), std::vector<std::string>{});
    const std::string& html = dom.output;
    ASSERT_NE(html.find("data-shown-frame=\"000001\""), std::string::npos) << html.substr(0, 3000);
    for (const char* id : {"L0", "L1", "L2", "L3", "fused", "footprint"}) {
      const bool layer = id[0] == 'L';
      const std::string stem = std::string(id) + (layer && q == "height" ? "_height" : "_hazard");
      const JdemGrid grid = read_jdem(frame1 / (stem + ".jdem"));
      const std::vector<double> box = known_box(grid, layer && q == "height" ? +height_known : +hazard_known);
      ASSERT_EQ(box.size(), 4u) << id << " knows nothing in frame 000001";
      expect_fitted(html, id, with_margin(box, grid.resolution_m));
      EXPECT_EQ(attribute_after(html, std::string("id=\"map-") + id + "\"", "data-fitted"), "known") << id;
      if (std::string(id) == "L0") {  // the sample's data covers a part of the window
        const double width = grid.cols * grid.resolution_m;
        EXPECT_LT(box[2] - box[0], 0.8 * width) << q;
      }
    }
  }
  // Nothing known: the whole window, with the page's 2 % border.
  const auto dom = hazmap::testing::run_chromium(dir.path(), "dom_blank", "--dump-dom",
                                                 url_of(run / "view.html", "#frame=0"));
  ASSERT_EQ(dom.exit_code, 0) << dom.log;
  ASSERT_NE(dom.output.find("data-shown-frame=\"000000\""), std::string::npos);
  EXPECT_EQ(attribute_after(dom.output, "id=\"map-footprint\"", "data-fitted"), "grid");
  const double w = blank.cols * blank.resolution_m, h = blank.rows * blank.resolution_m;
  const double grow = 0.02 / 2;
  expect_fitted(dom.output, "footprint",
                {blank.center_x_m - w / 2 - grow * w, blank.center_y_m - h / 2 - grow * h,
                 blank.center_x_m + w / 2 + grow * w, blank.center_y_m + h / 2 + grow * h});
  // A view given in the address is kept, not fitted.
  const auto pinned = hazmap::testing::run_chromium(dir.path(), "dom_pinned", "--dump-dom",
                                                    url_of(run / "view.html", "#frame=1&view=0.5,0,2"));
  ASSERT_EQ(pinned.exit_code, 0) << pinned.log;
  EXPECT_EQ(attribute_after(pinned.output, "id=\"map-L0\"", "data-fitted"), "no");
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
