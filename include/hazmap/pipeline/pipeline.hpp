#pragma once
// The per-frame path, in order: grey conversion -> rectification -> disparity ->
// points with covariance -> map insertion -> hazards. Buffers live here and are reused
// from frame to frame.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/hazard/ccm_hazards.hpp"
#include "hazmap/hazard/roughness_filter.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/map/layer_stack.hpp"
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
  /// Points the SPEC 4 gates dropped, summed over layers (a point counts once per layer
  /// that dropped it); per layer in Pipeline::layer_gates().
  GateCounts gated;
  StageTimes ms;
};

/// What a layer shows after a frame: dense grids in image order (row 0 = largest y).
struct LayerView {
  LayerGrids map;         ///< height, variance (+ plane grids for CCM layers)
  DenseGrid kernel_range; ///< piecewise-constant layers: max - min in the kernel [m]
  DenseGrid kernel_fill;  ///< observed fraction of the kernel
  DenseGrid hazard;       ///< HazardClass values
};

/// Roughness parameters of a layer: the kernel from its config, the threshold given or
/// derived as (D - 1) r tan(max_slope) (SPEC 8.1).
RoughnessParams roughness_params(const LayerConfig& layer, const HazardConfig& hazard);

/// CCM hazard parameters of a layer: h_min given or 0.75 r, rho_max given or h_min^2/16.
CcmHazardParams ccm_params(const LayerConfig& layer, const HazardConfig& hazard);

/// Classifies one layer's exported grids into view.hazard: CCM layers by their plane
/// tests (SPEC 8.2), the others by the roughness kernel (SPEC 8.1).
void classify_layer(bool has_plane, const RoughnessParams& roughness, const CcmHazardParams& ccm,
                    RoughnessFilter& filter, LayerView& view);

class Pipeline {
 public:
  Pipeline(const Config& config, const StereoCalibration& calibration);

  /// Runs one stereo pair (any 8/16-bit grey or colour images of the calibrated size)
  /// taken at body pose T_W_B through the whole path.
  /// `noise`: pose noise added since the previous frame (SPEC 2), used when
  /// pose_uncertainty.enabled.
  FrameReport process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                      const PoseNoise& noise = {});

  const std::vector<LayerView>& layers() const { return views_; }
  const DenseGrid& fused_hazard() const { return fused_; }
  const LayerStack& map() const { return map_; }
  /// Each layer's share of the last frame's insertion, ms (LayerStack::insert).
  const std::vector<double>& layer_map_ms() const { return layer_map_ms_; }
  /// What each layer's SPEC 4 gates dropped in the last frame (a member, not part of
  /// FrameReport, so that a frame allocates nothing for it).
  const std::vector<GateCounts>& layer_gates() const { return layer_gates_; }
  const PointCloud& cloud() const { return front_.cloud(); }
  const cv::Mat& disparity_x16() const { return front_.disparity_x16(); }
  const Rectifier& rectifier() const { return front_.rectifier(); }

 private:
  void analyse_hazards();

  Config config_;
  StereoFrontEnd front_;
  LayerStack map_;
  CcmWeighting weighting_;
  MapPoints points_;  ///< the frame's points as the map reads them
  std::vector<double> layer_map_ms_;
  std::vector<GateCounts> layer_gates_;
  RoughnessFilter roughness_;
  std::vector<RoughnessParams> roughness_params_;
  std::vector<CcmHazardParams> ccm_params_;

  std::vector<LayerView> views_;
  std::vector<const DenseGrid*> hazard_ptrs_;
  DenseGrid fused_;
};

}  // namespace hazmap
