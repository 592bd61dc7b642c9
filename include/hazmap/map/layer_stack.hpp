#pragma once
// The multi-resolution map (SPEC 5): layers finest first, each with its own rule,
// built once from the config. Per frame: begin_frame (roll + per-frame rule updates),
// insert (all_layers or finest_then_pool), then export grids for hazards and output.

#include <cstdint>
#include <memory>
#include <vector>

#include "hazmap/core/core_config.hpp"
#include "hazmap/core/parallel_for.hpp"
#include "hazmap/map/layer.hpp"
#include "hazmap/map/pose_uncertainty.hpp"

namespace hazmap {

/// Builds layer `index` of `map` with its rule (one switch over the YAML rule name).
/// `hazard` gives CCM layers the tilt their unevaluable cells may hide (SPEC 6.4).
std::unique_ptr<Layer> make_layer(const MapConfig& map, const RulesConfig& rules,
                                  const HazardConfig& hazard, std::size_t index);
/// The same with the default hazard config (tests and benchmarks).
std::unique_ptr<Layer> make_layer(const MapConfig& map, const RulesConfig& rules, std::size_t index);

/// SPEC 4 lateral gate of a layer: max_std_ratio (the layer's, else rules.ccm's) times the
/// uniform-cell std r / sqrt(12) [m]; 0 when off.
double gate_std_m(const LayerConfig& layer, const RulesConfig& rules);

class LayerStack {
 public:
  /// `pose_uncertainty`: track pose noise and inflate exported variances (SPEC 7).
  /// `hazard`: hazard.max_slope_deg enters CCM layers' published variance (SPEC 6.4).
  LayerStack(const MapConfig& map, const RulesConfig& rules, const HazardConfig& hazard,
             bool pose_uncertainty = false);
  /// The same with the default hazard config (tests and benchmarks).
  LayerStack(const MapConfig& map, const RulesConfig& rules, bool pose_uncertainty = false);

  /// Rolls every layer to the robot position and applies per-frame rule updates.
  /// `noise`: pose noise added since the previous frame (SPEC 2), if known.
  void begin_frame(double robot_x_m, double robot_y_m, const PoseNoise& noise = {});

  /// Inserts the frame's points and, in finest_then_pool mode, rebuilds covered coarse
  /// cells from their children. Returns the number of point-into-layer updates. The
  /// points go in chunks to every layer in turn, coarsest first (layer_stack.cpp).
  /// `layer_ms`, if given (size() entries): each layer's time in milliseconds, measured
  /// inside the chunk loop (a layer pays for the cache traffic the others cause it);
  /// pooling into a layer counts for that layer. In one thread they add up to the call's
  /// wall time; on several (set_parallel) to more.
  std::size_t insert(const MapPoints& points, double* layer_ms = nullptr);

  /// Inserts on `pool`'s threads (null: in the calling thread): each thread takes a set
  /// of layers through every chunk, the sets balanced by the layers' times in the frame
  /// before. The same results: a layer's state depends only on its own points. Not in
  /// finest_then_pool mode, where one layer takes the points. `pool` must outlive its use.
  void set_parallel(const ParallelFor* pool);

  /// Exports layer i's grids (variance inflated by pose uncertainty when enabled);
  /// `seen_whole`: its cells also evaluable by a hole-free view (map/seen_whole.hpp).
  void export_layer(std::size_t i, LayerGrids& out, const SeenWhole* seen_whole = nullptr) const;

  /// Cells of layer i whose state this frame may have changed, as global indices cut to
  /// the window (SPEC 8.6): those under the bounding box of the points of the last insert
  /// (a superset of the cells they updated, one cell wider for rounding), and on a pooled
  /// layer every cell the finer window covers (rebuilt from its children each frame).
  /// Empty after a begin_frame without insert. Cells that entered the window are not in
  /// it: the caller sees the window move.
  CellRange changed_cells(std::size_t i) const;

  /// Whether layer i's exported grids change every frame, updated or not: its rule ages
  /// what it exports (Kalman time inflation), or pose uncertainty inflates every variance.
  bool exports_vary(std::size_t i) const { return track_pose_ || layers_[i]->ages_exports(); }

  /// What layer i's SPEC 4 gates dropped in the last insert.
  GateCounts gate_counts(std::size_t i) const { return layers_[i]->gate_counts(); }

  std::size_t size() const { return layers_.size(); }
  const Layer& layer(std::size_t i) const { return *layers_[i]; }
  Layer& layer(std::size_t i) { return *layers_[i]; }
  bool pooling() const { return pooling_; }
  std::uint32_t frame() const { return frame_; }

 private:
  std::vector<std::unique_ptr<Layer>> layers_;
  std::vector<PoolGrid> pools_;  ///< pools_[i]: children of layer i (i >= 1)
  std::vector<std::uint64_t> layer_ticks_;  ///< insert's per-layer time, in read_ticks() units
  const ParallelFor* pool_ = nullptr;
  std::vector<int> group_of_;               ///< set_parallel: layer i's thread's set
  std::vector<int> by_time_;                ///< layers, longest last frame first
  std::vector<std::uint64_t> group_load_;   ///< per set: ticks assigned, while balancing
  std::vector<std::size_t> group_updates_;  ///< per set: its point-into-layer updates
  bool pooling_ = false;
  bool track_pose_ = false;
  PoseUncertainty pose_;
  std::uint32_t frame_ = 0;
  bool started_ = false;
  /// Bounding box of the last insert's points [m] (changed_cells); none when !has_points_.
  bool inserted_ = false;  ///< insert ran since begin_frame
  bool has_points_ = false;
  float min_x_ = 0, max_x_ = 0, min_y_ = 0, max_y_ = 0;
  double robot_x_m_ = 0, robot_y_m_ = 0;
};

}  // namespace hazmap
