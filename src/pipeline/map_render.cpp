#include "hazmap/pipeline/map_render.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace hazmap {
namespace {

const cv::Vec3b kUnknownBgr(90, 90, 90);
const cv::Vec3b kTraversableBgr(70, 170, 40);
const cv::Vec3b kHazardBgr(40, 40, 220);
const cv::Scalar kBackground(30, 30, 30);
const cv::Scalar kText(235, 235, 235);
const cv::Scalar kRobotRing(255, 255, 255);
const cv::Scalar kRobotEdge(0, 0, 0);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

/// Text size and stroke for an image `width_px` wide: about 60 characters across, never
/// smaller than OpenCV's font at 0.45 (legible on screen).
struct Ink {
  double scale;
  int thickness;
  int line_px;  ///< baseline-to-baseline
  int pad_px;
  static Ink for_width(int width_px) {
    Ink ink;
    ink.scale = std::max(0.45, width_px / 1100.0);
    ink.thickness = std::max(1, static_cast<int>(std::lround(ink.scale * 1.6)));
    int base = 0;
    const cv::Size s = cv::getTextSize("Hg", kFont, ink.scale, ink.thickness, &base);
    ink.line_px = s.height + base + static_cast<int>(std::lround(6 * ink.scale));
    ink.pad_px = std::max(4, ink.line_px / 3);
    return ink;
  }
  int text_width(std::string text) const {
    std::replace(text.begin(), text.end(), '\x01', ' ');
    int base = 0;
    return cv::getTextSize(text, kFont, scale, thickness, &base).width;
  }
  /// Appends `text` to `lines`, broken at spaces so that each line fits `max_px`.
  void wrap(const std::string& text, int max_px, std::vector<std::string>& lines) const {
    std::string line, word;
    auto flush_word = [&] {
      if (word.empty()) return;
      const std::string joined = line.empty() ? word : line + " " + word;
      if (!line.empty() && text_width(joined) > max_px) {
        lines.push_back(line);
        line = word;
      } else {
        line = joined;
      }
      word.clear();
    };
    for (char ch : text) {
      if (ch == ' ') flush_word();
      else word += ch;
    }
    flush_word();
    if (!line.empty()) lines.push_back(line);
  }
  void put(cv::Mat& image, std::string text, cv::Point at) const {
    std::replace(text.begin(), text.end(), '\x01', ' ');
    cv::putText(image, text, at, kFont, scale, kText, thickness, cv::LINE_AA);
  }
};

/// Cells per image pixel so that the map fits `max_size` (1 when it does, or no limit).
int cells_per_pixel(const DenseGrid& grid, int max_size) {
  const int side = std::max(grid.rows, grid.cols);
  return max_size > 0 && side > max_size ? (side + max_size - 1) / max_size : 1;
}

/// `grid` with f x f blocks merged: the largest hazard class (a hazard is never hidden),
/// or the mean of the known heights.
DenseGrid reduce(const DenseGrid& grid, int f, bool hazard_classes) {
  DenseGrid out;
  out.reset((grid.rows + f - 1) / f, (grid.cols + f - 1) / f, grid.resolution_m * f,
            grid.center_x_m, grid.center_y_m, NAN);
  for (int r = 0; r < out.rows; ++r)
    for (int c = 0; c < out.cols; ++c) {
      double sum = 0, best = -1;
      int n = 0;
      for (int i = r * f; i < std::min(grid.rows, (r + 1) * f); ++i)
        for (int j = c * f; j < std::min(grid.cols, (c + 1) * f); ++j) {
          const float v = grid.at(i, j);
          if (std::isnan(v)) continue;
          sum += v;
          best = std::max(best, static_cast<double>(v));
          ++n;
        }
      if (n > 0) out.values[static_cast<size_t>(r * out.cols + c)] =
                     static_cast<float>(hazard_classes ? best : sum / n);
    }
  return out;
}

int cell_pixels(const DenseGrid& grid, int min_size) {
  const int side = std::max(grid.rows, grid.cols);
  return std::max(1, (min_size + side - 1) / std::max(1, side));
}

std::string metres(double v, const char* format = "%+.3f m") {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string length_label(double m) {
  char buf[32];
  if (m < 1.0) std::snprintf(buf, sizeof buf, "%g cm", m * 100.0);
  else std::snprintf(buf, sizeof buf, "%g m", m);
  return buf;
}

void draw_robot(cv::Mat& image, const DenseGrid& grid, int k, const RobotMarker& robot) {
  const double col = (robot.x_m - grid.center_x_m) / grid.resolution_m + grid.cols / 2.0;
  const double row = (grid.center_y_m - robot.y_m) / grid.resolution_m + grid.rows / 2.0;
  const cv::Point2d c(col * k, row * k);
  const int radius = std::max(5, image.cols / 64);
  const int thickness = std::max(1, image.cols / 400);
  const cv::Point centre(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y)));
  // A dark edge under the white ring keeps it visible on any colour.
  cv::circle(image, centre, radius, kRobotEdge, thickness + 2, cv::LINE_AA);
  cv::circle(image, centre, radius, kRobotRing, thickness, cv::LINE_AA);
  if (!std::isnan(robot.yaw_rad)) {
    // Image columns follow +x, rows follow -y.
    const cv::Point2d dir(std::cos(robot.yaw_rad), -std::sin(robot.yaw_rad));
    const cv::Point a(c + dir * radius), b(c + dir * (2.0 * radius));
    cv::line(image, a, b, kRobotEdge, thickness + 2, cv::LINE_AA);
    cv::line(image, a, b, kRobotRing, thickness, cv::LINE_AA);
  }
}

