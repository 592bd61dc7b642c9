// File readers, the simulator and the evaluation: what a script needs around a Pipeline.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <spdlog/spdlog.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/sim/simulate.hpp"

namespace hazmap::python {
namespace {

/// SPEC 10 metrics under the key names of metrics.json (run_evaluation.cpp).
py::dict metrics_dict(const eval::MetricSums& sums) {
  const eval::LayerMetrics m = eval::derive_metrics(sums);
  py::dict d;
  d["extent_m2"] = m.extent_area_m2;
  d["known_m2"] = m.known_area_m2;
  d["unknown_fraction"] = m.unknown_fraction;
  d["height_rms_m"] = m.height_rms_m;
  d["height_samples"] = m.height_samples;
  d["gt_hazard_m2"] = m.gt_hazard_area_m2;
  d["gt_hazard_known_m2"] = m.gt_hazard_known_area_m2;
  d["missed_m2"] = m.missed_area_m2;
  d["missed_fraction"] = m.missed_fraction;
  d["missed_of_hazard"] = m.missed_of_hazard;
  d["false_alarm_m2"] = m.false_alarm_area_m2;
  d["false_alarm_fraction"] = m.false_alarm_fraction;
  d["variance_violation"] = m.variance_violation;
  d["hazard_recall"] = m.hazard_recall;
  d["hazard_unknown"] = m.hazard_unknown;
  d["height_rms_all_m"] = m.height_rms_all_m;
  d["height_samples_all"] = m.height_samples_all;
  d["variance_violation_all"] = m.variance_violation_all;
  d["max_below_m"] = m.max_below_m;
  return d;
}

py::dict evaluate(const std::filesystem::path& run_dir, const std::filesystem::path& sequence_dir,
                  const py::object& out_dir, const py::object& near_radius_m,
                  const std::vector<std::string>& error_map_frames, bool write_report) {
  eval::EvaluationOptions options;
  options.run_dir = run_dir;
  options.sequence_dir = sequence_dir;
  // None, not an empty path: pathlib reads "" as ".", the current folder.
  if (!out_dir.is_none()) options.out_dir = out_dir.cast<std::filesystem::path>();
  options.error_map_frames = error_map_frames;
  options.write_report = write_report;
  if (!near_radius_m.is_none()) {
    try {
      options.near_radius_m = near_radius_m.cast<double>();
    } catch (const py::cast_error&) {
      throw py::type_error("near_radius_m: expected a number (metres) or None");
    }
    if (!(options.near_radius_m > 0) || !std::isfinite(options.near_radius_m))
      throw py::value_error("near_radius_m: expected a positive radius in metres");
  }
  eval::RunEvaluation ev;
  {
    py::gil_scoped_release release;
    ev = eval::evaluate_run(options);
  }
  py::list layers;
  for (std::size_t l = 0; l < ev.layers.size(); ++l) {
    const eval::EvaluatedLayer& L = ev.layers[l];
    py::dict d = metrics_dict(ev.pooled[l]);
    d["layer"] = L.name;
    d["resolution_m"] = L.resolution_m;
    d["rule"] = L.rule;
    d["h_min_m"] = L.h_min_m;
    d["h_min_source"] = L.h_min_source;
    if (options.near_enabled()) d["near"] = metrics_dict(ev.near_pooled[l]);
    layers.append(d);
  }
  py::list per_frame;
  for (std::size_t f = 0; f < ev.frames.size(); ++f) {
    py::dict frame;
    for (std::size_t l = 0; l < ev.layers.size(); ++l) frame[ev.layers[l].name.c_str()] = metrics_dict(ev.sums[f][l]);
    per_frame.append(frame);
  }
  py::dict out;
  out["layers"] = layers;
  out["frames"] = ev.frames;
  out["per_frame"] = per_frame;
  out["used_true_poses"] = ev.used_true_poses;
  out["out_dir"] = ev.out_dir;
  return out;
}

}  // namespace

void bind_io_and_eval(py::module_& m) {
  m.def("read_image", [](const std::filesystem::path& path) { return numpy_from_mat(read_image(path)); },
        py::arg("path"), "Reads an image unchanged (8/16-bit, grey or BGR) into a numpy array.");

  m.def("read_jdem", [](const std::filesystem::path& path) {
    JdemGrid g = read_jdem(path);
    py::array_t<float> values({g.rows, g.cols});
    std::copy(g.values.begin(), g.values.end(), values.mutable_data());
    py::dict meta;
    meta["quantity"] = g.quantity;
    meta["units"] = g.units;
    meta["resolution_m"] = g.resolution_m;
    meta["center_m"] = py::make_tuple(g.center_x_m, g.center_y_m);
    meta["yaw_rad"] = g.yaw_rad;
    for (const auto& [key, value] : g.metadata) meta[key.c_str()] = value;
    return py::make_tuple(values, meta);
  }, py::arg("path"), "Reads a JDEM grid (SPEC 9): (float32 rows x cols array, NaN = no data; "
                      "header dict: quantity, units, resolution_m, center_m, yaw_rad, other keys).");

  m.def("load_sequence", [](const std::filesystem::path& dir) {
    const Sequence seq = load_sequence(dir);
    py::list frames;
    for (const SequenceFrame& f : seq.frames) {
      py::dict d;
      d["name"] = f.name;
      d["left"] = f.left_path;
      d["right"] = f.right_path;
      d["t_s"] = f.pose.t_s;
      d["T_W_B"] = numpy_from_pose(f.pose.T_W_B);
      d["noise"] = f.pose.has_noise ? py::object(py::make_tuple(f.pose.noise.sx_m, f.pose.noise.sy_m,
                                                                f.pose.noise.sz_m, f.pose.noise.syaw_rad))
                                    : py::object(py::none());
      frames.append(d);
    }
    py::dict out;
    out["calibration"] = seq.calibration;
    out["frames"] = frames;
    return out;
  }, py::arg("dir"), R"(Loads and checks a sequence folder (SPEC 2) as `hazmap run` does:
{calibration: Calibration, frames: [{name, left, right (paths), t_s, T_W_B (4 x 4),
noise (sx, sy, sz, syaw) or None}]}, frames sorted by name.)");

  m.def("simulate", [](const std::filesystem::path& out_dir, const std::string& scenario, int frames,
                       double scale, std::uint64_t seed, bool ground_truth) {
    sim::SimulationOptions options;
    options.scenario = scenario;
    options.frames = frames;
    options.scale = scale;
    options.seed = seed;
    options.write_ground_truth = ground_truth;
    sim::SimulationSummary s;
    {
      py::gil_scoped_release release;
      s = sim::simulate_sequence(options, out_dir);
    }
    py::dict d;
    d["frames"] = s.frames;
    d["width_px"] = s.width_px;
    d["height_px"] = s.height_px;
    d["rocks"] = s.rocks;
    d["craters"] = s.craters;
    return d;
  }, py::arg("out_dir"), py::arg("scenario") = "rocks", py::arg("frames") = 8, py::arg("scale") = 0.4,
     py::arg("seed") = 1, py::arg("ground_truth") = false,
     R"(Renders a synthetic sequence into out_dir, as `hazmap simulate --scenario S --frames N
--scale X --seed K [--ground-truth]` with every other option at its default (the CLI has
the rest). Returns {frames, width_px, height_px, rocks, craters}.)");

  m.def("evaluate", &evaluate, py::arg("run_dir"), py::arg("sequence_dir"),
        py::arg("out_dir") = py::none(), py::arg("near_radius_m") = py::none(),
        py::arg("error_map_frames") = std::vector<std::string>{}, py::arg("write_report") = true,
        R"(Scores a run folder (the --out of `hazmap run`) against its sequence's ground truth,
as `hazmap evaluate --run RUN --sequence SEQ` (SPEC 10), writing the same files into
out_dir (default RUN/eval). Returns {layers: [metrics of each scored map, pooled over
frames, under metrics.json's keys, plus layer, resolution_m, rule, h_min_m,
h_min_source and, with near_radius_m, near: the metrics within that radius of the
rover], frames: [names], per_frame: [{layer name: metrics}], used_true_poses, out_dir}.)");

  m.def("set_log_level", [](const std::string& level) {
    const auto l = spdlog::level::from_str(level);
    if (l == spdlog::level::off && level != "off")
      throw py::value_error("log level '" + level + "': expected trace, debug, info, warn, error, critical or off");
    spdlog::set_level(l);
  }, py::arg("level"), "The library's log level (it logs through spdlog to stderr/stdout): "
                       "trace, debug, info, warn, error, critical or off.");
}

}  // namespace hazmap::python
