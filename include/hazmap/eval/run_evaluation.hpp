#pragma once
// `hazmap evaluate`: scores every written frame and layer of a run (OUT of `hazmap run`)
// against the ground truth of its sequence (SPEC 10), and writes
//   metrics.csv            one row per frame and layer (the fused and footprint maps are
//                          layers "fused" and "footprint")
//   summary.csv            one row per layer, pooled over frames (what sweeps read)
//   metrics.json           the same per-layer summary with the settings behind it
//   metrics_over_time.png  each metric against the frame, one line per layer
//   errors_<frame>.png     per layer |h - h_gt| and missed / false-alarm pixels
//   report.html            a static page with the table, the plots and a frame viewer
//
// Inputs. RUN/summary.json ("settings_yaml": the configuration used, for the layers'
// resolution, rule and hazard parameters; "poses_fingerprint": checked against
// SEQ/poses.txt first, so that a run is never scored against another sequence),
// RUN/frames/<frame>/L<i>_{height,variance,hazard}.jdem (+ L<i>_slope_{x,y}.jdem for
// CCM), fused_hazard.jdem and, when the run wrote it in every frame,
// footprint_hazard.jdem (else that map is skipped); SEQ/gt_height.jdem,
// SEQ/gt_hazard.jdem, SEQ/poses.txt and, if the run drove on drifted poses,
// SEQ/poses_true.txt.
//
// True pose. The map of frame k was built in the frame of the poses the run was given
// (poses.txt, possibly drifted). The ground truth lives in the true world W. The map's
// frame relative to W at frame k is taken as the transform that carries the true body
// pose onto the drifted one,
//     T_map_W = T_W_B(drifted, k) * T_W_B(true, k)^-1,
// i.e. the map is compared with the ground truth as the rover saw it at frame k: an
// obstacle seen where the rover believes it is counts as found. (Older map content was
// placed with older, smaller drift; that residual misplacement is what a drift test
// measures.) Without poses_true.txt, T_map_W = identity.
//
// h_min per layer (what counts as an obstacle the layer must find) is the pipeline's own,
// from resolve_hazard_params (hazard/hazard_params.hpp): hazard.h_min when set; else
// 0.75 r for CCM layers; else the roughness threshold for piecewise-constant layers. The
// fused and footprint maps use hazard.critical_height (SPEC 8.4, 10).
//
// Near metrics (--near R): the same sums restricted to GT pixels within R metres
// (horizontally, in W) of the rover's true position at that frame (poses_true.txt when
// present, else poses.txt), reported with a near_ prefix.
//
// Seen cells (issue 34; seen_confusion.hpp): when SEQ/depth/ holds the simulator's depth
// images (`simulate --depth`), each map's confusion table over the GT pixels the left
// camera has seen within stereo.z_max since the run's first frame, with seen_ (and
// near_seen_) columns, and the reasons for unknown when the run wrote
// L<i>_unknown_reason grids (output.unknown_reasons).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hazmap/core/types.hpp"
#include "hazmap/eval/metrics.hpp"
#include "hazmap/eval/seen_confusion.hpp"
#include "hazmap/io/config.hpp"

