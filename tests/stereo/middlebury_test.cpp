// Disparity quality on real Middlebury pairs with dense ground truth (shared data, see
// ../shared/data/middlebury/README_SOURCE.txt). The matchers run with the shipped
// settings (config/default.yaml; only the disparity range widened to cover each scene)
// on the colour images as they come, through the same grey conversion as the pipeline.
// Figures must not get worse than those recorded in docs/stereo.md ("Stereo front end").

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/stereo/disparity.hpp"
#include "hazmap/camera/grey_pair.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr double kBadThresholdPx = 2.0;  // a pixel is bad when |d - d_gt| > 2 px

std::filesystem::path middlebury_dir() {
  return testing::source_dir() / "../shared/data/middlebury";
}

/// PFM (Portable Float Map) grey image: header "Pf", "W H", scale (< 0: little endian),
/// then float rows stored bottom to top. Returns CV_32F top row first; the scale's
/// magnitude is not applied (Middlebury stores disparities in pixels).
cv::Mat read_pfm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0;
  double scale = 0;
  in >> magic >> w >> h >> scale;
  in.get();  // the single whitespace byte before the data
  if (!in || magic != "Pf" || w <= 0 || h <= 0 || scale >= 0)
    throw std::runtime_error(path.string() + ": not a little-endian grey PFM");
  cv::Mat out(h, w, CV_32F);
  for (int row = h - 1; row >= 0; --row)
    in.read(reinterpret_cast<char*>(out.ptr<float>(row)), static_cast<std::streamsize>(w) * 4);
  if (!in) throw std::runtime_error(path.string() + ": truncated PFM");
  return out;
}

struct Quality {
  double bad_rate = 0;  ///< over pixels where both the estimate and the GT exist
  double density = 0;   ///< estimated pixels / GT pixels
};

Quality evaluate(const cv::Mat& disparity_x16, int invalid_below, const cv::Mat& gt_px) {
  size_t gt_pixels = 0, both = 0, bad = 0;
  for (int v = 0; v < gt_px.rows; ++v)
    for (int u = 0; u < gt_px.cols; ++u) {
      const float g = gt_px.at<float>(v, u);
      if (!std::isfinite(g) || g <= 0) continue;
      ++gt_pixels;
      const int d16 = disparity_x16.at<int16_t>(v, u);
      if (d16 <= invalid_below) continue;
      ++both;
      if (std::abs(d16 / 16.0 - g) > kBadThresholdPx) ++bad;
    }
  return {static_cast<double>(bad) / static_cast<double>(both),
          static_cast<double>(both) / static_cast<double>(gt_pixels)};
}

struct SceneCase {
  const char* scene;
  const char* matcher;
  double max_bad_rate;  ///< docs/stereo.md figure (rounded up)
  double min_density;   ///< docs/stereo.md figure (rounded down)
};

void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.scene << " " << c.matcher; }

class Middlebury : public ::testing::TestWithParam<SceneCase> {};