// The axis glyph, all its constants here: two arrows from the map's bottom-left corner,
// +x to the right and +y up, labelled. That is how every panel is drawn (columns follow
// W's +x, rows its -y, as in draw_robot; maps never rotate), so the glyph is the same on
// every panel and frame; it is the reader's key to the heading tick and to the JDEM's
// north-up rows. White on a dark edge like the robot ring, with no backdrop: only its
// strokes cover cells. Its size follows the map's width within bounds; a map too small to
// hold it (under twice the glyph's box each way) gets none.
constexpr double kGlyphArrowPerMapWidth = 1.0 / 20;
constexpr int kGlyphMinArrowPx = 14, kGlyphMaxArrowPx = 40;
constexpr double kGlyphTextPerArrow = 1.0 / 45;  // OpenCV font scale per arrow pixel
constexpr double kGlyphHeadPerArrow = 0.25;      // arrow head length / arrow length
constexpr int kGlyphInsetPx = 3;                 // from the map's edges to the glyph's box

struct AxisGlyph {
  bool fits = false;
  cv::Point origin, x_tip, y_tip, x_label, y_label;  // label: bottom-left of the text
  int stroke = 1, edge = 3;                          // white pen, dark pen under it
  double text_scale = 0.5;
  cv::Rect box;
};

AxisGlyph axis_glyph(cv::Size map) {
  AxisGlyph g;
  const int arrow = std::clamp(static_cast<int>(std::lround(map.width * kGlyphArrowPerMapWidth)),
                               kGlyphMinArrowPx, kGlyphMaxArrowPx);
  g.stroke = std::max(1, arrow / 20);
  g.edge = g.stroke + 2;
  g.text_scale = arrow * kGlyphTextPerArrow;
  // Half the dark pen, plus anti-aliasing and the rounding of the head's barbs.
  const int half = g.edge / 2 + 2;
  // The head's barbs leave the shaft at 45 degrees: sideways by head / sqrt(2).
  const int spread =
      static_cast<int>(std::ceil(arrow * kGlyphHeadPerArrow / std::sqrt(2.0))) + half;
  const int gap = std::max(2, arrow / 8);
  int base_x = 0, base_y = 0;
  const cv::Size tx = cv::getTextSize("x", kFont, g.text_scale, g.edge, &base_x);
  const cv::Size ty = cv::getTextSize("y", kFont, g.text_scale, g.edge, &base_y);
  // Laid out around an origin at (0, 0), then moved into the corner.
  g.x_tip = {arrow, 0};
  g.y_tip = {0, -arrow};
  g.x_label = {arrow + half + gap, tx.height / 2};
  g.y_label = {spread + gap, -arrow + ty.height / 2};
  cv::Rect box(cv::Point(-spread, -arrow - half), cv::Point(arrow + half + 1, spread + 1));
  box |= cv::Rect(g.x_label.x - half, g.x_label.y - tx.height - half, tx.width + 2 * half,
                  tx.height + base_x + 2 * half);
  box |= cv::Rect(g.y_label.x - half, g.y_label.y - ty.height - half, ty.width + 2 * half,
                  ty.height + base_y + 2 * half);
  const cv::Point shift(kGlyphInsetPx - box.x, map.height - kGlyphInsetPx - (box.y + box.height));
  for (cv::Point* p : {&g.origin, &g.x_tip, &g.y_tip, &g.x_label, &g.y_label}) *p += shift;
  g.box = box + shift;
  g.fits = 2 * (g.box.width + kGlyphInsetPx) <= map.width &&
           2 * (g.box.height + kGlyphInsetPx) <= map.height;
  if (!g.fits) g.box = cv::Rect();
  return g;
}

