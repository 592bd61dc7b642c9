#pragma once
// The map core's facade: the map half of a frame (SPEC 5-8) in one object. It owns the
// layer stack, the hazard stage (each layer's hazards, the fused and footprint maps) and
// the terrain view the stereo front end's occlusion check reads, all built once from the
// core's configuration (core/core_config.hpp, no YAML needed). Per frame:
//   insert(points, robot x, y, noise)   rolls every layer's window, inserts the points
//   classify()                          runs the hazard stage on the layers as they stand
// Pipeline (pipeline/pipeline.hpp) puts stereo in front of it; the Python LayerStack and
// examples/embed_core feed it points from elsewhere. Once the map is built a frame
// allocates nothing (tests/map/allocation_test.cpp).

#include <cstddef>
#include <vector>

#include "hazmap/core/core_config.hpp"
#include "hazmap/core/parallel_for.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/map/known_terrain.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/map/map_points.hpp"

namespace hazmap {

class Mapper {
 public:
  /// `pose_uncertainty`: track pose noise and inflate exported variances (SPEC 7,
  /// pose_uncertainty.enabled in the run configuration).
  explicit Mapper(const CoreConfig& config, bool pose_uncertainty = false);

  /// Rolls every layer to centre on the robot at (robot_x_m, robot_y_m) in W, applies the
  /// rules' per-frame updates and inserts `points`. `noise`: pose noise added since the
  /// previous frame (SPEC 2), used with pose uncertainty. Returns the point-into-layer
  /// updates; layer_ms() and layer_gates() then hold the insertion's per-layer figures.
  std::size_t insert(const MapPoints& points, double robot_x_m, double robot_y_m,
                     const PoseNoise& noise = {});
  /// The same for a point cloud, converted into a buffer the mapper keeps (points()) with
  /// the configured CCM weighting (rules.ccm.weighting).
  std::size_t insert(const PointCloud& cloud, double robot_x_m, double robot_y_m,
                     const PoseNoise& noise = {});
  /// Converts `cloud` into points() (the conversion insert(cloud, ...) makes) and returns it.
  const MapPoints& assign_points(const PointCloud& cloud);

  /// Classifies the layers as the last insert left them, fuses them and builds the
  /// footprint map (HazardStage::run); then points known_terrain() at the finest layer's
  /// new grids. `view`: what the frame's cameras looked at (hazard.partial_ring_proof:
  /// view_edge), null when the points came from elsewhere.
  void classify(const SensorView* view = nullptr);

  /// Runs the insertion and the hazard stage's larger loops on `pool`'s threads (null:
  /// in the calling thread); the same results either way. `pool` must outlive its use.
  void set_parallel(const ParallelFor* pool);

  const LayerStack& layers() const { return map_; }
  const HazardStage& hazards() const { return hazards_; }
  const std::vector<LayerView>& layer_views() const { return hazards_.layers(); }
  const DenseGrid& fused() const { return hazards_.planner_maps().fused; }
  const PlannerMaps& planner_maps() const { return hazards_.planner_maps(); }
  const HazardParams& hazard_params() const { return hazards_.params(); }
  /// The CCM weighting the map's points carry (rules.ccm.weighting).
  CcmWeighting weighting() const { return weighting_; }
  /// The buffer insert(cloud, ...) and assign_points fill.
  const MapPoints& points() const { return points_; }

  /// Each layer's share of the last insert's wall time, ms (LayerStack::insert).
  const std::vector<double>& layer_ms() const { return layer_ms_; }
  /// What each layer's SPEC 4 gates dropped in the last insert, and their sum.
  const std::vector<GateCounts>& layer_gates() const { return layer_gates_; }
  const GateCounts& gated() const { return gated_; }

  /// The terrain the finest layer published at the last classify() (empty before the
  /// first), for visibility checks on the next frame's points (stereo.occlusion_*). Only
  /// the finest: coarser cells are too coarse for rays a few centimetres from the lens,
  /// and where the finest layer knows nothing (under the rover) neither does a coarse
  /// cell's mean. Mutable: its near-field buffers are prepared by the reader.
  KnownTerrain& known_terrain() { return terrain_; }

 private:
  LayerStack map_;
  CcmWeighting weighting_;
  MapPoints points_;
  std::vector<double> layer_ms_;
  std::vector<GateCounts> layer_gates_;
  GateCounts gated_;
  HazardStage hazards_;
  KnownTerrain terrain_;  ///< views of hazards_' finest layer grids
};

}  // namespace hazmap
