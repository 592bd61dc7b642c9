#pragma once
// Per-frame outputs (SPEC 9): hazard and height PNGs, JDEM grids, all written
// atomically into OUT/frames/<frame>/.

#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {

struct HazardAreas {
  double hazard_m2 = 0;
  double traversable_m2 = 0;
  double unknown_m2 = 0;
};

HazardAreas hazard_areas(const DenseGrid& hazard);

/// A dense grid as a JDEM grid (same layout: row 0 = largest y); `frame_name` becomes
/// the `frame` metadata key unless it is empty.
JdemGrid to_jdem(const DenseGrid& grid, const std::string& quantity, const std::string& units,
                 const std::string& frame_name);

/// Hazard palette image (unknown 90,90,90; traversable 40,170,70; hazard 220,40,40; BGR
/// in memory), each cell k x k pixels with k chosen so the image is >= min_size, and the
/// robot at (x, y) as a small white cross.
cv::Mat render_hazard(const DenseGrid& hazard, int min_size, double robot_x_m, double robot_y_m);

/// Height image in the viridis colour map with a colour bar labelled in metres;
/// unknown cells grey.
cv::Mat render_height(const DenseGrid& height, int min_size, double robot_x_m, double robot_y_m);

/// One image tiling every layer (hazard on top, height below) and the fused hazard map,
/// each tile titled with layer, resolution and rule, for flipping through a run.
cv::Mat render_mosaic(const Pipeline& pipeline, const MapConfig& map, const std::string& frame_name,
                      double robot_x_m, double robot_y_m);

/// Writes every output file of one frame into `frame_dir`.
void write_frame_outputs(const std::filesystem::path& frame_dir, const std::string& frame_name,
                         const Pipeline& pipeline, const Pose3d& T_W_B,
                         const OutputConfig& output);

}  // namespace hazmap