void draw_axis_glyph(cv::Mat& map) {
  const AxisGlyph g = axis_glyph(map.size());
  if (!g.fits) return;
  for (const auto& [colour, width] : {std::pair{kRobotEdge, g.edge}, std::pair{kRobotRing, g.stroke}}) {
    cv::arrowedLine(map, g.origin, g.x_tip, colour, width, cv::LINE_AA, 0, kGlyphHeadPerArrow);
    cv::arrowedLine(map, g.origin, g.y_tip, colour, width, cv::LINE_AA, 0, kGlyphHeadPerArrow);
    cv::putText(map, "x", g.x_label, kFont, g.text_scale, colour, width, cv::LINE_AA);
    cv::putText(map, "y", g.y_label, kFont, g.text_scale, colour, width, cv::LINE_AA);
  }
}

/// `map` centred on a side x side square of the background (the mosaic's equal panels).
cv::Mat padded_square(const cv::Mat& map, int side) {
  if (side <= 0 || (map.cols >= side && map.rows >= side)) return map;
  cv::Mat out(std::max(side, map.rows), std::max(side, map.cols), CV_8UC3, kBackground);
  map.copyTo(out(cv::Rect((out.cols - map.cols) / 2, (out.rows - map.rows) / 2, map.cols, map.rows)));
  return out;
}

/// Pixels per cell: the smallest k with the map >= min_size, or with side_px > 0 the
/// largest with the map <= side_px.
int pixels_per_cell(const DenseGrid& grid, int min_size, int side_px) {
  if (side_px <= 0) return cell_pixels(grid, min_size);
  return std::max(1, side_px / std::max({1, grid.rows, grid.cols}));
}

