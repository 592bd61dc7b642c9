#pragma once
// Small, dependency-free charts drawn with OpenCV for the evaluation reports: line
// charts, annotated heat maps and colour-mapped grids with a colour bar. Drawn in C++ so
// that `hazmap evaluate` writes its own figures (no Python or plotting runtime on the
// rover's ground tools, and the figures come out byte-identical for the same input).
// Images are BGR, 8 bit.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap::eval {

struct Series {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;  ///< NaN breaks the line
};

struct LineChart {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
  bool log2_x = false;      ///< x axis in log2 (tick labels stay in data units)
  bool y_from_zero = true;  ///< include 0 in the y range
  /// x tick positions in data units; empty: chosen automatically.
  std::vector<double> x_ticks;
  int width_px = 560;
  int height_px = 320;
};

/// Renders a line chart with markers, axes, "nice" ticks and a legend. Series without
/// any finite point are listed in the legend as "(none)".
cv::Mat plot_lines(const LineChart& chart);

struct HeatMap {
  std::string title;
  std::string row_label;  ///< e.g. "layer"
  std::string col_label;  ///< e.g. "obstacle radius [cm]"
  std::vector<std::string> rows;
  std::vector<std::string> cols;
  std::vector<std::vector<double>> values;  ///< [row][col]; NaN = no data (grey, "-")
  double min_value = 0.0;
  double max_value = 1.0;
  std::string value_format = "%.2f";  ///< printf format for the cell text
  int cell_w_px = 44;
  int cell_h_px = 30;
};

/// Renders a heat map (low values light, high values dark red) with the value written in
/// each cell and a colour bar. Throws Error if values do not match rows x cols.
cv::Mat plot_heatmap(const HeatMap& map);

/// One colour-mapped grid: finite cells through the viridis colour map over
/// [min_value, max_value], NaN cells dark grey; each cell scale x scale pixels, with a
/// colour bar labelled `units` on the right and `title` on top.
cv::Mat render_scalar_grid(const DenseGrid& grid, double min_value, double max_value,
                           const std::string& title, const std::string& units, int scale);

/// Places images in a grid of `columns`, left to right then top to bottom, on a white
/// background with a small gap (images of different sizes are top-left aligned).
cv::Mat tile_images(const std::vector<cv::Mat>& images, int columns);

/// Writes `text` with the project's chart font at baseline (x, y).
void put_label(cv::Mat& image, const std::string& text, int x, int y, double scale = 0.45,
               const cv::Scalar& bgr = cv::Scalar(30, 30, 30), int thickness = 1);

}  // namespace hazmap::eval
