#include "hazmap/pipeline/output_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "hazmap/io/geotiff.hpp"
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

/// One grid file in the configured format(s); `stem` without extension.
void write_grid(const std::filesystem::path& dir, const std::string& stem, const JdemGrid& grid,
                const OutputConfig& output) {
  if (output.format == "jdem" || output.format == "both") write_jdem(dir / (stem + ".jdem"), grid);
  if (output.format == "geotiff" || output.format == "both")
    write_geotiff(dir / (stem + ".tif"), grid);
}

/// Copy assignment keeps `to`'s buffer when it is large enough: no allocation per frame.
void copy_grid(const DenseGrid& from, DenseGrid& to) { to = from; }

}  // namespace

void capture_frame_outputs(const Pipeline& pipeline, const std::string& frame_name,
                           const Pose3d& T_W_B, FrameOutputs& into) {
  const MapConfig& map = pipeline.config().map;
  into.frame_name = frame_name;
  into.robot_x_m = T_W_B.translation().x();
  into.robot_y_m = T_W_B.translation().y();
  const auto& views = pipeline.layers();
  into.layers.resize(views.size());
  for (size_t i = 0; i < views.size(); ++i) {
    const LayerView& v = views[i];
    LayerOutputs& l = into.layers[i];
    copy_grid(v.hazard, l.hazard);
    copy_grid(v.map.height, l.height);
    copy_grid(v.map.variance, l.variance);
    l.published_extra_variance_m2 = pipeline.hazard_params().layers[i].published_extra_variance_m2;
    if (v.map.slope_x.rows > 0) {
      copy_grid(v.map.slope_x, l.slope_x);
      copy_grid(v.map.slope_y, l.slope_y);
    } else {
      l.slope_x.rows = l.slope_y.rows = 0;
      l.slope_x.values.clear();  // keeps the capacity
      l.slope_y.values.clear();
    }
    l.resolution_m = map.layers[i].resolution_m;
    l.rule = map.layers[i].rule;
  }
  const PlannerMaps& planner = pipeline.planner_maps();
  copy_grid(planner.fused, into.fused);
  copy_grid(planner.clearance, into.clearance);
  copy_grid(planner.footprint, into.footprint);
  copy_grid(planner.hazard_distance, into.hazard_distance);
}

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
  // Pixel by pixel through row pointers: a setTo on a k x k sub-image per cell cost
  // ~100 ms for a 512 x 512 grid, most of a frame's PNG time.
  for (int r = 0; r < hazard.rows; ++r)
    for (int i = 0; i < k; ++i) {
      cv::Vec3b* out = image.ptr<cv::Vec3b>(r * k + i);
      for (int c = 0; c < hazard.cols; ++c) {
        const auto cls = static_cast<HazardClass>(static_cast<int>(hazard.at(r, c)));
        const cv::Vec3b colour = cls == HazardClass::hazard        ? kHazardBgr
                                 : cls == HazardClass::traversable ? kTraversableBgr
                                                                   : kUnknownBgr;
        for (int j = 0; j < k; ++j) *out++ = colour;
      }
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

cv::Mat render_mosaic(const FrameOutputs& frame) {
  constexpr int kTile = 320, kTitle = 28, kGap = 8;
  const auto& views = frame.layers;
  const double robot_x_m = frame.robot_x_m, robot_y_m = frame.robot_y_m;
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
  cv::putText(canvas, "frame " + frame.frame_name, cv::Point(kGap, 20), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              text, 1, cv::LINE_AA);
  for (size_t i = 0; i < views.size(); ++i) {
    char title[96];
    std::snprintf(title, sizeof title, "L%zu  %g cm  %s", i, views[i].resolution_m * 100,
                  rule_name(views[i].rule));
    place(render_hazard(views[i].hazard, kTile, robot_x_m, robot_y_m), static_cast<int>(i), 0,
          title);
    place(render_height(views[i].height, kTile, robot_x_m, robot_y_m), static_cast<int>(i), 1,
          std::string(title) + "  height");
  }
  place(render_hazard(frame.fused, kTile, robot_x_m, robot_y_m), columns - 1, 0, "fused hazard");
  place(render_hazard(frame.footprint, kTile, robot_x_m, robot_y_m), columns - 1, 1, "footprint");
  return canvas;
}

void write_frame_outputs(const std::filesystem::path& dir, const FrameOutputs& frame,
                         const OutputConfig& output) {
  const double rx = frame.robot_x_m, ry = frame.robot_y_m;
  const std::string& name = frame.frame_name;
  for (size_t i = 0; i < frame.layers.size(); ++i) {
    const std::string prefix = "L" + std::to_string(i) + "_";
    const LayerOutputs& v = frame.layers[i];
    if (output.png) {
      write_png(dir / (prefix + "hazard.png"), render_hazard(v.hazard, output.png_min_size, rx, ry));
      write_png(dir / (prefix + "height.png"), render_height(v.height, output.png_min_size, rx, ry));
    }
    if (output.jdem) {
      write_grid(dir, prefix + "height", to_jdem(v.height, "height", "m", name), output);
      JdemGrid variance = to_jdem(v.variance, "variance", "m^2", name);
      const double extra = v.published_extra_variance_m2;
      for (float& value : variance.values) value = static_cast<float>(value + extra);  // NaN stays NaN
      write_grid(dir, prefix + "variance", variance, output);
      write_grid(dir, prefix + "hazard", to_jdem(v.hazard, "hazard", "class", name), output);
      if (v.slope_x.rows > 0) {  // CCM: h + slope_x dx + slope_y dy is the sub-cell surface
        write_grid(dir, prefix + "slope_x", to_jdem(v.slope_x, "slope_x", "m/m", name), output);
        write_grid(dir, prefix + "slope_y", to_jdem(v.slope_y, "slope_y", "m/m", name), output);
      }
    }
  }
  if (output.png) {
    write_png(dir / "fused_hazard.png", render_hazard(frame.fused, output.png_min_size, rx, ry));
    write_png(dir / "footprint_hazard.png",
              render_hazard(frame.footprint, output.png_min_size, rx, ry));
  }
  if (output.jdem) {
    write_grid(dir, "fused_hazard", to_jdem(frame.fused, "hazard", "class", name), output);
    write_grid(dir, "fused_clearance", to_jdem(frame.clearance, "clearance", "m", name), output);
    write_grid(dir, "footprint_hazard", to_jdem(frame.footprint, "hazard", "class", name), output);
    write_grid(dir, "hazard_distance", to_jdem(frame.hazard_distance, "distance", "m", name),
               output);
  }
}

void write_frame_outputs(const std::filesystem::path& dir, const std::string& frame_name,
                         const Pipeline& pipeline, const Pose3d& T_W_B,
                         const OutputConfig& output) {
  FrameOutputs frame;
  capture_frame_outputs(pipeline, frame_name, T_W_B, frame);
  write_frame_outputs(dir, frame, output);
}

}  // namespace hazmap