/// `map` (k pixels per cell of `grid`), with `right` beside it if not empty, above a
/// footer: `title` and the extent, then `note`, and a scale bar at the right end of the
/// first line that has room for it (a line of its own on a narrow panel).
cv::Mat with_footer(const cv::Mat& map, const cv::Mat& right, const DenseGrid& grid, double k,
                    const std::string& title, const std::string& note) {
  const int width = map.cols + right.cols;
  const Ink ink = Ink::for_width(width);
  char extent[96];
  // \x01 (a space wrap() does not break at) holds "2.56 x 2.56 m" on one line.
  std::snprintf(extent, sizeof extent, "%s cells, %.2f\x01x\x01%.2f\x01m",
                length_label(grid.resolution_m).c_str(), grid.cols * grid.resolution_m,
                grid.rows * grid.resolution_m);
  std::vector<std::string> lines;
  ink.wrap(title + "  " + extent, width - 2 * ink.pad_px, lines);
  if (!note.empty()) ink.wrap(note, width - 2 * ink.pad_px, lines);

  const double bar_m = scale_bar_length_m(grid.cols * grid.resolution_m);
  const int bar_px = static_cast<int>(std::lround(bar_m / grid.resolution_m * k));
  const std::string bar_text = length_label(bar_m);
  const int bar_room = bar_px + ink.text_width(bar_text) + 5 * ink.pad_px;
  size_t bar_line = 0;
  while (bar_line < lines.size() && ink.text_width(lines[bar_line]) + ink.pad_px + bar_room > width)
    ++bar_line;
  const int n_lines = static_cast<int>(std::max(lines.size(), bar_line + 1));
  const int body = std::max(map.rows, right.rows);
  cv::Mat canvas(body + n_lines * ink.line_px + 2 * ink.pad_px, width, CV_8UC3, kBackground);
  map.copyTo(canvas(cv::Rect(0, 0, map.cols, map.rows)));
  if (!right.empty()) right.copyTo(canvas(cv::Rect(map.cols, 0, right.cols, right.rows)));

  const int top = body + ink.pad_px;
  for (size_t i = 0; i < lines.size(); ++i)
    ink.put(canvas, lines[i],
            {ink.pad_px, top + static_cast<int>(i + 1) * ink.line_px - ink.pad_px});
  // The bar: its length on the left of its label, both on line `bar_line`, right-aligned.
  const int label_w = ink.text_width(bar_text);
  const int bar_right = width - 2 * ink.pad_px - label_w;
  const int bar_left = bar_right - bar_px;
  const int baseline = top + static_cast<int>(bar_line + 1) * ink.line_px - ink.pad_px;
  const int bar_y = baseline - ink.line_px / 4;
  const int tick = ink.line_px / 4;
  cv::line(canvas, {bar_left, bar_y}, {bar_right, bar_y}, kText, ink.thickness + 1);
  cv::line(canvas, {bar_left, bar_y - tick}, {bar_left, bar_y + tick}, kText, ink.thickness + 1);
  cv::line(canvas, {bar_right, bar_y - tick}, {bar_right, bar_y + tick}, kText, ink.thickness + 1);
  ink.put(canvas, bar_text, {bar_right + ink.pad_px, baseline});
  return canvas;
}

}  // namespace

cv::Rect axis_glyph_box(cv::Size map_size) { return axis_glyph(map_size).box; }

int map_side_px(const DenseGrid& grid, int min_size, int max_size) {
  const int f = cells_per_pixel(grid, max_size);
  const int side = (std::max(grid.rows, grid.cols) + f - 1) / f;  // as reduce()
  return side * std::max(1, (min_size + side - 1) / std::max(1, side));
}

double scale_bar_length_m(double width_m) {
  const double target = width_m / 4.0;
  if (!(target > 0)) return 0.0;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= target * (1 + 1e-9)) return m * decade;
  return decade;
}

cv::Mat render_hazard(const DenseGrid& full, int min_size, const RobotMarker& robot,
                      const std::string& title, int max_size, int side_px) {
  const int f = cells_per_pixel(full, max_size);
  const DenseGrid reduced = f > 1 ? reduce(full, f, true) : DenseGrid();
  const DenseGrid& hazard = f > 1 ? reduced : full;
  const int k = pixels_per_cell(hazard, min_size, side_px);
  cv::Mat image(hazard.rows * k, hazard.cols * k, CV_8UC3);
  // Pixel by pixel through row pointers: a setTo on a k x k sub-image per cell cost
  // ~100 ms for a 512 x 512 grid, most of a frame's PNG time.
  for (int r = 0; r < hazard.rows; ++r)
    for (int i = 0; i < k; ++i) {
      cv::Vec3b* out = image.ptr<cv::Vec3b>(r * k + i);
      for (int c = 0; c < hazard.cols; ++c) {
        const float v = hazard.at(r, c);
        const cv::Vec3b colour = v == 2.0f ? kHazardBgr : v == 1.0f ? kTraversableBgr : kUnknownBgr;
        for (int j = 0; j < k; ++j) *out++ = colour;
      }
    }
  draw_robot(image, hazard, k, robot);
  image = padded_square(image, side_px);
  draw_axis_glyph(image);
  return with_footer(image, cv::Mat(), full, k * 1.0 / f, title,
                     f > 1 ? "grey unknown, green traversable, red hazard (" + std::to_string(f) +
                                 " x " + std::to_string(f) + " cells per pixel, the worst shown)"
                           : "grey unknown, green traversable, red hazard");
}

