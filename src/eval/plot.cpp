#include "hazmap/eval/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap::eval {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// Distinct, colour-blind-friendly series colours (Okabe-Ito, BGR).
const cv::Scalar kPalette[] = {
    {178, 114, 0},  {0, 159, 230},  {115, 158, 0}, {167, 121, 204},
    {0, 94, 213},   {233, 180, 86}, {66, 228, 240}, {0, 0, 0},
};

std::string format_number(double v) {
  char buf[32];
  const double a = std::abs(v);
  if (a == 0.0) return "0";
  if (a < 1e5 && std::abs(v - std::round(v)) < 1e-9) std::snprintf(buf, sizeof buf, "%.0f", v);
  else if (a >= 1e4 || a < 1e-3) std::snprintf(buf, sizeof buf, "%.1e", v);
  else if (a >= 100) std::snprintf(buf, sizeof buf, "%.0f", v);
  else if (a >= 10) std::snprintf(buf, sizeof buf, "%.1f", v);
  else if (a >= 1) std::snprintf(buf, sizeof buf, "%.2f", v);
  else std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// A tick label with just the decimals the tick step needs (0.5 -> 1, 20 -> 0).
std::string format_tick(double v, double step) {
  if (!(step > 0) || std::abs(v) >= 1e5 || (v != 0 && std::abs(v) < 1e-4)) return format_number(v);
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// Ticks at 1, 2, 5 x 10^k covering [lo, hi] with about `target` steps.
std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

cv::Vec3b viridis(double t) {
  static cv::Mat lut;
  if (lut.empty()) {
    cv::Mat ramp(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i) ramp.at<unsigned char>(0, i) = static_cast<unsigned char>(i);
    cv::applyColorMap(ramp, lut, cv::COLORMAP_VIRIDIS);
  }
  const int i = std::clamp(static_cast<int>(std::lround(t * 255.0)), 0, 255);
  return lut.at<cv::Vec3b>(0, i);
}

// White -> yellow -> orange -> dark red, for "bad is dark" heat maps.
cv::Vec3b heat(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const double stops[][3] = {{255, 255, 255}, {255, 230, 120}, {245, 140, 50}, {200, 40, 30},
                             {110, 0, 20}};  // RGB
  const double s = t * 4.0;
  const int k = std::min(3, static_cast<int>(s));
  const double f = s - k;
  cv::Vec3b bgr;
  for (int ch = 0; ch < 3; ++ch)
    bgr[2 - ch] = static_cast<unsigned char>(
        std::lround(stops[k][ch] + f * (stops[k + 1][ch] - stops[k][ch])));
  return bgr;
}

int text_width(const std::string& text, double scale, int thickness = 1) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, thickness, &baseline).width;
}

}  // namespace

void put_label(cv::Mat& image, const std::string& text, int x, int y, double scale,
               const cv::Scalar& bgr, int thickness) {
  cv::putText(image, text, cv::Point(x, y), kFont, scale, bgr, thickness, cv::LINE_AA);
}

