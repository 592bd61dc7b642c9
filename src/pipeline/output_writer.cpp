#include "hazmap/pipeline/output_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "hazmap/io/geotiff.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "hazmap/io/run_layout.hpp"

namespace hazmap {
namespace {

/// One grid file in the configured format(s); `stem` without extension.
void write_grid(const std::filesystem::path& dir, const std::string& stem, const JdemGrid& grid,
                const OutputConfig& output) {
  if (output.format == GridFormat::jdem || output.format == GridFormat::both)
    write_jdem(dir / (stem + ".jdem"), grid);
  if (output.format == GridFormat::geotiff || output.format == GridFormat::both)
    write_geotiff(dir / (stem + ".tif"), grid);
}

RobotMarker frame_robot(const FrameOutputs& frame) {
  return {frame.robot_x_m, frame.robot_y_m, frame.robot_yaw_rad};
}

/// "L0 kalman": the panel's name; its footer adds the resolution and extent.
std::string layer_title(const LayerOutputs& layer, size_t index) {
  return run_layout::layer_id(index) + " " + rule_name(layer.rule);
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
  // Heading: where the body's x axis points in the W plane.
  into.robot_yaw_rad = std::atan2(T_W_B.linear()(1, 0), T_W_B.linear()(0, 0));
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
    if (pipeline.config().output.unknown_reasons) {
      pipeline.hazard_stage().explain(i, l.unknown_reason);
    } else {
      l.unknown_reason.rows = 0;
      l.unknown_reason.values.clear();  // keeps the capacity
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
  static_cast<DenseGrid&>(j) = grid;
  j.quantity = quantity;
  j.units = units;
  if (!frame_name.empty()) j.metadata.emplace_back("frame", frame_name);
  return j;
}

namespace {
// The mosaic's layout: panels' map parts at least kMosaicPanelPx (a grid of more cells
// than that a side shows several cells per pixel), kMosaicGapPx between panels, the
// frame's name in a kMosaicTitlePx strip on top.
constexpr int kMosaicPanelPx = 320, kMosaicGapPx = 8, kMosaicTitlePx = 32;
}  // namespace

std::vector<cv::Mat> render_mosaic_panels(const FrameOutputs& frame, double png_height_clip_pct) {
  const RobotMarker robot = frame_robot(frame);
  // One map side for all: the largest any panel needs at kMosaicPanelPx.
  int side = 0;
  const auto need = [&](const DenseGrid& g) {
    side = std::max(side, map_side_px(g, kMosaicPanelPx, kMosaicPanelPx));
  };
  for (const LayerOutputs& layer : frame.layers) {
    need(layer.hazard);
    need(layer.height);
  }
  need(frame.fused);
  need(frame.footprint);
  std::vector<cv::Mat> panels;
  for (size_t i = 0; i < frame.layers.size(); ++i) {
    const std::string title = layer_title(frame.layers[i], i);
    panels.push_back(render_hazard(frame.layers[i].hazard, kMosaicPanelPx, robot,
                                   title + " hazard", kMosaicPanelPx, side));
    panels.push_back(render_height(frame.layers[i].height, kMosaicPanelPx, robot, title,
                                   png_height_clip_pct, kMosaicPanelPx, side));
  }
  panels.push_back(
      render_hazard(frame.fused, kMosaicPanelPx, robot, "fused hazard", kMosaicPanelPx, side));
  panels.push_back(
      render_hazard(frame.footprint, kMosaicPanelPx, robot, "footprint", kMosaicPanelPx, side));
  // Padded right and below (the maps stay at the top-left, aligned across the mosaic).
  int width = 0, height = 0;
  for (const cv::Mat& p : panels) {
    width = std::max(width, p.cols);
    height = std::max(height, p.rows);
  }
  for (cv::Mat& p : panels) {
    if (p.cols == width && p.rows == height) continue;
    cv::Mat padded(height, width, CV_8UC3, cv::Scalar(30, 30, 30));
    p.copyTo(padded(cv::Rect(0, 0, p.cols, p.rows)));
    p = padded;
  }
  return panels;
}

cv::Mat render_mosaic(const FrameOutputs& frame, double png_height_clip_pct) {
  const std::vector<cv::Mat> panels = render_mosaic_panels(frame, png_height_clip_pct);
  const int columns = static_cast<int>(panels.size() / 2);
  const int w = panels.front().cols, h = panels.front().rows;
  cv::Mat canvas(kMosaicTitlePx + 2 * (h + kMosaicGapPx), kMosaicGapPx + columns * (w + kMosaicGapPx),
                 CV_8UC3, cv::Scalar(30, 30, 30));
  for (size_t i = 0; i < panels.size(); ++i) {
    const int col = static_cast<int>(i / 2), row = static_cast<int>(i % 2);
    panels[i].copyTo(canvas(cv::Rect(kMosaicGapPx + col * (w + kMosaicGapPx),
                                     kMosaicTitlePx + row * (h + kMosaicGapPx), w, h)));
  }
  cv::putText(canvas, "frame " + frame.frame_name, cv::Point(kMosaicGapPx, kMosaicTitlePx - 10),
              cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(235, 235, 235), 1, cv::LINE_AA);
  return canvas;
}

void write_frame_outputs(const std::filesystem::path& dir, const FrameOutputs& frame,
                         const OutputConfig& output) {
  using run_layout::layer_stem;
  using run_layout::png_file;
  const RobotMarker robot = frame_robot(frame);
  const int size = output.png_min_size;
  const std::string& name = frame.frame_name;
  for (size_t i = 0; i < frame.layers.size(); ++i) {
    const LayerOutputs& v = frame.layers[i];
    if (output.png) {
      const std::string title = layer_title(v, i);
      write_png(dir / png_file(layer_stem(i, "hazard")),
                render_hazard(v.hazard, size, robot, title + " hazard"));
      write_png(dir / png_file(layer_stem(i, "height")),
                render_height(v.height, size, robot, title, output.png_height_clip_pct));
    }
    if (output.jdem) {
      write_grid(dir, layer_stem(i, "height"), to_jdem(v.height, "height", "m", name), output);
      JdemGrid variance = to_jdem(v.variance, "variance", "m^2", name);
      const double extra = v.published_extra_variance_m2;
      for (float& value : variance.values)
        value = static_cast<float>(value + extra);  // NaN stays NaN
      write_grid(dir, layer_stem(i, "variance"), variance, output);
      write_grid(dir, layer_stem(i, "hazard"), to_jdem(v.hazard, "hazard", "class", name), output);
      if (v.slope_x.rows > 0) {  // CCM: h + slope_x dx + slope_y dy is the sub-cell surface
        write_grid(dir, layer_stem(i, "slope_x"), to_jdem(v.slope_x, "slope_x", "m/m", name),
                   output);
        write_grid(dir, layer_stem(i, "slope_y"), to_jdem(v.slope_y, "slope_y", "m/m", name),
                   output);
      }
      if (v.unknown_reason.rows > 0)
        write_grid(dir, layer_stem(i, "unknown_reason"),
                   to_jdem(v.unknown_reason, "unknown_reason", "bits", name), output);
    }
  }
  if (output.png) {
    write_png(dir / png_file(run_layout::kFusedHazard),
              render_hazard(frame.fused, size, robot, "fused hazard"));
    write_png(dir / png_file(run_layout::kFootprintHazard),
              render_hazard(frame.footprint, size, robot, "footprint hazard"));
  }
  if (output.jdem) {
    write_grid(dir, run_layout::kFusedHazard, to_jdem(frame.fused, "hazard", "class", name),
               output);
    write_grid(dir, run_layout::kFusedClearance, to_jdem(frame.clearance, "clearance", "m", name),
               output);
    write_grid(dir, run_layout::kFootprintHazard, to_jdem(frame.footprint, "hazard", "class", name),
               output);
    write_grid(dir, run_layout::kHazardDistance,
               to_jdem(frame.hazard_distance, "distance", "m", name), output);
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
