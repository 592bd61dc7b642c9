#pragma once
// The hazard stage of a frame (SPEC 8): each layer's export and classification, the
// fused map and the footprint, with their buffers kept from frame to frame.
//
// Incremental (SPEC 8.6, hazard.incremental): a frame recomputes only the cells whose
// result can have changed, and gives the same maps as a whole pass, cell for cell:
//  - a layer re-exports the cells the frame's points may have updated (LayerStack::
//    changed_cells) and the strips its window gained; it re-classifies those and the
//    strips it lost, grown by the classifier's reach (kernel, wheel ring). The rest of
//    its grids moves with the window (DenseGrid::shift).
//  - a layer whose exports change every frame without an update (Kalman time inflation,
//    pose uncertainty: every known cell's variance grows, so any cell's result can
//    change) is exported and classified whole. This is exact by construction; on the
//    shipped stacks it is the Kalman 1 cm layer (time_inflation > 0).
//  - the fused map re-fuses the cells where some layer's hazard value changed (found by
//    comparing with the last frame), the strips a layer's window lost and those the
//    fused window gained; the footprint the cells where the fused map changed, and the
//    strips the fused window gained or lost, grown by the footprint radius. The hazard
//    distance stays a whole pass (HazardFusion::footprint).
//  - with hazard.partial_ring_proof: view_edge a ring reads the layer's view mask: the
//    cells the frame's view newly reached are re-classified, grown by the reach.
//  - with map.layers.N.hole_free_coverage a layer's export reads its hole-free marks: the
//    cells whose mark changed are re-exported and re-classified, grown by the reach.
//  - with hazard.coarse_ring_fill a layer's rings read the next coarser layer too: the
//    coarser layer runs first, and the finer one also re-classifies, grown by its reach,
//    the cells under the coarser layer's changed cells and window strips (whole when the
//    coarser layer was classified whole).
// Any frame whose window jumped by its own size or more is computed whole.

#include <memory>
#include <vector>

#include "hazmap/hazard/coarse_ring_fill.hpp"
#include "hazmap/hazard/dirty_region.hpp"
#include "hazmap/hazard/fused_hazard.hpp"
#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/hole_marker.hpp"
#include "hazmap/hazard/sensor_view.hpp"
#include "hazmap/map/layer_stack.hpp"

namespace hazmap {

/// What a layer shows after a frame: dense grids in image order (row 0 = largest y).
struct LayerView {
  LayerGrids map;                 ///< height, variance (+ plane grids for CCM layers)
  HazardDiagnostics diagnostics;  ///< the classifier's intermediate grids
  DenseGrid hazard;               ///< HazardClass values
  /// How much of each cell the stereo pair has ever looked at (0, kPartlyViewed,
  /// kWhollyViewed; ViewMarker); kept only with hazard.partial_ring_proof: view_edge
  /// (empty otherwise).
  DenseGrid viewed;
  /// Which cells a frame's disparity image saw whole (0, kSeenWhole, kHoleSeen;
  /// HoleMarker); kept only with map.layers.N.hole_free_coverage (empty otherwise).
  DenseGrid seen_whole;
  /// 1 where a cell is unknown only for its wheel ring (HazardClassifier::set_ring_only);
  /// kept only with hazard.footprint_centre_ring (empty otherwise).
  DenseGrid ring_only;
};

/// The maps a planner consumes (SPEC 8.4, 8.5), at the finest layer's resolution.
struct PlannerMaps {
  DenseGrid fused;            ///< HazardClass values
  DenseGrid clearance;        ///< [m], NaN where no layer proves the cell traversable
  DenseGrid footprint;        ///< HazardClass values for the rover's centre
  DenseGrid hazard_distance;  ///< [m] to the nearest fused hazard cell, capped
  /// hazard.footprint_centre_ring: 1 where a fused cell is clear under the rover's body
  /// (HazardFusion::fuse); empty otherwise.
  DenseGrid clear;
};

class HazardStage {
 public:
  /// `incremental`: SPEC 8.6 (hazard.incremental); false recomputes every cell.
  HazardStage(const HazardParams& params, bool incremental);