TEST_P(Middlebury, NoWorseThanTheRecordedFigures) {
  const SceneCase sc = GetParam();
  if (!std::filesystem::is_directory(middlebury_dir()))
    GTEST_SKIP() << middlebury_dir().string() << " is absent (shared real data)";
  const bool aloe = std::strcmp(sc.scene, "aloe") == 0;
  const std::filesystem::path dir = middlebury_dir() / sc.scene;
  const cv::Mat left = read_image(dir / (aloe ? "aloeL.jpg" : "im0.png"));
  const cv::Mat right = read_image(dir / (aloe ? "aloeR.jpg" : "im1.png"));
  cv::Mat gt;
  if (aloe) {
    read_image(dir / "aloeGT.png").convertTo(gt, CV_32F);  // px, 0 = unknown
  } else {
    gt = read_pfm(dir / "disp0GT.pfm");  // px, inf = unknown
    // OpenCV's own PFM reader divides by the header's scale (here 1/255), so it would
    // give 255 x the disparity; its row order (top first) must match ours.
    const cv::Mat by_opencv = cv::imread((dir / "disp0GT.pfm").string(), cv::IMREAD_UNCHANGED);
    if (!by_opencv.empty()) {
      const cv::Mat known = gt < 1e6f;
      EXPECT_LT(cv::norm(gt * 255.0, by_opencv, cv::NORM_INF, known), 0.05 * 255.0);
    }
  }
  ASSERT_EQ(gt.size(), left.size());
  double gt_max = 0;
  cv::minMaxLoc(gt, nullptr, &gt_max, nullptr, nullptr, gt < 1e6f);
  // Scale check (README_SOURCE): aloe at most 211 px, teddyH 30..106 px.
  EXPECT_NEAR(gt_max, aloe ? 211 : 106, 2.0);

  // The shipped settings, the range widened to the scene's largest disparity.
  const Config config = load_config(testing::source_dir() / "config/default.yaml",
                                     {std::string("stereo.matcher=") + sc.matcher,
                                      aloe ? "stereo.num_disparities=224"
                                           : "stereo.num_disparities=112"});
  GreyPairConverter grey(config.stereo.input_bits);
  cv::Mat l8, r8, disparity;
  grey.convert(left, right, l8, r8);
  DisparityMatcher matcher(config.stereo);
  matcher.compute(l8, r8, disparity);
  const Quality q = evaluate(disparity, matcher.invalid_below(), gt);
  std::printf("[ measured ] %s %s: bad pixels (> 2 px) %.2f %%, density %.2f %%\n", sc.scene,
              sc.matcher, 100 * q.bad_rate, 100 * q.density);
  EXPECT_LE(q.bad_rate, sc.max_bad_rate);
  EXPECT_GE(q.density, sc.min_density);
}

TEST(MiddleburyKnobs, LeftRightCheckAndSpeckleFilterRemoveBadMatches) {
  // On teddyH with StereoBM: each filter removes more bad than good pixels, i.e. the
  // bad-pixel rate falls and so does the density.
  if (!std::filesystem::is_directory(middlebury_dir()))
    GTEST_SKIP() << middlebury_dir().string() << " is absent (shared real data)";
  const std::filesystem::path dir = middlebury_dir() / "teddyH";
  const cv::Mat gt = read_pfm(dir / "disp0GT.pfm");
  GreyPairConverter grey;
  cv::Mat l8, r8, disparity;
  grey.convert(read_image(dir / "im0.png"), read_image(dir / "im1.png"), l8, r8);
  auto run = [&](int disp12_max_diff, int speckle_window) {
    StereoConfig s;
    s.num_disparities = 112;
    s.disp12_max_diff = disp12_max_diff;
    s.speckle_window = speckle_window;
    DisparityMatcher matcher(s);
    matcher.compute(l8, r8, disparity);
    return evaluate(disparity, matcher.invalid_below(), gt);
  };
  const Quality raw = run(-1, 0), lr = run(1, 0), speckle = run(-1, 100);
  EXPECT_LT(lr.bad_rate, raw.bad_rate);
  EXPECT_LT(lr.density, raw.density);
  EXPECT_LT(speckle.bad_rate, raw.bad_rate);
  EXPECT_LT(speckle.density, raw.density);
  std::printf("[ measured ] teddyH bm: no filter %.2f %% bad / %.2f %% dense; LR check %.2f / "
              "%.2f; speckle filter %.2f / %.2f\n",
              100 * raw.bad_rate, 100 * raw.density, 100 * lr.bad_rate, 100 * lr.density,
              100 * speckle.bad_rate, 100 * speckle.density);
}

INSTANTIATE_TEST_SUITE_P(Scenes, Middlebury,
                         ::testing::Values(SceneCase{"aloe", "bm", 0.026, 0.758},
                                           SceneCase{"aloe", "sgbm", 0.041, 0.834},
                                           SceneCase{"teddyH", "bm", 0.061, 0.768},
                                           SceneCase{"teddyH", "sgbm", 0.068, 0.846}));

}  // namespace
}  // namespace hazmap
