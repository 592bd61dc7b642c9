// hazmap simulate: render a synthetic stereo sequence with ground truth.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/io/output_folder.hpp"
#include "hazmap/sim/simulate.hpp"

namespace hazmap::cli {

namespace {
const char* kSimulateUsage =
    R"(usage: hazmap simulate --scenario NAME --out DIR [--seed N] [--frames N] [--scale S] [options]

Renders a synthetic sequence in the SPEC 2 layout (left/, right/, calibration.yaml,
poses.txt, simulation.yaml): CADRE camera geometry (1600 x 1300, f = 671 px, B = 5 cm,
15 cm above the ground, view top 10 deg above the horizon) at --scale (0.4: 640 x 520).

Scenario and terrain (1 cm detail grid):
  --scenario NAME        flat | ramp | sine | rocks | craters (default rocks)
  --terrain-size M       side of the detail grid in metres (default 8; grown to cover the path)
  --ramp-deg D           ramp angle (ramp; default 15)
  --sine-amplitude M     sine: amplitude (default 0.05), --sine-wavelength M (default 1.0),
  --sine-direction-deg D   direction of the wave from +x (default 0): steepest slope 17.4 deg
  --noise-amplitude M    fractal ground, longest octave (rocks, craters; default 0.015)
Rocks (hemispherical caps; rocks scenario, or any scenario with --scatter-rocks):
  --rock-count N | --rock-count A:B | --rock-density PER_M2
  --rock-radius R | --rock-radius A:B    radius or range in metres (default 0.03:0.08)
  --rock-sizes uniform|power_law          radius distribution (default uniform)
  --rock-exponent Q                       power law N(>r) ~ r^-Q (default 2.5)
  --rock-box X0,X1,Y                      centres in x [X0, X1], |y| <= Y (default 0.25,0.9,0.35)
  --rock-buried F                         burial up to this fraction of the radius (default 0.3)
  --rock-clearance M                      keep rocks this far from the path (default 0: drive through)
  --scatter-rocks                         add the rock field to other scenarios
Craters (craters scenario):
  --crater-count N | A:B | --crater-density PER_M2   (default 5:8)
  --crater-radius R | A:B (default 0.15:0.8), --crater-sizes uniform|power_law (power_law),
  --crater-exponent Q (2), --crater-box X0,X1,Y (0.5,6,2.5),
  --crater-depth F (depth/diameter, 0.1), --crater-rim F (rim height/diameter, 0.02)
Path and poses:
  --step M               horizontal travel per frame (default 0.04)
  --path straight|spline straight along +x, or a C2 spline through seeded random waypoints
  --waypoint-spacing M   spline: distance between waypoints (default 1.0)
  --max-turn-deg D       spline: largest heading change between legs (default 30)
  --wheelbase M, --track M   wheel contacts (default 0.30, 0.25): body height, roll and pitch
                         come from the plane through the ground under them (rocks ignored)
  --drift F              poses.txt drifts by F x distance travelled (true poses in
                         poses_true.txt); --drift-direction-deg D (default: random from the seed)
Cameras and rendering:
  --distort              typical wide-angle distortion (-0.08, 0.012, 4e-4, -3e-4, 0)
  --distortion K1,K2,P1,P2,K3   explicit distortion of both lenses
  --misalign             right camera 0.3,-0.2,0.4 deg and 0.5,-0.3,0.4 mm off
  --misalignment R,P,Y,X,Y,Z    explicit (deg, m); either makes calibration.yaml unrectified
  --samples N            rays per pixel and axis (default 2)
  --noise-sigma DN       image noise (default 1), --no-sun: no Lambertian sun shading
Outputs:
  --ground-truth         gt_height.jdem and gt_hazard.jdem over the path +- --gt-margin M (2)
  --depth                depth/<name>.tiff: float32 Z [m] in the left camera, NaN sky
  --overwrite            DIR may hold an earlier hazmap simulate output: left/, right/,
                         depth/, calibration.yaml, simulation.yaml, poses.txt,
                         poses_true.txt, gt_height.jdem, gt_hazard.jdem. They are removed
                         (after every option is checked) before the first file is written,
                         so no file of the earlier sequence survives. DIR must otherwise be
                         absent or empty; a folder holding anything else (or a sequence
                         without simulation.yaml) is refused and left untouched.
  --quiet
)";

// "a,b,c" -> numbers; exactly `count` of them.
std::vector<double> numbers(const Args& args, const std::string& flag, std::size_t count) {
  std::vector<double> values;
  std::stringstream in(args.get(flag));
  for (std::string item; std::getline(in, item, ',');) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw UsageError("--" + flag + ": '" + item + "' is not a number");
    values.push_back(v);
  }
  if (values.size() != count)
    throw UsageError("--" + flag + " expects " + std::to_string(count) +
                     " comma-separated numbers");
  return values;
}