cv::Mat plot_lines(const LineChart& chart) {
  cv::Mat img(chart.height_px, chart.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 62, right = 165, top = 30, bottom = 44;
  const int pw = chart.width_px - left - right, ph = chart.height_px - top - bottom;
  const auto tx = [&](double x) { return chart.log2_x ? std::log2(x) : x; };

  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  for (const Series& s : chart.series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || (chart.log2_x && s.x[i] <= 0)) continue;
      x_lo = std::min(x_lo, tx(s.x[i]));
      x_hi = std::max(x_hi, tx(s.x[i]));
      if (!std::isfinite(s.y[i])) continue;
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  for (double t : chart.x_ticks) {
    x_lo = std::min(x_lo, tx(t));
    x_hi = std::max(x_hi, tx(t));
  }
  if (x_lo > x_hi) x_lo = 0, x_hi = 1;
  if (y_lo > y_hi) y_lo = 0, y_hi = 1;
  if (chart.y_from_zero) y_lo = std::min(y_lo, 0.0), y_hi = std::max(y_hi, 0.0);
  if (x_hi - x_lo < 1e-12) x_lo -= 0.5, x_hi += 0.5;
  if (y_hi - y_lo < 1e-12) y_hi = y_lo + (y_lo == 0 ? 1.0 : std::abs(y_lo) * 0.1);
  std::vector<double> yt = nice_ticks(y_lo, y_hi, 5);
  y_lo = std::min(y_lo, yt.front());
  const double y_step = yt.size() > 1 ? yt[1] - yt[0] : (y_hi - y_lo);
  if (yt.back() < y_hi - 1e-12) yt.push_back(yt.back() + y_step);
  y_hi = std::max(y_hi, yt.back());
  const double xpad = (x_hi - x_lo) * 0.04;
  x_lo -= xpad;
  x_hi += xpad;

  const auto px = [&](double x) {
    return left + static_cast<int>(std::lround((tx(x) - x_lo) / (x_hi - x_lo) * pw));
  };
  const auto py = [&](double y) {
    return top + ph - static_cast<int>(std::lround((y - y_lo) / (y_hi - y_lo) * ph));
  };

  // Grid, axes and ticks.
  for (double t : yt) {
    cv::line(img, {left, py(t)}, {left + pw, py(t)}, cv::Scalar(232, 232, 232), 1);
    const std::string label = format_tick(t, y_step);
    put_label(img, label, left - 6 - text_width(label, 0.4), py(t) + 4, 0.4);
  }
  std::vector<double> xt = chart.x_ticks;
  if (xt.empty()) {
    if (chart.log2_x) {
      for (double e = std::ceil(x_lo); e <= x_hi; e += 1.0) xt.push_back(std::exp2(e));
    } else {
      xt = nice_ticks(x_lo, x_hi, 6);
    }
  }
  const double x_step = (!chart.log2_x && xt.size() > 1) ? xt[1] - xt[0] : 0.0;
  for (double t : xt) {
    if (tx(t) < x_lo || tx(t) > x_hi) continue;
    cv::line(img, {px(t), top + ph}, {px(t), top + ph + 4}, cv::Scalar(80, 80, 80), 1);
    const std::string label = x_step > 0 ? format_tick(t, x_step) : format_number(t);
    put_label(img, label, px(t) - text_width(label, 0.4) / 2, top + ph + 17, 0.4);
  }
  cv::rectangle(img, {left, top}, {left + pw, top + ph}, cv::Scalar(80, 80, 80), 1);
  put_label(img, chart.title, left, 20, 0.5, cv::Scalar(0, 0, 0), 1);
  put_label(img, chart.x_label, left + pw / 2 - text_width(chart.x_label, 0.42) / 2,
            chart.height_px - 8, 0.42);
  // Vertical y label: draw horizontally into a patch and rotate it.
  if (!chart.y_label.empty()) {
    const int w = text_width(chart.y_label, 0.42) + 4;
    cv::Mat patch(18, w, CV_8UC3, cv::Scalar(255, 255, 255));
    put_label(patch, chart.y_label, 2, 13, 0.42);
    cv::Mat rotated;
    cv::rotate(patch, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int y0 = std::max(0, top + ph / 2 - rotated.rows / 2);
    if (y0 + rotated.rows <= img.rows) rotated.copyTo(img(cv::Rect(2, y0, rotated.cols, rotated.rows)));
  }

  // Series and legend.
  int legend_y = top + 12;
  for (size_t k = 0; k < chart.series.size(); ++k) {
    const Series& s = chart.series[k];
    const cv::Scalar colour = kPalette[k % (sizeof kPalette / sizeof kPalette[0])];
    bool any = false;
    cv::Point prev;
    bool have_prev = false;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (chart.log2_x && s.x[i] <= 0)) {
        have_prev = false;
        continue;
      }
      const cv::Point p(px(s.x[i]), py(s.y[i]));
      if (have_prev) cv::line(img, prev, p, colour, 2, cv::LINE_AA);
      cv::circle(img, p, 3, colour, cv::FILLED, cv::LINE_AA);
      prev = p;
      have_prev = any = true;
    }
    const int lx = left + pw + 10;
    cv::line(img, {lx, legend_y - 4}, {lx + 18, legend_y - 4}, colour, 2, cv::LINE_AA);
    cv::circle(img, {lx + 9, legend_y - 4}, 3, colour, cv::FILLED, cv::LINE_AA);
    put_label(img, any ? s.name : s.name + " (none)", lx + 24, legend_y, 0.4);
    legend_y += 18;
  }
  return img;
}

