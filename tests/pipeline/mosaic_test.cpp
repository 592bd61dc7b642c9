// The --mosaic image (issue 35): every panel the same pixel size, whatever its grid's
// cell count; each grid drawn with whole pixels per cell (nearest neighbour, no blur)
// as large as fits the common map side, centred; the mosaic tiles the panels on one
// grid, read back from a written PNG.

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/images.hpp"
#include "hazmap/pipeline/output_writer.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

DenseGrid random_grid(int n, double resolution, unsigned seed, bool classes) {
  DenseGrid g;
  g.reset(n, n, resolution, 0.0, 0.0, 0.0f);
  for (float& v : g.values) {
    seed = seed * 1103515245u + 12345u;
    const unsigned r = (seed >> 16) & 0x7fffu;
    v = classes ? static_cast<float>(r % 3u) : static_cast<float>(r) * 1e-5f;
  }
  return g;
}

/// Layers of 42, 32 and 28 cells (thesis_ccm.yaml's sizes) and 200-cell fused and
/// footprint maps; the robot far outside every map.
FrameOutputs uneven_frame() {
  FrameOutputs f;
  f.frame_name = "000007";
  f.robot_x_m = f.robot_y_m = 1000.0;
  const int sizes[] = {42, 32, 28};
  const double res[] = {0.04, 0.08, 0.16};
  for (int i = 0; i < 3; ++i) {
    LayerOutputs l;
    l.hazard = random_grid(sizes[i], res[i], 11u + i, true);
    l.height = random_grid(sizes[i], res[i], 23u + i, false);
    l.variance = l.height;
    l.resolution_m = res[i];
    l.rule = RuleKind::ccm;
    f.layers.push_back(l);
  }
  f.fused = random_grid(200, 0.01, 5u, true);
  f.footprint = random_grid(200, 0.01, 7u, true);
  return f;
}

bool is_palette(const cv::Vec3b& p) {
  return p == cv::Vec3b(90, 90, 90) || p == cv::Vec3b(70, 170, 40) || p == cv::Vec3b(40, 40, 220);
}

/// The bounding box of the pixels of `panel`'s top-left `side` square that `keep` accepts,
/// the axis glyph's box left out.
template <class Keep>
cv::Rect drawn_box(const cv::Mat& panel, int side, Keep keep) {
  const cv::Rect glyph = axis_glyph_box({side, side});
  int x0 = side, y0 = side, x1 = -1, y1 = -1;
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c)
      if (!glyph.contains({c, r}) && keep(panel.at<cv::Vec3b>(r, c))) {
        x0 = std::min(x0, c), x1 = std::max(x1, c);
        y0 = std::min(y0, r), y1 = std::max(y1, r);
      }
  return x1 < 0 ? cv::Rect() : cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
}

TEST(Mosaic, EveryPanelHasOneSizeAndEachGridFillsTheCommonMapSide) {
  const FrameOutputs frame = uneven_frame();
  const std::vector<cv::Mat> panels = render_mosaic_panels(frame, 2.0);
  ASSERT_EQ(panels.size(), 8u);  // 3 layers x (hazard, height), fused, footprint
  for (const cv::Mat& p : panels) EXPECT_EQ(p.size(), panels.front().size());

  // The common map side, worked out here: 320 px at least, whole pixels per cell, so a
  // grid of n cells needs n * ceil(320 / n); the largest need wins (the 200-cell maps).
  int side = 0;
  for (int n : {42, 32, 28, 200}) side = std::max(side, n * ((320 + n - 1) / n));
  ASSERT_EQ(side, 400);
  const cv::Vec3b background(30, 30, 30);
  // Column by column: the grid of n cells drawn k = floor(side / n) px a cell, centred.
  const int cells[] = {42, 42, 32, 32, 28, 28, 200, 200};
  for (size_t i = 0; i < panels.size(); ++i) {
    const int n = cells[i], k = side / n, offset = (side - n * k) / 2;
    const bool height_panel = i < 6 && i % 2 == 1;
    const cv::Rect drawn =
        height_panel ? drawn_box(panels[i], side, [&](const cv::Vec3b& p) { return p != background; })
                     : drawn_box(panels[i], side, is_palette);
    EXPECT_EQ(drawn, cv::Rect(offset, offset, n * k, n * k)) << "panel " << i << ", " << n << " cells";
    // Whole pixels per cell: a hazard panel's pixel is its cell's class colour.
    if (!height_panel && i < 6) {
      const DenseGrid& g = frame.layers[i / 2].hazard;
      const int r = offset + k * 5 + k / 2, c = offset + k * 9 + k - 1;  // cell (5, 9)
      const float v = g.values[5 * static_cast<size_t>(n) + 9];
      const cv::Vec3b want = v == 2.0f ? cv::Vec3b(40, 40, 220)
                             : v == 1.0f ? cv::Vec3b(70, 170, 40) : cv::Vec3b(90, 90, 90);
      EXPECT_EQ(panels[i].at<cv::Vec3b>(r, c), want) << "panel " << i;
    }
  }

  // The written mosaic tiles them on one grid: an 8 px gap around panels, a 32 px title.
  testing::TempDir dir;
  write_png(dir / "mosaic.png", render_mosaic(frame, 2.0));
  const cv::Mat mosaic = cv::imread((dir / "mosaic.png").string(), cv::IMREAD_COLOR);
  const int w = panels.front().cols, h = panels.front().rows;
  ASSERT_EQ(mosaic.cols, 8 + 4 * (w + 8));
  ASSERT_EQ(mosaic.rows, 32 + 2 * (h + 8));
  for (size_t i = 0; i < panels.size(); ++i) {
    const cv::Rect at(8 + static_cast<int>(i / 2) * (w + 8), 32 + static_cast<int>(i % 2) * (h + 8), w, h);
    cv::Mat diff;
    cv::absdiff(mosaic(at), panels[i], diff);
    EXPECT_EQ(cv::countNonZero(diff.reshape(1)), 0) << "panel " << i;
  }
}

}  // namespace
}  // namespace hazmap
