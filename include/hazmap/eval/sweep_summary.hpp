#pragma once
// Tables, figures and a report over many evaluated runs (`hazmap evaluate --sweep DIR`,
// driven by tools/sweep.sh). The sweep folder holds a manifest, sweep.tsv, with a header
// line and one tab-separated line per run:
//   experiment  map  scenario  radius_m  drift  run_dir
// experiment: "sizes" (obstacle-size sweep), "craters" (height precision) or "drift";
// map: the config's stem (thesis_pwc, thesis_ccm, ...); radius_m / drift: the swept value
// (or "-"); run_dir: the run's OUT, relative to the sweep folder or absolute, whose
// eval/summary.csv `hazmap evaluate` wrote. Runs whose summary is missing (a failed job)
// are reported and left out.
//
// Written into the output folder:
//   missed_by_size_<map>.csv/.png               missed-obstacle fraction, layer x radius
//   known_obstacle_by_size_<map>.csv/.png       share of the obstacle area the layer knows
//   false_alarm_by_size_<map>.csv/.png          false-alarm fraction, layer x radius
//   detectable_size.csv                         per map and layer: smallest radius from
//                                               which every larger radius is found
//   craters_rms.csv, craters_rms.png            height RMS by layer and cell size
//   drift.csv, drift_missed_<map>.png, drift_false_alarm_<map>.png   layers against drift
//   tables.md                                   every table in Markdown (for docs/evaluation.md)
//   report.html                                 all of it on one static page

#include <filesystem>
#include <string>
#include <vector>

namespace hazmap::eval {

/// A layer counts as detecting obstacles of a radius when it misses at most this fraction
/// of their known area (pooled over the run's frames).
constexpr double kDetectedMissedFraction = 0.05;

struct SweepEntry {
  std::string experiment;
  std::string map;
  std::string scenario;
  double radius_m = 0.0;  ///< NaN when not swept
  double drift = 0.0;     ///< NaN when not swept
  std::filesystem::path run_dir;
};

/// Reads SWEEP/sweep.tsv; relative run_dirs are resolved against the sweep folder.
/// Throws Error naming the file and line on a malformed manifest.
std::vector<SweepEntry> read_sweep_manifest(const std::filesystem::path& sweep_dir);

/// Writes everything listed above into out_dir (created). Returns the number of runs
/// that had an evaluation. Throws Error if none had.
int summarize_sweep(const std::filesystem::path& sweep_dir, const std::filesystem::path& out_dir);

}  // namespace hazmap::eval
