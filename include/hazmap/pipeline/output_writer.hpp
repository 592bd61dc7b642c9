#pragma once
// Per-frame outputs (SPEC 9): hazard and height PNGs, JDEM or GeoTIFF grids, all
// written atomically into OUT/frames/<frame>/. The frame loop copies what a frame
// writes into a FrameOutputs (capture_frame_outputs, no allocation once its buffers
// have grown) so that the writing can happen on another thread (frame_writer.hpp).

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/pipeline/map_render.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {

struct HazardAreas {
  double hazard_m2 = 0;
  double traversable_m2 = 0;
  double unknown_m2 = 0;
};

HazardAreas hazard_areas(const DenseGrid& hazard);

/// One layer's grids as a frame publishes them.
struct LayerOutputs {
  DenseGrid hazard;
  DenseGrid height;
  DenseGrid variance;                ///< as the map holds it; the writer adds the extra
  double published_extra_variance_m2 = 0.0;
  DenseGrid slope_x, slope_y;        ///< CCM layers only (rows 0 otherwise)
  DenseGrid unknown_reason;          ///< output.unknown_reasons only (rows 0 otherwise)
  double resolution_m = 0.0;         ///< for the mosaic's titles
  RuleKind rule = RuleKind::kalman;
};

/// Everything one frame writes, copied out of the pipeline.
struct FrameOutputs {
  std::string frame_name;
  double robot_x_m = 0.0, robot_y_m = 0.0;
  double robot_yaw_rad = 0.0;  ///< heading of the body's x axis in W
  std::vector<LayerOutputs> layers;
  DenseGrid fused, clearance, footprint, hazard_distance;
};

/// Copies the pipeline's current outputs into `into`, reusing its buffers (copy
/// assignment of equal-sized grids does not allocate).
void capture_frame_outputs(const Pipeline& pipeline, const std::string& frame_name,
                           const Pose3d& T_W_B, FrameOutputs& into);

/// A dense grid as a JDEM grid (same layout: row 0 = largest y); `frame_name` becomes
/// the `frame` metadata key unless it is empty.
JdemGrid to_jdem(const DenseGrid& grid, const std::string& quantity, const std::string& units,
                 const std::string& frame_name);

/// The mosaic's panels, column by column: layer i's hazard then its height, then the
/// fused and the footprint map. All of one pixel size: every map part is the same square
/// (the largest map_side_px among them, each grid's cells the largest whole number of
/// pixels that fits, centred), and each panel is padded with the background to the
/// largest panel (the height panels' colour bar, the longest footer).
std::vector<cv::Mat> render_mosaic_panels(const FrameOutputs& frame, double png_height_clip_pct);

/// One image tiling render_mosaic_panels (hazard above height, the fused and footprint
/// maps in the last column) under the frame's name, each panel labelled with its
/// resolution, extent and scale bar, for flipping through a run.
cv::Mat render_mosaic(const FrameOutputs& frame, double png_height_clip_pct);

/// Writes every output file of one frame into `frame_dir` (PNGs, and the grids in
/// output.format: `<name>.jdem` and/or `<name>.tif`), each file atomically.
void write_frame_outputs(const std::filesystem::path& frame_dir, const FrameOutputs& frame,
                         const OutputConfig& output);

/// The same straight from a pipeline (capture, then write).
void write_frame_outputs(const std::filesystem::path& frame_dir, const std::string& frame_name,
                         const Pipeline& pipeline, const Pose3d& T_W_B,
                         const OutputConfig& output);

}  // namespace hazmap