// "N" or "A:B" -> [lo, hi].
void range(const Args& args, const std::string& flag, double& lo, double& hi) {
  const std::string text = args.get(flag);
  const auto colon = text.find(':');
  auto parse = [&](const std::string& item) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw UsageError("--" + flag + ": expected N or A:B, got '" + text + "'");
    return v;
  };
  lo = parse(text.substr(0, colon));
  hi = colon == std::string::npos ? lo : parse(text.substr(colon + 1));
}

void int_range(const Args& args, const std::string& flag, int& lo, int& hi) {
  double a = 0, b = 0;
  range(args, flag, a, b);
  if (a != std::floor(a) || b != std::floor(b) || a < 0 || b > 1e6)
    throw UsageError("--" + flag + " expects whole numbers");
  lo = static_cast<int>(a);
  hi = static_cast<int>(b);
}

/// The flags a rock field and a crater field share (--PREFIX-count, -density, -radius,
/// -sizes, -exponent, -box); both option structs name these members alike.
template <class Field>
void parse_field_flags(const Args& args, const std::string& prefix, Field& field) {
  const std::string p = prefix + "-";
  if (args.has(p + "count")) int_range(args, p + "count", field.min_count, field.max_count);
  if (args.has(p + "density")) field.density_per_m2 = args.number(p + "density");
  if (args.has(p + "radius")) range(args, p + "radius", field.min_radius_m, field.max_radius_m);
  if (args.has(p + "sizes"))
    field.size_distribution =
        sim::parse_size_distribution(args.get(p + "sizes"), "--" + p + "sizes");
  if (args.has(p + "exponent")) field.power_law_exponent = args.number(p + "exponent");
  if (args.has(p + "box")) {
    const auto box = numbers(args, p + "box", 3);
    field.min_x_m = box[0];
    field.max_x_m = box[1];
    field.max_abs_y_m = box[2];
  }
}

}  // namespace