  /// Classifies `map`'s layers as they stand after a frame's insertion, fuses them and
  /// builds the footprint map. `view`: what the frame's stereo pair looked at, added to
  /// each layer's view mask first (hazard.partial_ring_proof: view_edge); null: nothing.
  void run(const LayerStack& map, const SensorView* view = nullptr);

  /// The layers' classifiers split their regions over `pool`'s threads (null: this
  /// thread); the same results. `pool` must outlive its use.
  void set_parallel(const ParallelFor* pool) {
    pool_ = pool;
    for (auto& c : classifiers_) c->set_parallel(pool);
  }

  const std::vector<LayerView>& layers() const { return views_; }
  const PlannerMaps& planner_maps() const { return planner_; }
  const HazardParams& params() const { return params_; }

  /// Layer i's UnknownReason bits as the last run left it (HazardClassifier::explain: a
  /// whole-layer diagnostic pass, for output.unknown_reasons; it allocates).
  void explain(std::size_t i, DenseGrid& reasons) const;

  /// The cells of layer i the last run re-classified (the whole layer on a whole pass),
  /// and of the fused and footprint maps.
  const DirtyRegion& classified(std::size_t i) const { return layer_state_[i].classified; }
  const DirtyRegion& fused_region() const { return fused_region_; }
  const DirtyRegion& footprint_region() const { return footprint_region_; }

 private:
  /// Where a grid's window was in the last run (global cell indices of its first cell).
  struct Placement {
    bool placed = false;
    CellIndex x = 0, y = 0;
    /// How an n x n window moved to first cell (x0, y0) since the last run: `placed` when
    /// it was placed before and still overlaps; `old_window` its last cells (empty when not
    /// placed); a kept cell's row grows by drow, its column by dcol (row 0 = largest y).
    struct Move {
      bool placed;
      CellRange old_window;
      int drow, dcol;
    };
    /// Records the new place and returns the move.
    Move move_to(CellIndex x0, CellIndex y0, int n);
  };
  struct LayerState {
    Placement at;
    DirtyRegion classified;
    Placement::Move moved{};  ///< the last run's move of the window
    bool whole = false;       ///< the last run classified the whole layer
  };

  /// Runs layer i; adds to fused_region_ what the fused map must redo because of it.
  /// Returns false when the fused map must be redone whole.
  bool run_layer(const LayerStack& map, std::size_t i, CellIndex fused_x0, CellIndex fused_y0,
                 int cells, const SensorView* view);
  void run_planner(bool whole, CellIndex fused_x0, CellIndex fused_y0, int cells);

  HazardParams params_;
  bool incremental_;
  std::vector<std::unique_ptr<HazardClassifier>> classifiers_;  ///< one per layer
  const ParallelFor* pool_ = nullptr;                           ///< set_parallel
  /// Layer i's ring fallback on layer i + 1 (hazard.coarse_ring_fill), else null.
  std::vector<std::unique_ptr<CoarseRingFill>> fills_;
  /// Layer i's terrain band for its view mask: the coarser layers' heights.
  std::vector<TerrainBand> bands_;
  /// Layer i's hole-free rule (marks: views_[i].seen_whole), or marks null: none.
  std::vector<SeenWhole> seen_whole_;
  ViewMarker marker_;
  std::vector<FusionInput> fusion_inputs_;
  HazardFusion fusion_;
  std::vector<LayerView> views_;
  PlannerMaps planner_;

  std::vector<LayerState> layer_state_;
  Placement fused_at_;
  DirtyRegion fused_region_, footprint_region_;
  DirtyRegion scratch_;           ///< a layer's changed cells before growing
  std::vector<float> before_;     ///< a grid's values before this run's recomputation
  std::vector<float> before_ring_;  ///< the same for a layer's ring_only / the fused clear grid
};

}  // namespace hazmap