namespace hazmap::eval {

struct EvaluationOptions {
  std::filesystem::path run_dir;
  std::filesystem::path sequence_dir;
  std::filesystem::path out_dir;  ///< empty: RUN/eval
  /// Frames that get an errors_<frame>.png: names, or "all"; empty: the last frame.
  std::vector<std::string> error_map_frames;
  bool write_report = true;  ///< report.html
  double near_radius_m = -1.0;  ///< --near R; negative: no near metrics
  bool near_enabled() const { return near_radius_m >= 0.0; }
};

/// What is scored as a layer: "L<i>", "fused" or "footprint".
struct EvaluatedLayer {
  std::string name;
  int index = -1;            ///< layer index, -1 for the fused and footprint maps
  double resolution_m = 0.0;
  std::string rule;          ///< "ccm", "omg", ..., "fused", "footprint"
  double h_min_m = 0.0;
  std::string h_min_source;  ///< "hazard.h_min", "0.75 r", "roughness threshold", ...
  std::string hazard_file;   ///< the hazard-only map's file (index -1), e.g. fused_hazard.jdem
  /// > 0: scored against obstacles dilated by this radius (dilate_obstacles): the
  /// footprint map's truth is the rover centre's configuration space, not the rocks.
  double gt_dilation_m = 0.0;
};

struct RunEvaluation {
  std::vector<EvaluatedLayer> layers;
  std::vector<std::string> frames;              ///< written frames, sorted
  std::vector<std::vector<MetricSums>> sums;    ///< [frame][layer]
  std::vector<MetricSums> pooled;               ///< [layer], over all frames
  double near_radius_m = -1.0;                  ///< negative: no near metrics
  std::vector<std::vector<MetricSums>> near_sums;  ///< [frame][layer], with --near
  std::vector<MetricSums> near_pooled;             ///< [layer], with --near
  bool used_true_poses = false;                 ///< poses_true.txt was found
  bool seen_enabled = false;                    ///< SEQ/depth/ was found
  std::vector<std::vector<SeenSums>> seen_sums;       ///< [frame][layer]
  std::vector<SeenSums> seen_pooled;                  ///< [layer]
  std::vector<std::vector<SeenSums>> near_seen_sums;  ///< [frame][layer], with --near
  std::vector<SeenSums> near_seen_pooled;             ///< [layer], with --near
  /// [layer], with --near: over cells seen within the vouching layers' lateral gate
  /// (seen_confusion.hpp, LateralGate).
  std::vector<SeenSums> near_gated_pooled;
  /// [layer], with --near: over cells seen within the gate together with every GT pixel
  /// within the wheel ring's radius of them (for the footprint map: the footprint radius
  /// plus the ring's): the ground a full, measured wheel ring could prove at best.
  std::vector<SeenSums> near_ring_gated_pooled;
  std::filesystem::path out_dir;
};

/// The maps scored for a run of `config`: its layers, "fused" and, when
/// `with_footprint`, "footprint", with their h_min as documented above.
std::vector<EvaluatedLayer> evaluated_layers(const Config& config, bool with_footprint);

/// The configuration a run used, from RUN/summary.json "settings_yaml". Throws Error
/// naming the file when it is missing or has no settings.
Config read_run_config(const std::filesystem::path& run_dir);

/// Which sequence a run was made from, as RUN/summary.json records it.
struct RunSource {
  std::string sequence;  ///< its folder (absolute since the fingerprint is recorded)
  /// poses_fingerprint() of the sequence's poses; nullopt for a run made before it was
  /// recorded.
  std::optional<std::uint64_t> poses_fingerprint;
};

/// RUN/summary.json's "sequence" and "poses_fingerprint". Throws Error naming the file
/// when it is missing, or its fingerprint is not 16 hexadecimal digits.
RunSource read_run_source(const std::filesystem::path& run_dir);

/// The run was made from `sequence_dir`: its recorded poses fingerprint equals that of
/// SEQ/poses.txt (read_poses_fingerprint; all poses, so a run of --frames A:B matches
/// too). Throws Error, one line naming both folders, when they differ; a run that
/// records no fingerprint (older than the record) gets a warning through spdlog instead.
/// evaluate_run does this first.
void check_run_sequence(const std::filesystem::path& run_dir,
                        const std::filesystem::path& sequence_dir);

/// Reads a JDEM grid into a DenseGrid; throws Error naming the file if it is rotated
/// (yaw != 0) or unreadable.
DenseGrid read_dense_grid(const std::filesystem::path& path);

/// SEQ/gt_height.jdem and SEQ/gt_hazard.jdem. Throws Error naming a missing file (with a
/// hint to simulate with --ground-truth).
GroundTruth read_ground_truth(const std::filesystem::path& sequence_dir);

/// Scores the run and writes every output listed above into options.out_dir (created;
/// files written atomically). Logs progress through spdlog. Throws Error on bad input.
RunEvaluation evaluate_run(const EvaluationOptions& options);

}  // namespace hazmap::eval
