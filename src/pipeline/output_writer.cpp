#include "hazmap/pipeline/output_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "hazmap/io/images.hpp"

namespace hazmap {
namespace {

const cv::Vec3b kUnknownBgr(90, 90, 90);
const cv::Vec3b kTraversableBgr(70, 170, 40);
const cv::Vec3b kHazardBgr(40, 40, 220);
const cv::Scalar kRobotColour(255, 255, 255);

int cell_pixels(const DenseGrid& grid, int min_size) {
  const int side = std::max(grid.rows, grid.cols);
  return std::max(1, (min_size + side - 1) / side);
}

void draw_robot(cv::Mat& image, const DenseGrid& grid, int k, double x_m, double y_m) {
  const double col = (x_m - grid.center_x_m) / grid.resolution_m + grid.cols / 2.0;
  const double row = (grid.center_y_m - y_m) / grid.resolution_m + grid.rows / 2.0;
  const cv::Point p(static_cast<int>(std::lround(col * k)), static_cast<int>(std::lround(row * k)));
  const int arm = std::max(4, image.cols / 64);
  const int thickness = std::max(1, image.cols / 256);
  cv::line(image, p - cv::Point(arm, 0), p + cv::Point(arm, 0), kRobotColour, thickness);
  cv::line(image, p - cv::Point(0, arm), p + cv::Point(0, arm), kRobotColour, thickness);
}

std::string metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f m", v);
  return buf;
}

}  // namespace

HazardAreas hazard_areas(const DenseGrid& hazard) {
  HazardAreas a;
  const double cell = hazard.resolution_m * hazard.resolution_m;
  for (float v : hazard.values) {
    switch (static_cast<HazardClass>(static_cast<int>(v))) {
      case HazardClass::hazard: a.hazard_m2 += cell; break;
      case HazardClass::traversable: a.traversable_m2 += cell; break;
      default: a.unknown_m2 += cell; break;
    }
  }
  return a;
}

JdemGrid to_jdem(const DenseGrid& grid, const std::string& quantity, const std::string& units,
                 const std::string& frame_name) {
  JdemGrid j;
  j.quantity = quantity;
  j.units = units;
  j.rows = grid.rows;
  j.cols = grid.cols;
  j.resolution_m = grid.resolution_m;
  j.center_x_m = grid.center_x_m;
  j.center_y_m = grid.center_y_m;
  j.values = grid.values;
  if (!frame_name.empty()) j.metadata.emplace_back("frame", frame_name);
  return j;
}

cv::Mat render_hazard(const DenseGrid& hazard, int min_size, double robot_x_m, double robot_y_m) {
  const int k = cell_pixels(hazard, min_size);
  cv::Mat image(hazard.rows * k, hazard.cols * k, CV_8UC3);
  for (int r = 0; r < hazard.rows; ++r)
    for (int c = 0; c < hazard.cols; ++c) {
      const auto cls = static_cast<HazardClass>(static_cast<int>(hazard.at(r, c)));
      const cv::Vec3b colour = cls == HazardClass::hazard        ? kHazardBgr
                               : cls == HazardClass::traversable ? kTraversableBgr
                                                                 : kUnknownBgr;
      image(cv::Rect(c * k, r * k, k, k)).setTo(colour);
    }
  draw_robot(image, hazard, k, robot_x_m, robot_y_m);
  return image;
}

