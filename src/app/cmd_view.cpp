// hazmap view: one self-contained HTML page to look at a run in a browser.

#include <cstdio>
#include <string>
#include <vector>

#include "cli.hpp"
#include "hazmap/eval/run_viewer.hpp"

namespace hazmap::cli {

namespace {
const char* kViewUsage =
    R"(usage: hazmap view RUN [--out FILE] [--quiet]

Writes one static HTML page (default RUN/view.html, written atomically) that shows the
run in any browser, opened from disk: no server, no network, nothing beside it. Per
written frame it holds every layer's hazard classes, heights and variances (CCM: the cell
planes), the fused and footprint maps, exactly as the frame's grids (JDEM or GeoTIFF) hold
them; the rover's path and pose; summary.json's per-frame points, stage times and areas;
and, when RUN/eval/metrics.json exists (hazmap evaluate), the metrics and error maps.
In the page: a frame slider and play button, hazard / height / sigma per layer with
colours over the height PNGs' robust range (output.png_height_clip_pct), wheel to zoom,
drag to pan (views linked), a metric scale bar, the values of every map under the
pointer. view.html#frame=N opens at
frame N (a name, or a position from 0).
  --out FILE   where to write the page (default RUN/view.html)
  --quiet      no line about the page written (errors only)
)";
}  // namespace

int cmd_view(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kViewUsage, stdout);
    return kExitOk;
  }
  std::vector<std::string> positional;
  const Args args = parse_args(argc, argv, {"out"}, {"quiet"}, &positional);
  if (positional.size() != 1) throw UsageError("view needs one RUN folder");
  hazmap::eval::ViewerOptions options;
  options.run_dir = positional[0];
  if (args.has("out")) options.out_file = args.required("out");
  const hazmap::eval::ViewerReport r = hazmap::eval::write_run_viewer(options);
  if (args.on("quiet")) return kExitOk;
  std::printf("wrote %s: %.1f MB, %zu frames (of %zu processed), %zu maps, grids %.1f MB "
              "packed into %.1f MB%s%s\n",
              r.out_file.string().c_str(), static_cast<double>(r.page_bytes) / 1e6, r.frames,
              r.frames_processed, r.maps, static_cast<double>(r.grid_bytes) / 1e6,
              static_cast<double>(r.grid_text_bytes) / 1e6,
              r.with_evaluation ? ", with the evaluation" : "",
              r.with_poses ? "" : ", no poses (no path drawn)");
  return kExitOk;
}

}  // namespace hazmap::cli