cv::Mat plot_heatmap(const HeatMap& map) {
  check(map.values.size() == map.rows.size(), "heat map: values do not match the row labels");
  for (const auto& row : map.values)
    check(row.size() == map.cols.size(), "heat map: values do not match the column labels");
  int label_w = text_width(map.row_label, 0.42);
  for (const auto& r : map.rows) label_w = std::max(label_w, text_width(r, 0.42));
  const int left = label_w + 16, top = 46, bar_w = 14;
  const int grid_w = map.cell_w_px * static_cast<int>(map.cols.size());
  const int grid_h = map.cell_h_px * static_cast<int>(map.rows.size());
  const int width = std::max(left + grid_w + 90, text_width(map.title, 0.5) + 20);
  const int height = top + grid_h + 44;
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  put_label(img, map.title, 8, 18, 0.5, cv::Scalar(0, 0, 0));
  put_label(img, map.row_label, 8, top - 8, 0.42);
  const double span = map.max_value > map.min_value ? map.max_value - map.min_value : 1.0;
  for (size_t r = 0; r < map.rows.size(); ++r) {
    const int y = top + static_cast<int>(r) * map.cell_h_px;
    put_label(img, map.rows[r], 8, y + map.cell_h_px / 2 + 5, 0.42);
    for (size_t c = 0; c < map.cols.size(); ++c) {
      const int x = left + static_cast<int>(c) * map.cell_w_px;
      const double v = map.values[r][c];
      const cv::Rect cell(x, y, map.cell_w_px, map.cell_h_px);
      std::string text = "-";
      cv::Scalar ink(40, 40, 40);
      if (std::isfinite(v)) {
        const double t = (v - map.min_value) / span;
        const cv::Vec3b colour = heat(t);
        cv::rectangle(img, cell, cv::Scalar(colour[0], colour[1], colour[2]), cv::FILLED);
        char buf[32];
        std::snprintf(buf, sizeof buf, map.value_format.c_str(), v);
        text = buf;
        if (t > 0.55) ink = cv::Scalar(255, 255, 255);
      } else {
        cv::rectangle(img, cell, cv::Scalar(200, 200, 200), cv::FILLED);
      }
      cv::rectangle(img, cell, cv::Scalar(255, 255, 255), 1);
      put_label(img, text, x + map.cell_w_px / 2 - text_width(text, 0.36) / 2,
                y + map.cell_h_px / 2 + 4, 0.36, ink);
    }
  }
  for (size_t c = 0; c < map.cols.size(); ++c) {
    const int x = left + static_cast<int>(c) * map.cell_w_px + map.cell_w_px / 2;
    put_label(img, map.cols[c], x - text_width(map.cols[c], 0.38) / 2, top + grid_h + 16, 0.38);
  }
  put_label(img, map.col_label, left + grid_w / 2 - text_width(map.col_label, 0.42) / 2,
            top + grid_h + 36, 0.42);
  // Colour bar.
  const int bx = left + grid_w + 16;
  for (int i = 0; i < grid_h; ++i) {
    const cv::Vec3b colour = heat(1.0 - static_cast<double>(i) / std::max(1, grid_h - 1));
    cv::line(img, {bx, top + i}, {bx + bar_w, top + i}, cv::Scalar(colour[0], colour[1], colour[2]));
  }
  cv::rectangle(img, {bx, top}, {bx + bar_w, top + grid_h}, cv::Scalar(120, 120, 120), 1);
  put_label(img, format_number(map.max_value), bx + bar_w + 4, top + 10, 0.36);
  put_label(img, format_number(map.min_value), bx + bar_w + 4, top + grid_h, 0.36);
  return img;
}

cv::Mat render_scalar_grid(const DenseGrid& grid, double min_value, double max_value,
                           const std::string& title, const std::string& units, int scale) {
  scale = std::max(1, scale);
  const int gw = std::max(1, grid.cols * scale), gh = std::max(1, grid.rows * scale);
  const int top = 24, bar = 14, right = 70;
  cv::Mat img(gh + top + 6, gw + right + 4, CV_8UC3, cv::Scalar(255, 255, 255));
  const double span = max_value > min_value ? max_value - min_value : 1.0;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const double v = grid.at(r, c);
      const cv::Vec3b colour =
          std::isfinite(v) ? viridis((v - min_value) / span) : cv::Vec3b(70, 70, 70);
      img(cv::Rect(c * scale, top + r * scale, scale, scale)).setTo(colour);
    }
  put_label(img, title, 2, 16, 0.42, cv::Scalar(0, 0, 0));
  const int bx = gw + 8;
  for (int i = 0; i < gh; ++i) {
    const cv::Vec3b colour = viridis(1.0 - static_cast<double>(i) / std::max(1, gh - 1));
    cv::line(img, {bx, top + i}, {bx + bar, top + i}, cv::Scalar(colour[0], colour[1], colour[2]));
  }
  put_label(img, format_number(max_value), bx + bar + 3, top + 10, 0.36);
  put_label(img, format_number(min_value), bx + bar + 3, top + gh, 0.36);
  put_label(img, units, bx + bar + 3, top + gh / 2 + 4, 0.36);
  return img;
}

cv::Mat tile_images(const std::vector<cv::Mat>& images, int columns) {
  if (images.empty()) return cv::Mat(1, 1, CV_8UC3, cv::Scalar(255, 255, 255));
  columns = std::max(1, columns);
  const int gap = 8;
  const int n = static_cast<int>(images.size());
  const int rows = (n + columns - 1) / columns;
  std::vector<int> col_w(columns, 0), row_h(rows, 0);
  for (int i = 0; i < n; ++i) {
    col_w[i % columns] = std::max(col_w[i % columns], images[i].cols);
    row_h[i / columns] = std::max(row_h[i / columns], images[i].rows);
  }
  int width = gap, height = gap;
  for (int w : col_w) width += w + gap;
  for (int h : row_h) height += h + gap;
  cv::Mat out(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  int y = gap;
  for (int r = 0; r < rows; ++r) {
    int x = gap;
    for (int c = 0; c < columns; ++c) {
      const int i = r * columns + c;
      if (i < n) {
        cv::Mat bgr = images[i];
        if (bgr.channels() == 1) cv::cvtColor(bgr, bgr, cv::COLOR_GRAY2BGR);
        bgr.copyTo(out(cv::Rect(x, y, bgr.cols, bgr.rows)));
      }
      x += col_w[c] + gap;
    }
    y += row_h[r] + gap;
  }
  return out;
}

}  // namespace hazmap::eval
