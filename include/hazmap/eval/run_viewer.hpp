#pragma once
// `hazmap view`: one static HTML page to look at a run (the OUT of `hazmap run`) in a
// browser, opened from disk: no server, no network, no file beside it. It holds
//   - every written frame's grids, exactly (embedded_grids.hpp): per layer the hazard
//     classes, heights, variances and, for CCM, the cell planes' slopes; the fused hazard
//     map with its clearance and the footprint map. hazard_distance.jdem is left out: it
//     is dense and would make the page ten times larger (it follows from the fused map);
//   - the rover's path and pose per processed frame (summary.json "T_W_B"; runs older than
//     that record: the poses.txt of the sequence summary.json names, when it is there);
//   - summary.json's per-frame numbers (points, stage times, areas per layer), the
//     warnings and errors of run.log and the configuration used;
//   - when RUN/eval/metrics.json exists (`hazmap evaluate` with its default --out), the
//     metrics per layer, metrics.csv's per-frame values and the errors_<frame>.png maps.
// The page's script draws the grids with colour maps over robust ranges (heights and
// sigmas as the run's height PNGs: output.png_height_clip_pct percent cut from each end,
// per frame or the widest over the run), pans and zooms with a metric scale bar, reads
// out a cell's values under the pointer in every map, and plays the frames. view.html#frame=N (a frame's name,
// else its position from 0) opens at a frame.
//
// Inputs are checked before anything is written: a folder without summary.json, a
// damaged or missing grid, a grid whose size disagrees with its layer's other grids all
// throw Error naming the file, and the page is written atomically, so a failure never
// leaves a partial view.html (nor replaces an earlier one).

#include <cstddef>
#include <filesystem>
#include <string>

namespace hazmap::eval {

/// At most this many warning and error lines of run.log go into the page (the last
/// ones): run.log is appended to by every run into the folder.
constexpr std::size_t kMaxLogLines = 200;

struct ViewerOptions {
  std::filesystem::path run_dir;
  std::filesystem::path out_file;  ///< empty: RUN/view.html
};

/// What went into the page, for the command's report.
struct ViewerReport {
  std::filesystem::path out_file;
  std::size_t page_bytes = 0;
  std::size_t frames = 0;          ///< written frames on the page
  std::size_t frames_processed = 0;
  std::size_t maps = 0;            ///< layers + fused (+ footprint)
  std::size_t grid_bytes = 0;      ///< the grids' values before compression
  std::size_t grid_text_bytes = 0; ///< the same as embedded (deflate + base64)
  bool with_poses = false;
  bool with_evaluation = false;
};

/// The page for `run_dir` and what it holds, without writing anything. Throws Error,
/// one line naming the file, on input that is not a complete run.
std::string render_run_viewer(const std::filesystem::path& run_dir, ViewerReport* report = nullptr);

/// render_run_viewer, then written atomically to options.out_file (default
/// RUN/view.html). Throws Error as render_run_viewer does, or naming the output file.
ViewerReport write_run_viewer(const ViewerOptions& options);

}  // namespace hazmap::eval
