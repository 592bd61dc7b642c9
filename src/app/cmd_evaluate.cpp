// hazmap evaluate: score a run against ground truth (SPEC 10), or summarise a sweep.

#include <cmath>
#include <cstdio>
#include <sstream>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/eval/metrics.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "hazmap/eval/sweep_summary.hpp"

namespace hazmap::cli {

namespace {
const char* kEvaluateUsage =
    R"(usage: hazmap evaluate --run DIR --sequence DIR [--out DIR] [--near R] [--error-maps FRAMES] [--quiet]
       hazmap evaluate --sweep DIR [--out DIR] [--quiet]

Scores every written frame and layer of a run (the OUT of hazmap run) against the
sequence's ground truth (gt_height.jdem, gt_hazard.jdem from hazmap simulate
--ground-truth; SPEC 10): height RMS (CCM on the sub-cell plane), missed-obstacle and
false-alarm area and fraction, unknown fraction, hazard recall (share of the obstacles
>= h_min labelled hazard) and hazard unknown (share labelled unknown), variance
violations; height RMS and variance violations also over every published height
(*_all: cells of unknown class included). Layers are L0, L1, ... (h_min: the layer's,
as the pipeline resolves it), "fused" and "footprint" (h_min: hazard.critical_height;
footprint only when the run wrote footprint_hazard.jdem). When the sequence
has poses_true.txt (simulate --drift), the ground truth is placed into each frame's map
frame with T_map_W = T_W_B(drifted) T_W_B(true)^-1.
The run must have been made from this sequence: the poses fingerprint in RUN/summary.json
must equal that of SEQ/poses.txt (all its poses, so runs of --frames A:B match), else one
line names both folders (exit 1); a run older than the fingerprint gets a warning.
Writes into --out (default RUN/eval): metrics.csv (frame x layer), summary.csv and
metrics.json (per layer, pooled over frames), metrics_over_time.png, errors_<frame>.png
and report.html (static; open it in a browser).
  --near R         also score the hazard metrics over the ground-truth pixels within R
                   metres of the rover's true position in each frame (poses_true.txt, else
                   poses.txt): extra columns/keys near_extent_m2, near_known_m2,
                   near_gt_hazard_m2, near_hazard_recall, near_hazard_unknown,
                   near_missed_m2, near_missed_fraction, near_missed_of_hazard,
                   near_false_alarm_m2, near_false_alarm_fraction
  --error-maps F   frames that get an error map: NAME[,NAME...] or all (default: the last)

--sweep DIR reads DIR/sweep.tsv (written by tools/sweep.sh) and every run's evaluation,
and writes tables (CSV, tables.md), heat maps and charts and report.html into --out
(default DIR/summary).
)";

std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string pct(double v) {
  char buf[32];
  if (!(v == v)) return "-";
  std::snprintf(buf, sizeof buf, "%.2f %%", 100.0 * v);
  return buf;
}

/// A length in mm, or "none" when undefined (no known cell over the ground truth).
std::string mm(double metres) {
  char buf[32];
  if (!std::isfinite(metres)) return "none";
  std::snprintf(buf, sizeof buf, "%.2f mm", 1000.0 * metres);
  return buf;
}

}  // namespace

int cmd_evaluate(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kEvaluateUsage, stdout);
    return kExitOk;
  }
  const Args args =
      parse_args(argc, argv, {"run", "sequence", "out", "error-maps", "sweep", "near"}, {"quiet"});
  setup_logging({}, args.on("quiet"));
  if (args.has("sweep")) {
    if (args.has("run") || args.has("sequence") || args.has("near"))
      throw UsageError("--sweep cannot be combined with --run, --sequence or --near");
    const std::filesystem::path sweep = args.get("sweep");
    const std::filesystem::path out = args.get("out", (sweep / "summary").string());
    const int runs = hazmap::eval::summarize_sweep(sweep, out);
    spdlog::info("summarised {} evaluated runs into {} (report.html, tables.md)", runs, out.string());
    return kExitOk;
  }
  hazmap::eval::EvaluationOptions options;
  options.run_dir = args.required("run");
  options.sequence_dir = args.required("sequence");
  options.out_dir = args.get("out");
  options.error_map_frames = comma_list(args.get("error-maps"));
  if (args.has("near")) {
    options.near_radius_m = args.number("near");
    if (!(options.near_radius_m > 0.0) || !std::isfinite(options.near_radius_m))
      throw UsageError("--near: expected a positive radius in metres, got '" + args.get("near") +
                       "'");
  }
  const hazmap::eval::RunEvaluation ev = hazmap::eval::evaluate_run(options);
  for (size_t l = 0; l < ev.layers.size(); ++l) {
    const auto m = hazmap::eval::derive_metrics(ev.pooled[l]);
    spdlog::info("{:>5} {:>5.0f} cm {:<5} h_min {:>4.1f} cm: RMS {:>10}, unknown {:>8}, "
                 "missed {:.4f} m2 ({} of obstacles), false alarm {:.4f} m2 ({} of known), "
                 "recall {}",
                 ev.layers[l].name, ev.layers[l].resolution_m * 100, ev.layers[l].rule,
                 ev.layers[l].h_min_m * 100, mm(m.height_rms_m), pct(m.unknown_fraction),
                 m.missed_area_m2, pct(m.missed_of_hazard), m.false_alarm_area_m2,
                 pct(m.false_alarm_fraction), pct(m.hazard_recall));
  }
  spdlog::info("wrote metrics.csv, summary.csv, metrics.json, PNGs and report.html into {}",
               ev.out_dir.string());
  return kExitOk;
}

}  // namespace hazmap::cli
