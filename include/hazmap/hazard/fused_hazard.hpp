#pragma once
// The maps a planner consumes, on one grid at the finest layer's resolution.
//
// Fused hazard (SPEC 8.4): a coarse layer can only vouch for obstacles of at least its own
// h_min. A cell is a hazard where any layer covering its centre says hazard, traversable
// only where a layer whose h_min <= critical_height says traversable, unknown otherwise.
// Fused clearance: the smallest h_min of the layers that call the cell traversable (NaN
// where none does, or where the fused map says hazard): an upper bound on an obstacle
// that could still hide there.
//
// Footprint (SPEC 8.5), the configuration space of the rover's centre: hazard if a fused
// hazard cell overlaps the disc of the footprint radius, else unknown if an unknown cell
// (or the map's edge) does, else traversable. A cell counts when its centre lies within
// the radius plus half a cell's diagonal (every cell the disc touches, and a few more). Hazard distance: metres from each cell centre to
// the nearest fused hazard cell centre, capped at half the map's side.

#include <array>
#include <vector>

#include "hazmap/hazard/dirty_region.hpp"
#include "hazmap/hazard/distance_transform.hpp"
#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// One layer's contribution to the fused map.
struct FusionInput {
  const DenseGrid* hazard = nullptr;  ///< HazardClass values
  double h_min_m = 0.0;
  /// 1 where the layer's cell is unknown only for its wheel ring (set_ring_only), or null.
  const DenseGrid* ring_only = nullptr;
};

class HazardFusion {
 public:
  /// Finer proof (issue 34): a layer's hazard yields where a strictly finer layer with
  /// h_min <= critical height proves the cell traversable. A coarse cell's hazard lies
  /// somewhere in it (a rock's rim fills the whole coarse cell); the finer layer has
  /// measured this part of it and passed every test, the step above its own wheel ring
  /// and the slopes included. Off: SPEC 8.4's any-layer hazard.
  void set_finer_proof(bool on) { finer_proof_ = on; }

  /// Proof margin (hazard.proof_margin, issue 34): a cell whose centre lies within
  /// `margin_m` of a fused hazard cell's centre is not traversable (unknown) and not clear.
  /// A matcher's window at a rock's silhouette measures the rock's base as the ground in
  /// front of it (low sun, 12 cm rocks: the first 1-3 cm of the rock at ground height), so
  /// the cell beside the hazard the map did see may hold rock. Hazards outside the fused
  /// grid do not count. 0: off. `resolution_m`: the fused grid's.
  void set_proof_margin(double margin_m, double resolution_m);
  /// Cells the margin reaches (0: off); an incremental caller grows its region by it.
  int proof_margin_cells() const { return margin_cells_; }

  /// Fuses `layers` onto a `cells` x `cells` grid of resolution `resolution_m` centred
  /// at (center_x, center_y). Buffers are reused.
  /// With `clear` (hazard.footprint_centre_ring) also 1 there where the fused cell is
  /// traversable, or unknown and some vouching layer's cell is unknown only for its wheel
  /// ring (FusionInput::ring_only); 0 elsewhere.
  void fuse(const std::vector<FusionInput>& layers, double critical_height_m, int cells,
            double resolution_m, double center_x_m, double center_y_m, DenseGrid& fused,
            DenseGrid& clearance, DenseGrid* clear = nullptr);
  /// Re-fuses the cells of `region` only (SPEC 8.6); `fused` and `clearance` (and `clear`)
  /// must have their geometry for this frame already and keep their other cells.
  void fuse(const std::vector<FusionInput>& layers, double critical_height_m,
            const DirtyRegion& region, DenseGrid& fused, DenseGrid& clearance,
            DenseGrid* clear = nullptr);

  /// Footprint map and hazard distance from a fused map. With `clear`
  /// (hazard.footprint_centre_ring): traversable where the centre's cell is traversable
  /// and every cell in the disc is clear (the wheels stand on the centre's ring, which
  /// the centre's proof measured; a body cell needs its own tests, not its own ring).
  void footprint(const DenseGrid& fused, double radius_m, DenseGrid& footprint,
                 DenseGrid& hazard_distance, const DenseGrid* clear = nullptr);
  /// The footprint of the cells of `region` only (SPEC 8.6; `footprint` must have the
  /// fused map's geometry and keeps its other cells) and the hazard distance of every
  /// cell: an incremental distance transform would not be simple. Whether an unknown
  /// cell lies within the radius is found on each rectangle grown by the radius.
  void footprint(const DenseGrid& fused, double radius_m, const DirtyRegion& region,
                 DenseGrid& footprint, DenseGrid& hazard_distance,
                 const DenseGrid* clear = nullptr);

 private:
  bool finer_proof_ = false;
  struct FusedCell {
    float cls, clearance;
    bool ring_only;
  };
  int margin_cells_ = 0;
  double margin_resolution_m_ = 0.0;
  std::vector<std::array<int, 2>> margin_offsets_;  ///< (drow, dcol) within the margin
  std::vector<FusedCell> margin_fused_;  ///< a rectangle grown by the margin, before it
  std::vector<int> cols_, rows_;  ///< per layer: fused column/row -> layer column/row (-1 outside)
  /// Fused column/row lookups of `layers` for `fused`'s geometry.
  void map_layers(const std::vector<FusionInput>& layers, const DenseGrid& fused);

  std::vector<unsigned char> hazard_src_;
  std::vector<float> hazard_d2_;
  std::vector<int> near_unknown_;  ///< rows to the nearest unknown cell in the column
  std::vector<int> reach_;         ///< reach_[dc]: largest dr with dr^2 + dc^2 <= radius^2
  DistanceTransform edt_;
};

/// Cells per side of the fused grid: extent / resolution rounded to an even count.
int fused_cells(double extent_m, double resolution_m);

}  // namespace hazmap
