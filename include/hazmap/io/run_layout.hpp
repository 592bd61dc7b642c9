#pragma once
// The files of a run's output folder (SPEC 9), named once for the writer
// (pipeline/output_writer, frame_writer, sequence_runner), the evaluator and the run
// viewer (eval/), the CLI and the tests:
//
//   OUT/run.log, OUT/summary.json, OUT/view.html
//   OUT/frames/<frame>/L<i>_{hazard,height,variance,slope_x,slope_y,unknown_reason}.<ext>
//   OUT/frames/<frame>/{fused_hazard,fused_clearance,footprint_hazard,hazard_distance}.<ext>
//   OUT/mosaic/<frame>.png
//   OUT/eval/ (hazmap evaluate: summary.csv, report.html, ...)
//
// Grid files are named by their stem; the writer adds .jdem and/or .tif (output.format),
// PNGs add .png.

#include <filesystem>
#include <string>

namespace hazmap::run_layout {

inline constexpr const char* kRunLog = "run.log";
inline constexpr const char* kSummaryJson = "summary.json";
inline constexpr const char* kViewHtml = "view.html";
inline constexpr const char* kFramesDir = "frames";
inline constexpr const char* kMosaicDir = "mosaic";
inline constexpr const char* kEvalDir = "eval";

/// Stems of the whole-map grids in a frame folder.
inline constexpr const char* kFusedHazard = "fused_hazard";
inline constexpr const char* kFusedClearance = "fused_clearance";
inline constexpr const char* kFootprintHazard = "footprint_hazard";
inline constexpr const char* kHazardDistance = "hazard_distance";

/// "L<i>": layer i's name in file names, summary.json and the viewer.
inline std::string layer_id(std::size_t i) { return "L" + std::to_string(i); }

/// Stem of layer i's grid `quantity` ("hazard", "height", "variance", "slope_x",
/// "slope_y", "unknown_reason"): "L<i>_<quantity>".
inline std::string layer_stem(std::size_t i, const std::string& quantity) {
  return layer_id(i) + "_" + quantity;
}

/// "<stem>.png": a grid's picture beside its grid file.
inline std::string png_file(const std::string& stem) { return stem + ".png"; }

/// "<stem>.jdem": a grid's JDEM file (output.format jdem or both).
inline std::string jdem_file(const std::string& stem) { return stem + ".jdem"; }

/// OUT/frames/<frame>/
inline std::filesystem::path frame_dir(const std::filesystem::path& out_dir,
                                       const std::string& frame) {
  return out_dir / kFramesDir / frame;
}

/// OUT/mosaic/<frame>.png
inline std::filesystem::path mosaic_png(const std::filesystem::path& out_dir,
                                        const std::string& frame) {
  return out_dir / kMosaicDir / (frame + ".png");
}

}  // namespace hazmap::run_layout