cv::Mat render_height(const DenseGrid& height, int min_size, double robot_x_m, double robot_y_m) {
  const int k = cell_pixels(height, min_size);
  float lo = INFINITY, hi = -INFINITY;
  for (float v : height.values)
    if (!std::isnan(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  const bool any = lo <= hi;
  if (!any) lo = 0, hi = 0;
  const double span = hi > lo ? hi - lo : 1.0;

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
  draw_robot(map_image, height, k, robot_x_m, robot_y_m);

  // Colour bar with the metres it spans, to the right of the map.
  const int bar_w = std::max(16, map_image.cols / 24);
  const int label_w = 110;
  const int margin = 12;
  cv::Mat canvas(map_image.rows, map_image.cols + bar_w + label_w + 2 * margin, CV_8UC3,
                 cv::Scalar(30, 30, 30));
  map_image.copyTo(canvas(cv::Rect(0, 0, map_image.cols, map_image.rows)));
  const int bar_top = margin, bar_h = map_image.rows - 2 * margin;
  cv::Mat ramp(bar_h, 1, CV_8UC1);
  for (int i = 0; i < bar_h; ++i)
    ramp.at<uchar>(i, 0) = cv::saturate_cast<uchar>(255.0 * (bar_h - 1 - i) / std::max(1, bar_h - 1));
  cv::Mat ramp_colour, ramp_wide;
  cv::applyColorMap(ramp, ramp_colour, cv::COLORMAP_VIRIDIS);
  cv::resize(ramp_colour, ramp_wide, cv::Size(bar_w, bar_h), 0, 0, cv::INTER_NEAREST);
  const int bar_x = map_image.cols + margin;
  ramp_wide.copyTo(canvas(cv::Rect(bar_x, bar_top, bar_w, bar_h)));
  const cv::Scalar text(230, 230, 230);
  const int text_x = bar_x + bar_w + 6;
  cv::putText(canvas, any ? metres(hi) : "no data", cv::Point(text_x, bar_top + 12),
              cv::FONT_HERSHEY_SIMPLEX, 0.45, text, 1, cv::LINE_AA);
  if (any) {
    cv::putText(canvas, metres((hi + lo) / 2), cv::Point(text_x, bar_top + bar_h / 2 + 4),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, text, 1, cv::LINE_AA);
    cv::putText(canvas, metres(lo), cv::Point(text_x, bar_top + bar_h), cv::FONT_HERSHEY_SIMPLEX,
                0.45, text, 1, cv::LINE_AA);
  }
  return canvas;
}

cv::Mat render_mosaic(const Pipeline& pipeline, const MapConfig& map, const std::string& frame_name,
                      double robot_x_m, double robot_y_m) {
  constexpr int kTile = 320, kTitle = 28, kGap = 8;
  const auto& views = pipeline.layers();
  const int columns = static_cast<int>(views.size()) + 1;
  cv::Mat canvas(kTitle + 2 * (kTile + kTitle) + kGap, columns * (kTile + kGap) + kGap, CV_8UC3,
                 cv::Scalar(30, 30, 30));
  const cv::Scalar text(235, 235, 235);
  auto place = [&](const cv::Mat& img, int col, int row, const std::string& title) {
    // Height images carry a colour bar: keep their aspect, fit the tile width.
    const double s = std::min(double(kTile) / img.cols, double(kTile) / img.rows);
    cv::Mat scaled;
    cv::resize(img, scaled, cv::Size(), s, s, cv::INTER_NEAREST);
    const int x = kGap + col * (kTile + kGap), y = kTitle + row * (kTile + kTitle) + kTitle;
    scaled.copyTo(canvas(cv::Rect(x, y, scaled.cols, scaled.rows)));
    cv::putText(canvas, title, cv::Point(x, y - 8), cv::FONT_HERSHEY_SIMPLEX, 0.5, text, 1,
                cv::LINE_AA);
  };
  cv::putText(canvas, "frame " + frame_name, cv::Point(kGap, 20), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              text, 1, cv::LINE_AA);
  for (size_t i = 0; i < views.size(); ++i) {
    char title[96];
    std::snprintf(title, sizeof title, "L%zu  %g cm  %s", i, map.layers[i].resolution_m * 100,
                  rule_name(map.layers[i].rule));
    place(render_hazard(views[i].hazard, kTile, robot_x_m, robot_y_m), static_cast<int>(i), 0,
          title);
    place(render_height(views[i].map.height, kTile, robot_x_m, robot_y_m), static_cast<int>(i), 1,
          std::string(title) + "  height");
  }
  place(render_hazard(pipeline.fused_hazard(), kTile, robot_x_m, robot_y_m), columns - 1, 0,
        "fused hazard");
  place(render_hazard(pipeline.planner_maps().footprint, kTile, robot_x_m, robot_y_m), columns - 1,
        1, "footprint");
  return canvas;
}

void write_frame_outputs(const std::filesystem::path& dir, const std::string& frame_name,
                         const Pipeline& pipeline, const Pose3d& T_W_B,
                         const OutputConfig& output) {
  const double rx = T_W_B.translation().x(), ry = T_W_B.translation().y();
  const auto& views = pipeline.layers();
  for (size_t i = 0; i < views.size(); ++i) {
    const std::string prefix = "L" + std::to_string(i) + "_";
    const LayerView& v = views[i];
    if (output.png) {
      write_png(dir / (prefix + "hazard.png"), render_hazard(v.hazard, output.png_min_size, rx, ry));
      write_png(dir / (prefix + "height.png"), render_height(v.map.height, output.png_min_size, rx, ry));
    }
    if (output.jdem) {
      write_jdem(dir / (prefix + "height.jdem"), to_jdem(v.map.height, "height", "m", frame_name));
      JdemGrid variance = to_jdem(v.map.variance, "variance", "m^2", frame_name);
      const double extra = pipeline.hazard_params().layers[i].published_extra_variance_m2;
      for (float& value : variance.values) value = static_cast<float>(value + extra);  // NaN stays NaN
      write_jdem(dir / (prefix + "variance.jdem"), variance);
      write_jdem(dir / (prefix + "hazard.jdem"), to_jdem(v.hazard, "hazard", "class", frame_name));
      if (v.map.slope_x.rows > 0) {  // CCM: h + slope_x dx + slope_y dy is the sub-cell surface
        write_jdem(dir / (prefix + "slope_x.jdem"), to_jdem(v.map.slope_x, "slope_x", "m/m", frame_name));
        write_jdem(dir / (prefix + "slope_y.jdem"), to_jdem(v.map.slope_y, "slope_y", "m/m", frame_name));
      }
    }
  }
  const PlannerMaps& planner = pipeline.planner_maps();
  if (output.png) {
    write_png(dir / "fused_hazard.png", render_hazard(planner.fused, output.png_min_size, rx, ry));
    write_png(dir / "footprint_hazard.png",
              render_hazard(planner.footprint, output.png_min_size, rx, ry));
  }
  if (output.jdem) {
    write_jdem(dir / "fused_hazard.jdem", to_jdem(planner.fused, "hazard", "class", frame_name));
    write_jdem(dir / "fused_clearance.jdem",
               to_jdem(planner.clearance, "clearance", "m", frame_name));
    write_jdem(dir / "footprint_hazard.jdem",
               to_jdem(planner.footprint, "hazard", "class", frame_name));
    write_jdem(dir / "hazard_distance.jdem",
               to_jdem(planner.hazard_distance, "distance", "m", frame_name));
  }
}

}  // namespace hazmap
