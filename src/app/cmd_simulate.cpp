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
15 cm above the ground, view top 10 deg above the horizon) at --scale (0.4: 640 x 520),
or the POLAR Traverse pair (--rig polar).

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
  --rig cadre|polar      camera pair: CADRE (default) or POLAR Traverse (2048 x 2048 at
                         scale 1, f = 1457 px, B = 0.40 m, 1.30 m up, 28 deg down)
  --samples N            rays per pixel and axis (default 2)
  --noise-sigma DN       read noise (default 1), --no-sun: no Lambertian sun shading
  --gain G[,G_RIGHT]     camera gain (default 1); --exposure E[,E_RIGHT] relative exposure (1);
  --offset-dn D[,D_RIGHT]  black level (0). One value: both cameras; two: left, right
  --electrons-per-dn E   shot noise: variance signal / E DN^2 (default 0: none)
  --vignetting F         brightness falls by F at the image corners (default 0)
  --bits 8|12            quantisation (12: 16-bit PNG holding value x 16; default 8)
  --row-offset-px P      residual row offset after rectification: y_left - y_right (0)
Light and surface:
  --sun-elevation-deg D  (default 30), --sun-azimuth-deg D from +x towards +y (default 110)
  --lunar-polar-light    preset: sun 8 deg up, ground shadows, no ambient, regolith albedo,
                         opposition surge 0.3 (options given with it override its values)
  --terrain-shadows      shadows of the ground (craters, ridges) too, traced towards the sun
  --ambient A            fraction of light reaching shadows (default 0.25; Moon: ~0)
  --albedo value_noise|regolith   texture model (default value_noise: strong at every scale)
  --albedo-contrast C    relative std of the albedo (value_noise 0.45, regolith 0.05)
  --albedo-correlation M regolith: shortest wavelength with contrast (default 0.05 m)
  --opposition-surge A   brighter by 1 + A exp(-phase / width) (default 0), --opposition-width-deg W (6)
  --noise-octaves N, --noise-wavelength M, --noise-gain G   fractal ground relief (5, 2.0, 0.5)
  --terrain-resolution M detail grid spacing (default 0.01)
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

/// Terrain: ramp, sine, fractal ground, rock and crater fields.
void parse_terrain_flags(const Args& args, sim::SimulationOptions& options) {
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
}

/// Path and poses: the route, the wheel contacts and the drift of poses.txt.
void parse_path_flags(const Args& args, sim::SimulationOptions& options) {
  options.path.kind = args.get("path", options.path.kind);
  if (args.has("waypoint-spacing")) options.path.waypoint_spacing_m = args.number("waypoint-spacing");
  if (args.has("max-turn-deg")) options.path.max_turn_deg = args.number("max-turn-deg");
  if (args.has("wheelbase")) options.wheels.wheelbase_m = args.number("wheelbase");
  if (args.has("track")) options.wheels.track_m = args.number("track");
  if (args.has("drift")) options.drift.fraction = args.number("drift");
  if (args.has("drift-direction-deg"))
    options.drift.direction_deg = args.number("drift-direction-deg");
}

/// Camera errors: lens distortion and right-camera misalignment.
void parse_rig_error_flags(const Args& args, sim::SimulationOptions& options) {
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
}

/// Light, surface, ground relief and the camera pair (the preset first; explicit options
/// override it).
void parse_light_and_surface_flags(const Args& args, sim::SimulationOptions& options) {
  options.rig = args.get("rig", options.rig);
  if (args.on("lunar-polar-light")) sim::apply_lunar_polar_light(options.render);
  if (args.has("sun-elevation-deg"))
    options.render.sun_elevation_deg = args.number("sun-elevation-deg");
  if (args.has("sun-azimuth-deg")) options.render.sun_azimuth_deg = args.number("sun-azimuth-deg");
  if (args.on("terrain-shadows")) options.render.terrain_shadows = true;
  if (args.has("ambient")) options.render.ambient = args.number("ambient");
  if (args.has("albedo"))
    options.render.albedo_model = sim::parse_albedo_model(args.get("albedo"), "--albedo");
  if (args.has("albedo-contrast")) {
    (options.render.albedo_model == sim::AlbedoModel::regolith ? options.render.regolith_contrast
                                                               : options.render.texture_contrast) =
        args.number("albedo-contrast");
  }
  if (args.has("albedo-correlation"))
    options.render.regolith_correlation_m = args.number("albedo-correlation");
  if (args.has("opposition-surge")) options.render.opposition_surge = args.number("opposition-surge");
  if (args.has("opposition-width-deg"))
    options.render.opposition_width_deg = args.number("opposition-width-deg");
  if (args.has("noise-octaves"))
    options.ground_noise.octaves = static_cast<int>(args.whole("noise-octaves", 0, 12));
  if (args.has("noise-wavelength")) options.ground_noise.wavelength_m = args.number("noise-wavelength");
  if (args.has("noise-gain")) options.ground_noise.gain = args.number("noise-gain");
  if (args.has("terrain-resolution"))
    options.terrain_resolution_m = args.number("terrain-resolution");
}

/// The cameras' response, per camera ("V" for both or "L,R"), and quantisation.
void parse_camera_response_flags(const Args& args, sim::SimulationOptions& options) {
  auto per_camera = [&](const std::string& flag, double sim::CameraResponse::*member) {
    if (!args.has(flag)) return;
    const bool two = args.get(flag).find(',') != std::string::npos;
    const auto v = numbers(args, flag, two ? 2 : 1);
    options.left_response.*member = v[0];
    options.right_response.*member = v[two ? 1 : 0];
  };
  per_camera("gain", &sim::CameraResponse::gain);
  per_camera("exposure", &sim::CameraResponse::exposure);
  per_camera("offset-dn", &sim::CameraResponse::offset_dn);
  per_camera("electrons-per-dn", &sim::CameraResponse::electrons_per_dn);
  per_camera("vignetting", &sim::CameraResponse::vignetting);
  if (args.has("bits")) {
    const int bits = static_cast<int>(args.whole("bits", 8, 12));
    if (bits != 8 && bits != 12) throw UsageError("--bits expects 8 or 12");
    options.left_response.bits = options.right_response.bits = bits;
  }
  if (args.has("row-offset-px")) options.row_offset_px = args.number("row-offset-px");
}

/// Every option of the command line but --out, in the order they were always read (an
/// error names the first bad one).
sim::SimulationOptions simulation_options(const Args& args) {
  sim::SimulationOptions options;
  options.scenario = args.get("scenario", options.scenario);
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

  parse_terrain_flags(args, options);
  parse_path_flags(args, options);
  parse_rig_error_flags(args, options);
  parse_light_and_surface_flags(args, options);
  parse_camera_response_flags(args, options);
  return options;
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
       "track", "drift", "drift-direction-deg", "distortion", "misalignment", "rig", "gain",
       "exposure", "offset-dn", "electrons-per-dn", "vignetting", "bits", "row-offset-px",
       "sun-elevation-deg", "sun-azimuth-deg", "ambient", "albedo", "albedo-contrast",
       "albedo-correlation", "opposition-surge", "opposition-width-deg", "noise-octaves",
       "noise-wavelength", "noise-gain", "terrain-resolution"},
      {"ground-truth", "no-sun", "quiet", "depth", "scatter-rocks", "distort", "misalign",
       "overwrite", "lunar-polar-light", "terrain-shadows"});
  const std::filesystem::path out = args.required("out");
  sim::SimulationOptions options = simulation_options(args);

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
