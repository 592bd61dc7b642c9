#pragma once
// The per-frame path, in order: grey conversion -> rectification -> disparity ->
// points with covariance -> map insertion -> hazards. Buffers live here and are reused
// from frame to frame.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/hazard/mapper.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"

namespace hazmap {

/// Wall time of each stage of one frame, milliseconds.
struct StageTimes {
  double rectify_ms = 0;    ///< grey conversion + remap
  double disparity_ms = 0;
  double points_ms = 0;     ///< triangulation + covariance + transform
  double map_ms = 0;        ///< rolling + insertion
  double hazard_ms = 0;     ///< grid export + segmentation + fusion
  double total() const { return rectify_ms + disparity_ms + points_ms + map_ms + hazard_ms; }
};

struct FrameReport {
  size_t points = 0;       ///< valid points of the frame
  size_t updates = 0;      ///< point-into-layer updates
  /// Points dropped as below ground (SPEC 3.3), not in `points`.
  size_t points_below_ground = 0;
  /// Points dropped as seen through the terrain the map knew (stereo.occlusion_*).
  size_t points_occluded = 0;
  /// Disparities removed as unsupported (floating mismatches), before points.
  size_t disparities_unsupported = 0;
  /// Points the SPEC 4 gates dropped, summed over layers (a point counts once per layer
  /// that dropped it); per layer in Pipeline::layer_gates().
  GateCounts gated;
  StageTimes ms;
};

class Pipeline {
 public:
  Pipeline(const Config& config, const StereoCalibration& calibration);

  /// Runs one stereo pair (any 8/16-bit grey or colour images of the calibrated size)
  /// taken at body pose T_W_B through the whole path.
  /// `noise`: pose noise added since the previous frame (SPEC 2), used when
  /// pose_uncertainty.enabled.
  FrameReport process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                      const PoseNoise& noise = {});

  const Config& config() const { return config_; }
  const std::vector<LayerView>& layers() const { return mapper_.layer_views(); }
  const DenseGrid& fused_hazard() const { return mapper_.fused(); }
  const PlannerMaps& planner_maps() const { return mapper_.planner_maps(); }
  const HazardParams& hazard_params() const { return mapper_.hazard_params(); }
  /// The hazard stage, with what its last frame recomputed (SPEC 8.6).
  const HazardStage& hazard_stage() const { return mapper_.hazards(); }
  const LayerStack& map() const { return mapper_.layers(); }
  /// The map half of the path (hazard/mapper.hpp): layers, hazards, fused and footprint maps.
  const Mapper& mapper() const { return mapper_; }
  /// Each layer's share of the last frame's insertion, ms (LayerStack::insert).
  const std::vector<double>& layer_map_ms() const { return mapper_.layer_ms(); }
  /// What each layer's SPEC 4 gates dropped in the last frame (a member, not part of
  /// FrameReport, so that a frame allocates nothing for it).
  const std::vector<GateCounts>& layer_gates() const { return mapper_.layer_gates(); }
  const PointCloud& cloud() const { return front_.cloud(); }
  const cv::Mat& disparity_x16() const { return front_.disparity_x16(); }
  /// The last frame's rectified 8-bit grey pair (what the matcher saw).
  const cv::Mat& rectified_left() const { return front_.rectified_left(); }
  const cv::Mat& rectified_right() const { return front_.rectified_right(); }
  const Rectifier& rectifier() const { return front_.rectifier(); }
  const DisparityMatcher& matcher() const { return front_.matcher(); }
  const PointCloudBuilder& builder() const { return front_.builder(); }
  /// What the cameras looked at in the last frame, as the hazard stage read it.
  const SensorView& sensor_view() const { return view_; }

 private:
  Config config_;
  StereoFrontEnd front_;
  Mapper mapper_;  ///< the map half: insertion, hazards, the terrain for the occlusion check
  SensorView view_;  ///< what the cameras look at; the body pose set per frame
};

}  // namespace hazmap