int cmd_simulate(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kSimulateUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(
      argc, argv,
      {"scenario", "out", "seed", "frames", "scale", "step", "ramp-deg", "samples", "noise-sigma",
       "gt-margin", "terrain-size", "sine-amplitude", "sine-wavelength", "sine-direction-deg",
       "noise-amplitude", "rock-count", "rock-density", "rock-radius", "rock-sizes",
       "rock-exponent", "rock-box", "rock-buried", "rock-clearance", "crater-count",
       "crater-density", "crater-radius", "crater-sizes", "crater-exponent", "crater-box",
       "crater-depth", "crater-rim", "path", "waypoint-spacing", "max-turn-deg", "wheelbase",
       "track", "drift", "drift-direction-deg", "distortion", "misalignment"},
      {"ground-truth", "no-sun", "quiet", "depth", "scatter-rocks", "distort", "misalign",
       "overwrite"});
  hazmap::sim::SimulationOptions options;
  options.scenario = args.get("scenario", options.scenario);
  const std::filesystem::path out = args.required("out");
  // Whole numbers range-checked before the cast: 2^53 is the largest seed a double given
  // on the command line holds exactly; simulate accepts 1 to 100000 frames.
  if (args.has("seed"))
    options.seed = static_cast<std::uint64_t>(args.whole("seed", 0, 9007199254740992LL));
  if (args.has("frames")) options.frames = static_cast<int>(args.whole("frames", 1, 100000));
  if (args.has("scale")) options.scale = args.number("scale");
  if (args.has("step")) options.step_m = args.number("step");
  if (args.has("samples"))
    options.render.samples_per_axis = static_cast<int>(args.whole("samples", 1, 8));
  if (args.has("noise-sigma")) options.render.noise_sigma_dn = args.number("noise-sigma");
  if (args.has("gt-margin")) options.ground_truth_margin_m = args.number("gt-margin");
  options.render.sun_shading = !args.on("no-sun");
  options.write_ground_truth = args.on("ground-truth");
  options.write_depth = args.on("depth");

  // Terrain.
  if (args.has("terrain-size")) options.terrain_size_m = args.number("terrain-size");
  if (args.has("ramp-deg")) options.ramp_deg = args.number("ramp-deg");
  if (args.has("sine-amplitude")) options.sine.amplitude_m = args.number("sine-amplitude");
  if (args.has("sine-wavelength")) options.sine.wavelength_m = args.number("sine-wavelength");
  if (args.has("sine-direction-deg"))
    options.sine.direction_rad = args.number("sine-direction-deg") * M_PI / 180.0;
  if (args.has("noise-amplitude")) options.ground_noise.amplitude_m = args.number("noise-amplitude");

  parse_field_flags(args, "rock", options.rock_field);
  if (args.has("rock-buried")) options.rock_field.max_buried_fraction = args.number("rock-buried");
  if (args.has("rock-clearance")) options.rock_path_clearance_m = args.number("rock-clearance");
  options.scatter_rocks = args.on("scatter-rocks");

  parse_field_flags(args, "crater", options.crater_field);
  if (args.has("crater-depth")) options.crater_field.depth_ratio = args.number("crater-depth");
  if (args.has("crater-rim")) options.crater_field.rim_ratio = args.number("crater-rim");

  // Path and poses.
  options.path.kind = args.get("path", options.path.kind);
  if (args.has("waypoint-spacing")) options.path.waypoint_spacing_m = args.number("waypoint-spacing");
  if (args.has("max-turn-deg")) options.path.max_turn_deg = args.number("max-turn-deg");
  if (args.has("wheelbase")) options.wheels.wheelbase_m = args.number("wheelbase");
  if (args.has("track")) options.wheels.track_m = args.number("track");
  if (args.has("drift")) options.drift.fraction = args.number("drift");
  if (args.has("drift-direction-deg"))
    options.drift.direction_deg = args.number("drift-direction-deg");

  // Camera errors.
  if (args.on("distort")) options.rig_errors.distortion = sim::RigErrors::typical_distortion();
  if (args.has("distortion")) {
    const auto d = numbers(args, "distortion", 5);
    for (std::size_t i = 0; i < 5; ++i) options.rig_errors.distortion[i] = d[i];
  }
  if (args.on("misalign")) {
    options.rig_errors.misalignment_rpy_deg = sim::RigErrors::typical_misalignment_rpy_deg();
    options.rig_errors.misalignment_m = sim::RigErrors::typical_misalignment_m();
  }
  if (args.has("misalignment")) {
    const auto m = numbers(args, "misalignment", 6);
    options.rig_errors.misalignment_rpy_deg = Eigen::Vector3d(m[0], m[1], m[2]);
    options.rig_errors.misalignment_m = Eigen::Vector3d(m[3], m[4], m[5]);
  }

  // Files of two sequences never mix in one folder (a stale poses_true.txt would be read
  // as this sequence's true poses): the rule of hazmap run's OUT, for what simulate writes.
  const hazmap::OutputFolder out_folder =
      hazmap::inspect_output_folder(out, hazmap::OutputOwner::simulate);
  const std::string refusal = hazmap::output_folder_refusal(out_folder, args.on("overwrite"));
  if (!refusal.empty()) throw UsageError(refusal);

  setup_logging({}, args.on("quiet"));
  spdlog::info("simulating scenario '{}' (seed {}, {} frames, scale {}, {} path) into {}",
               options.scenario, options.seed, options.frames, options.scale, options.path.kind,
               out.string());
  options.log_progress = true;  // frame i/n, rate, time left (silenced by --quiet)
  const sim::SimulationSummary summary = hazmap::sim::simulate_sequence(
      options, out, [&] { hazmap::clear_output_folder(out_folder); });  // every check passed
  spdlog::info("done: {} frames of {}x{} px ({} rocks, {} craters) in {}; rendering {:.2f} s "
               "per frame (both cameras)",
               summary.frames, summary.width_px, summary.height_px, summary.rocks,
               summary.craters, out.string(), summary.render_seconds / summary.frames);
  return 0;
}

}  // namespace hazmap::cli
