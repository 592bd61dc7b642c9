// hazmap stereo: rectified images, disparity and point clouds per frame.

#include <cstdio>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/euroc.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/output_folder.hpp"
#include "hazmap/io/ply.hpp"
#include "hazmap/io/run_layout.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/rig_geometry.hpp"
#include "hazmap/stereo/band_matcher.hpp"
#include "hazmap/stereo/disparity_image.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"

namespace hazmap::cli {

namespace {
const char* kStereoUsage =
    R"(usage: hazmap stereo --config FILE --sequence DIR --out DIR [--frames A:B]
                     [--set KEY=VALUE]... [--overwrite] [--quiet]
                     [--poses CSV] [--pose-frame body|left_camera] [--max-pose-gap SECONDS]

Runs the stereo front end (SPEC 3-4: grey, rectify, StereoBM/SGBM, points with
covariance) on a sequence and writes, per frame, OUT/frames/<frame>/:
  left_rect.png, right_rect.png   rectified 8-bit grey images
  disparity.png                   16-bit, disparity x 16, 0 = invalid
  disparity_color.png             false colour (turbo, red near), black = invalid
  cloud.ply                       world-frame points, binary PLY with per-vertex
                                  covariance cov_xx..cov_zz [m^2] and grey colour
plus OUT/stereo_summary.json (per-frame points and stage timings) and OUT/run.log.
DIR is a sequence folder (SPEC 2) or an ASL/EuRoC folder (mav0/cam0, mav0/cam1), read
directly; EuRoC frames take their poses from --poses, else from
mav0/state_groundtruth_estimate0 when present, else the identity (said as a warning; the
cloud is then in EuRoC's body frame).
  --frames A:B   frame indices [A, B) of the sorted frames
  --poses CSV, --pose-frame body|left_camera, --max-pose-gap SECONDS
                 an EuRoC folder's poses, as for hazmap run
  --set K=V      override a YAML key, e.g. --set stereo.matcher=sgbm
  --overwrite    OUT may hold an earlier hazmap output (as for hazmap run): removed
                 before the first frame; OUT must otherwise be absent or empty, and a
                 folder holding anything else is refused and left untouched
  --quiet        no per-frame progress on the terminal
)";

std::string json_number(double v) { return printf_double(v, "%.4f"); }

/// Buffers reused from frame to frame.
struct FrameImages {
  cv::Mat disparity_u16, disparity_bgr;
  std::vector<std::uint8_t> grey;
};

/// OUT/frames/<frame>/: the rectified pair, the disparity (16-bit and false colour) and
/// the cloud with each point's grey value.
void write_frame_files(const hazmap::StereoFrontEnd& front_end, const hazmap::Config& config,
                       const std::filesystem::path& dir, const std::string& name,
                       FrameImages& images) {
  hazmap::write_png(dir / "left_rect.png", front_end.rectified_left());
  hazmap::write_png(dir / "right_rect.png", front_end.rectified_right());
  const int invalid = front_end.matcher().invalid_below();
  hazmap::disparity_to_u16(front_end.disparity_x16(), invalid, images.disparity_u16);
  hazmap::write_png(dir / "disparity.png", images.disparity_u16);
  hazmap::colorize_disparity(front_end.disparity_x16(), invalid,
                             front_end.matcher().min_disparity(),
                             front_end.matcher().num_disparities(), images.disparity_bgr);
  hazmap::write_png(dir / "disparity_color.png", images.disparity_bgr);
  images.grey.clear();
  for (const cv::Point& p : front_end.pixels())
    images.grey.push_back(front_end.rectified_left().at<std::uint8_t>(p));
  hazmap::write_ply(dir / "cloud.ply", front_end.cloud(), &images.grey,
                    {"hazmap stereo, frame " + name,
                     "frame W (world); covariance cov_* in m^2, SPEC 4 sensor model " +
                         std::string(hazmap::enum_name(config.sensor.model))});
}

/// The run's first lines: what runs on what, the rectified geometry and the matcher; the
/// whole configuration to run.log only.
void log_run_start(const hazmap::StereoFrontEnd& front_end, const hazmap::Config& config,
                   const std::filesystem::path& config_path,
                   const std::filesystem::path& sequence_dir,
                   const std::filesystem::path& out_dir, size_t frames) {
  const hazmap::StereoGeometry& g = front_end.rectifier().geometry();
  const cv::Rect region = front_end.builder().region();
  spdlog::info("hazmap {} stereo: config {}, sequence {}, out {}, {} frames", HAZMAP_VERSION,
               config_path.string(), sequence_dir.string(), out_dir.string(), frames);
  spdlog::info("rectified: f {:.2f} px, B {:.4f} m, c ({:.1f}, {:.1f}) px, points from x {} y {} "
               "w {} h {}; matcher {}, search {}, {} disparities",
               g.focal_px, g.baseline_m, g.cx_px, g.cy_px, region.x, region.y, region.width,
               region.height, hazmap::enum_name(config.stereo.matcher),
               hazmap::enum_name(config.stereo.search),
               config.stereo.num_disparities);
  if (const hazmap::BandMatcher* band = front_end.matcher().band())
    spdlog::info("ground band: {}", hazmap::describe_strips(band->strips()));
  log_to_file_only("configuration in use:\n" + hazmap::to_yaml(config));
}

/// One element of stereo_summary.json's per_frame array.
std::string frame_json(const std::string& name, size_t points, const hazmap::StereoTimes& t) {
  return "    {\"frame\": \"" + name + "\", \"points\": " + std::to_string(points) +
         ", \"grey_ms\": " + json_number(t.grey_ms) +
         ", \"rectify_ms\": " + json_number(t.rectify_ms) +
         ", \"disparity_ms\": " + json_number(t.disparity_ms) +
         ", \"points_ms\": " + json_number(t.points_ms) + "}";
}

/// OUT/stereo_summary.json: totals, the rectified geometry, mean stage times and the
/// per-frame elements.
std::string summary_json(size_t frames, size_t points_total, const hazmap::Config& config,
                         const hazmap::StereoGeometry& g, const hazmap::StereoTimes& sum,
                         const std::string& per_frame) {
  const double n = static_cast<double>(frames);
  return "{\n  \"frames\": " + std::to_string(frames) +
         ",\n  \"points\": " + std::to_string(points_total) +
         ",\n  \"matcher\": \"" + std::string(hazmap::enum_name(config.stereo.matcher)) + "\"" +
         ",\n  \"focal_px\": " + json_number(g.focal_px) +
         ",\n  \"baseline_m\": " + json_number(g.baseline_m) +
         ",\n  \"mean_ms\": {\"grey\": " + json_number(sum.grey_ms / n) +
         ", \"rectify\": " + json_number(sum.rectify_ms / n) +
         ", \"disparity\": " + json_number(sum.disparity_ms / n) +
         ", \"points\": " + json_number(sum.points_ms / n) +
         ", \"total\": " + json_number(sum.total() / n) + "}" +
         ",\n  \"per_frame\": [\n" + per_frame + "\n  ]\n}\n";
}

}  // namespace

int cmd_stereo(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kStereoUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(argc, argv,
                               {"config", "sequence", "out", "frames", "poses", "pose-frame",
                                "max-pose-gap"},
                               {"quiet", "overwrite"});
  const std::filesystem::path config_path = args.required("config");
  const std::filesystem::path sequence_dir = args.required("sequence");
  const std::filesystem::path out_dir = args.required("out");
  // The same rule as hazmap run's: frames of two runs never mix in one folder.
  const hazmap::OutputFolder out = hazmap::inspect_output_folder(out_dir);
  const std::string refusal = hazmap::output_folder_refusal(out, args.on("overwrite"));
  if (!refusal.empty()) throw UsageError(refusal);
  // Every input is checked before anything is logged or written.
  const hazmap::Config config = hazmap::load_config(config_path, args.sets);
  setup_logging("", args.on("quiet"));  // the terminal only, plain lines, until OUT is ready
  const hazmap::Sequence sequence =
      load_any_sequence(sequence_dir, args, /*identity_fallback=*/true);
  const std::vector<hazmap::SequenceFrame> frames =
      args.has("frames") ? hazmap::select_frames(sequence.frames, args.get("frames"))
                         : sequence.frames;
  hazmap::check_frame_images(frames, sequence.calibration);
  std::vector<std::string> warnings =
      hazmap::enforce_rig_geometry(hazmap::check_rig_geometry(sequence, frames));
  if (sequence.poses_assumed_identity)
    warnings.push_back(sequence.dir.string() + ": no poses (no --poses, no "
                       "mav0/state_groundtruth_estimate0): every frame at the identity, the "
                       "clouds in EuRoC's body frame");
  hazmap::StereoFrontEnd front_end(config.stereo, config.sensor, sequence.calibration);
  hazmap::clear_output_folder(out);  // every check has passed

  setup_logging(out_dir / hazmap::run_layout::kRunLog, args.on("quiet"));
  for (const std::string& w : warnings) spdlog::warn("{}", w);
  log_run_start(front_end, config, config_path, sequence_dir, out_dir, frames.size());
  const hazmap::StereoGeometry& g = front_end.rectifier().geometry();

  std::string per_frame;
  hazmap::StereoTimes sum;
  size_t points_total = 0;
  FrameImages images;
  for (size_t i = 0; i < frames.size(); ++i) {
    const hazmap::SequenceFrame& f = frames[i];
    try {
      const cv::Mat left = hazmap::read_image(f.left_path);
      const cv::Mat right = hazmap::read_image(f.right_path);
      const hazmap::StereoTimes t = front_end.process(left, right, f.pose.T_W_B);

      write_frame_files(front_end, config, hazmap::run_layout::frame_dir(out_dir, f.name), f.name,
                        images);

      const size_t points = front_end.cloud().size();
      points_total += points;
      sum.grey_ms += t.grey_ms;
      sum.rectify_ms += t.rectify_ms;
      sum.disparity_ms += t.disparity_ms;
      sum.points_ms += t.points_ms;
      spdlog::info("frame {}/{} {}: {} points; grey {:.1f} ms, rectify {:.1f} ms, disparity {:.1f} "
                   "ms, points {:.1f} ms",
                   i + 1, frames.size(), f.name, points, t.grey_ms, t.rectify_ms, t.disparity_ms,
                   t.points_ms);
      per_frame += std::string(per_frame.empty() ? "" : ",\n") + frame_json(f.name, points, t);
    } catch (const hazmap::Error& e) {
      throw hazmap::Error(std::string(e.what()) + " (frame " + f.name + ", " +
                          std::to_string(i + 1) + " of " + std::to_string(frames.size()) +
                          ", stopped the run; the " + std::to_string(i) +
                          " frame folders before it are complete)");
    }
  }
  const double n = static_cast<double>(frames.size());
  hazmap::write_file_atomically(out_dir / "stereo_summary.json",
                                summary_json(frames.size(), points_total, config, g, sum, per_frame));
  spdlog::info("done: {} frames, {} points; mean per frame: grey {:.1f} ms, rectify {:.1f} ms, "
               "disparity {:.1f} ms, points {:.1f} ms",
               frames.size(), points_total, sum.grey_ms / n, sum.rectify_ms / n,
               sum.disparity_ms / n, sum.points_ms / n);
  return kExitOk;
}

}  // namespace hazmap::cli