cv::Mat render_height(const DenseGrid& full, int min_size, const RobotMarker& robot,
                      const std::string& title, double clip_pct, int max_size, int side_px) {
  const int f = cells_per_pixel(full, max_size);
  const DenseGrid reduced = f > 1 ? reduce(full, f, false) : DenseGrid();
  const DenseGrid& height = f > 1 ? reduced : full;
  const int k = pixels_per_cell(height, min_size, side_px);
  const HeightRange range = robust_height_range(height, clip_pct);
  const double lo = range.lo, span = range.hi > range.lo ? range.hi - range.lo : 1.0;

  cv::Mat levels(height.rows, height.cols, CV_8UC1);
  cv::Mat unknown(height.rows, height.cols, CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < height.rows; ++r)
    for (int c = 0; c < height.cols; ++c) {
      const float v = height.at(r, c);
      if (std::isnan(v)) {
        unknown.at<uchar>(r, c) = 255;
        levels.at<uchar>(r, c) = 0;
      } else {
        levels.at<uchar>(r, c) = cv::saturate_cast<uchar>((v - lo) / span * 255.0);
      }
    }
  cv::Mat coloured;
  cv::applyColorMap(levels, coloured, cv::COLORMAP_VIRIDIS);
  coloured.setTo(cv::Scalar(kUnknownBgr), unknown);
  cv::Mat map_image;
  cv::resize(coloured, map_image, cv::Size(), k, k, cv::INTER_NEAREST);
  draw_robot(map_image, height, k, robot);
  map_image = padded_square(map_image, side_px);
  draw_axis_glyph(map_image);

  // Colour bar with the metres it spans, labelled in the footer's font.
  const Ink ink = Ink::for_width(map_image.cols);
  const int margin = ink.pad_px * 2;
  const int bar_w = std::max(16, map_image.cols / 24);
  const int label_w = ink.text_width("+00.000 m") + ink.pad_px;
  cv::Mat side(map_image.rows, bar_w + label_w + 2 * margin, CV_8UC3, kBackground);
  const int bar_top = margin, bar_h = std::max(2, map_image.rows - 2 * margin);
  cv::Mat ramp(bar_h, 1, CV_8UC1);
  for (int i = 0; i < bar_h; ++i)
    ramp.at<uchar>(i, 0) = cv::saturate_cast<uchar>(255.0 * (bar_h - 1 - i) / std::max(1, bar_h - 1));
  cv::Mat ramp_colour, ramp_wide;
  cv::applyColorMap(ramp, ramp_colour, cv::COLORMAP_VIRIDIS);
  cv::resize(ramp_colour, ramp_wide, cv::Size(bar_w, bar_h), 0, 0, cv::INTER_NEAREST);
  ramp_wide.copyTo(side(cv::Rect(margin, bar_top, bar_w, bar_h)));
  const int text_x = margin + bar_w + ink.pad_px;
  const int half_line = ink.line_px / 3;
  if (!range.any) {
    ink.put(side, "no data", {text_x, bar_top + ink.line_px});
  } else {
    ink.put(side, metres(range.hi), {text_x, bar_top + 2 * half_line});
    ink.put(side, metres((range.hi + range.lo) / 2), {text_x, bar_top + bar_h / 2 + half_line});
    ink.put(side, metres(range.lo), {text_x, bar_top + bar_h});
  }
  std::string note;
  if (range.any) {
    char text[160];
    if (clip_pct > 0)
      std::snprintf(text, sizeof text, "colours: %g-%g %% of cells; all %+.3f .. %+.3f m", clip_pct,
                    100 - clip_pct, range.min, range.max);
    else
      std::snprintf(text, sizeof text, "colours: all cells, %+.3f .. %+.3f m", range.min, range.max);
    note = text;
  }
  return with_footer(map_image, side, full, k * 1.0 / f, title + " height", note);
}

}  // namespace hazmap
