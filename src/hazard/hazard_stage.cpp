#include "hazmap/hazard/hazard_stage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace hazmap {
namespace {

/// a \ b for two rectangles of global cells: at most four rectangles (some empty).
int difference(const CellRange& a, const CellRange& b, CellRange (&out)[4]) {
  if (b.empty() || a.x1 <= b.x0 || b.x1 <= a.x0 || a.y1 <= b.y0 || b.y1 <= a.y0) {
    out[0] = a;
    return 1;
  }
  const CellIndex mx0 = std::max(a.x0, b.x0), mx1 = std::min(a.x1, b.x1);
  out[0] = {a.x0, mx0, a.y0, a.y1};                    // left of b
  out[1] = {mx1, a.x1, a.y0, a.y1};                    // right of b
  out[2] = {mx0, mx1, a.y0, std::max(a.y0, b.y0)};     // below b
  out[3] = {mx0, mx1, std::min(a.y1, b.y1), a.y1};     // above b
  return 4;
}

/// Image rectangle (row 0 = largest y) of the global cells `r` of a coarser grid, each
/// `scale` cells of this one, on a rows-high grid whose first cell is (x0, y0). Not cut
/// to the grid (a rectangle outside it may still reach in once grown), but kept within a
/// few grid sizes so that it fits an int.
GridRect image_rect(const CellRange& r, CellIndex scale, CellIndex x0, CellIndex y0, int rows) {
  if (r.empty()) return {};
  const CellIndex lim = 4 * static_cast<CellIndex>(rows) + 4;
  auto fit = [lim](CellIndex v) { return static_cast<int>(std::clamp(v, -lim, lim)); };
  return {fit(rows - (r.y1 * scale - y0)), fit(rows - (r.y0 * scale - y0)), fit(r.x0 * scale - x0),
          fit(r.x1 * scale - x0)};
}

/// How many cells of a `fine_m` grid one cell of a `coarse_m` grid spans along a side:
/// 0 unless a whole number >= 1 (then their cell borders agree: global index x scale).
CellIndex whole_scale(double coarse_m, double fine_m) {
  const double ratio = coarse_m / fine_m;
  const auto scale = static_cast<CellIndex>(std::llround(ratio));
  return scale >= 1 && std::abs(ratio - double(scale)) <= 1e-6 ? scale : 0;
}

/// The global cells a rolling grid's window covers.
CellRange window_of(const RollingGrid& g) {
  return {g.origin_x(), g.origin_x() + g.size(), g.origin_y(), g.origin_y() + g.size()};
}

/// Global cells of the image rectangle `g` on an n-high grid whose first cell is (x0, y0).
CellRange global_range(const GridRect& g, CellIndex x0, CellIndex y0, int n) {
  if (g.empty()) return {};
  return {x0 + g.col0, x0 + g.col1, y0 + n - g.row1, y0 + n - g.row0};
}

/// The smallest rectangle holding every cell of `region` whose value differs from
/// `before` (the grid's values before this run recomputed the region).
GridRect changed_bounds(const DenseGrid& now, const std::vector<float>& before,
                        const DirtyRegion& region) {
  GridRect bounds;
  for (const GridRect& rect : region) {
    const GridRect cut = rect.clipped(now.rows, now.cols);
    for (int row = cut.row0; row < cut.row1; ++row) {
      const size_t base = static_cast<size_t>(row) * now.cols;
      int first = -1, last = -1;
      for (int col = cut.col0; col < cut.col1; ++col)
        if (now.values[base + col] != before[base + col]) {
          if (first < 0) first = col;
          last = col;
        }
      if (first >= 0) bounds = bounds.hull({row, row + 1, first, last + 1});
    }
  }
  return bounds;
}

/// The grids of a layer's export that are in use (plane grids are empty on other layers).
template <class F>
void for_each_grid(LayerGrids& g, F&& f) {
  for (DenseGrid* d : {&g.height, &g.variance, &g.count, &g.slope_x, &g.slope_y, &g.roughness,
                       &g.coverage, &g.evaluable, &g.noise_variance, &g.lateral_xx, &g.lateral_yy,
                       &g.lateral_xy, &g.lateral_xz, &g.lateral_yz})
    if (d->rows > 0) f(*d);
}

}  // namespace

HazardStage::Placement::Move HazardStage::Placement::move_to(CellIndex x0, CellIndex y0, int n) {
  Move m{};
  m.placed = placed && std::abs(x0 - x) < n && std::abs(y0 - y) < n;
  if (m.placed) {
    m.old_window = {x, x + n, y, y + n};
    m.drow = -static_cast<int>(y0 - y);
    m.dcol = static_cast<int>(x0 - x);
  }
  *this = {true, x0, y0};
  return m;
}

HazardStage::HazardStage(const HazardParams& params, bool incremental)
    : params_(params),
      incremental_(incremental),
      views_(params.layers.size()),
      layer_state_(params.layers.size()) {
  fusion_.set_finer_proof(params.finer_proof);
  if (!params.layers.empty())
    fusion_.set_proof_margin(params.proof_margin_m, params.layers.front().resolution_m);
  for (size_t i = 0; i < views_.size(); ++i) {
    classifiers_.push_back(make_hazard_classifier(params_.layers[i]));
    fusion_inputs_.push_back({&views_[i].hazard, params_.layers[i].h_min_m});
    if (params_.footprint_centre_ring) {  // views_ never grows: pointers stay valid
      classifiers_[i]->set_ring_only(&views_[i].ring_only);
      fusion_inputs_.back().ring_only = &views_[i].ring_only;
    }
    // views_ never grows: the classifier may keep a pointer to the mask.
    if (params_.layers[i].partial_ring_proof == PartialRingProof::view_edge)
      classifiers_[i]->set_view_mask(&views_[i].viewed);
  }
  seen_whole_.resize(views_.size());
  for (size_t i = 0; i < views_.size(); ++i)
    if (params_.layers[i].hole_free_coverage > 0) {
      // views_ never grows: the rule keeps a pointer to the marks.
      seen_whole_[i] = {&views_[i].seen_whole, params_.layers[i].hole_free_coverage,
                        params_.layers[i].min_points};
    }
  bands_.resize(views_.size());
  for (size_t i = 0; i < views_.size(); ++i)
    for (size_t j = i + 1; j < views_.size(); ++j) {
      const LayerHazardParams& c = params_.layers[j];
      bands_[i].add(&views_[j].map.height, &views_[j].map.variance, c.k_sigma,
                    c.resolution_m * std::tan(c.max_slope_rad));
    }
  // views_ never grows: the fallbacks may keep pointers to its grids.
  fills_.resize(views_.size());
  for (size_t i = 0; params.coarse_ring_fill && i + 1 < views_.size(); ++i)
    if (params_.layers[i].ring_tests && params_.layers[i + 1].family == HazardFamily::plane) {
      fills_[i] = std::make_unique<CoarseRingFill>(params_.layers[i + 1]);
      fills_[i]->set_grids(&views_[i + 1].map);
      classifiers_[i]->set_ring_fallback(fills_[i].get());
    }
}

void HazardStage::run(const LayerStack& map, const SensorView* view) {
  const RollingGrid& finest = map.layer(0).grid();
  // The planner's maps are centred like the finest layer, which shares its cell borders:
  // their first cell, in the finest layer's global indices.
  const int cells = fused_cells(params_.fused_extent_m, finest.resolution_m());
  const CellIndex fused_x0 = finest.origin_x() + finest.size() / 2 - cells / 2;
  const CellIndex fused_y0 = finest.origin_y() + finest.size() / 2 - cells / 2;
  if (!fused_at_.placed) {  // the comparison buffer's largest size, once: no allocation later
    size_t largest = static_cast<size_t>(cells) * cells;
    for (size_t i = 0; i < map.size(); ++i)
      largest = std::max(largest, static_cast<size_t>(map.layer(i).grid().size()) *
                                      static_cast<size_t>(map.layer(i).grid().size()));
    before_.reserve(largest);
  }
  fused_region_.clear();
  bool whole = false;
  // Coarsest first: a finer layer's rings may read the coarser layer's fresh export.
  for (size_t i = map.size(); i-- > 0;)
    if (!run_layer(map, i, fused_x0, fused_y0, cells, view)) whole = true;
  run_planner(whole, fused_x0, fused_y0, cells);
}

void HazardStage::explain(std::size_t i, DenseGrid& reasons) const {
  // The classifier's scratch buffers change, not the stage's maps.
  classifiers_[i]->explain(views_[i].map, reasons);
}

bool HazardStage::run_layer(const LayerStack& map, std::size_t i, CellIndex fused_x0,
                            CellIndex fused_y0, int cells, const SensorView* view) {
  const Layer& layer = map.layer(i);
  const RollingGrid& g = layer.grid();
  const int n = g.size();
  LayerState& s = layer_state_[i];
  LayerView& v = views_[i];
  const CellRange window = window_of(g);
  const Placement::Move move = s.at.move_to(window.x0, window.y0, n);
  const bool placed = move.placed;
  const CellRange& old_window = move.old_window;
  const int drow = move.drow, dcol = move.dcol;
  s.classified.clear();
  s.moved = move;
  // The coarser layer this one's rings read (coarse_ring_fill), run before this one: its
  // cells map onto whole blocks of this layer's, else this layer is classified whole.
  const bool fill = i + 1 < map.size() && fills_[i] != nullptr;
  const CellIndex coarse_scale =
      fill ? whole_scale(map.layer(i + 1).grid().resolution_m(), g.resolution_m()) : 0;
  const bool coarse_whole = fill && (layer_state_[i + 1].whole ||
                                     !layer_state_[i + 1].moved.placed || coarse_scale == 0);
  if (placed) {
    v.hazard.shift(drow, dcol, static_cast<float>(HazardClass::unknown));
    before_ = v.hazard.values;
  }
  // A per-cell mask of what frames saw moves with the window; cells new to it hold 0.
  const auto follow_window = [&](DenseGrid& mask) {
    if (placed) {
      mask.shift(drow, dcol, 0.0f);
      mask.center_x_m = g.center_x_m();
      mask.center_y_m = g.center_y_m();
    } else {
      mask.reset(n, n, g.resolution_m(), g.center_x_m(), g.center_y_m(), 0.0f);
    }
  };
  // The ring-only flags (footprint_centre_ring) move with the window like the hazard.
  const bool ring_only = params_.footprint_centre_ring;
  if (ring_only) {
    follow_window(v.ring_only);
    before_ring_ = v.ring_only.values;
  }
  // The view mask moves with the window (cells new to it: never looked at), then takes
  // this frame's view; the cells it newly reached are re-classified below.
  GridRect newly_viewed;
  if (params_.layers[i].partial_ring_proof == PartialRingProof::view_edge) {
    follow_window(v.viewed);
    if (view) {
      newly_viewed = marker_.mark(*view, v.viewed, &bands_[i]);
    } else if (std::any_of(v.viewed.values.begin(), v.viewed.values.end(),
                           [](float x) { return x < kWhollyViewed; })) {
      // No camera (points from elsewhere): nothing is known to be outside the view, so
      // every cell counts as looked at and only full rings prove.
      std::fill(v.viewed.values.begin(), v.viewed.values.end(), kWhollyViewed);
      newly_viewed = GridRect::full(n, n);
    }
  }

  // The hole-free marks move with the window (cells new to it: no verdict yet).
  const SeenWhole* seen_whole = seen_whole_[i].marks ? &seen_whole_[i] : nullptr;
  if (seen_whole) follow_window(v.seen_whole);
  // This frame's verdicts, on the export as it stands; the cells whose mark changed are
  // exported again (their plane) and returned.
  const auto mark_holes = [&]() -> GridRect {
    if (!seen_whole || !view) return {};
    const double limit = i < view->layer_depth_limit_m.size() && view->layer_depth_limit_m[i] > 0
                             ? view->layer_depth_limit_m[i]
                             : 1e300;
    return HoleMarker::mark(*view, v.map, params_.layers[i].hole_free_tolerance_px, v.seen_whole,
                            limit, pool_);
  };

  // Whole when the coarser layer this one's rings read was (rare: a jump, the first frame).
  s.whole = !incremental_ || !placed || map.exports_vary(i) || coarse_whole;
  if (s.whole) {
    map.export_layer(i, v.map, seen_whole);
    // Whole again, not the region: a layer exported whole may inflate every variance.
    if (!mark_holes().empty()) map.export_layer(i, v.map, seen_whole);
    classifiers_[i]->classify(v.map, v.hazard, v.diagnostics);
    s.classified.add(GridRect::full(n, n));
  } else {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for_each_grid(v.map, [&](DenseGrid& d) { d.shift(drow, dcol, nan); });
    v.diagnostics.kernel_range.shift(drow, dcol, nan);
    v.diagnostics.kernel_sigma.shift(drow, dcol, nan);
    v.diagnostics.kernel_fill.shift(drow, dcol, 0.0f);
    v.diagnostics.kernel_slope.shift(drow, dcol, nan);
    v.diagnostics.kernel_slope_sigma.shift(drow, dcol, nan);
    v.hazard.center_x_m = g.center_x_m();
    v.hazard.center_y_m = g.center_y_m();
    for (DenseGrid* d : {&v.diagnostics.kernel_range, &v.diagnostics.kernel_sigma,
                         &v.diagnostics.kernel_fill, &v.diagnostics.kernel_slope,
                         &v.diagnostics.kernel_slope_sigma})
      if (d->rows > 0) {  // plane layers leave them empty
        d->center_x_m = g.center_x_m();
        d->center_y_m = g.center_y_m();
      }
    // Cells whose export may differ: updated by the frame, or new to the window.
    scratch_.clear();
    scratch_.add(image_rect(map.changed_cells(i), 1, window.x0, window.y0, n));
    CellRange parts[4];
    for (int k = 0, m = difference(window, old_window, parts); k < m; ++k)
      scratch_.add(image_rect(parts[k], 1, window.x0, window.y0, n));
    for (const GridRect& r : scratch_) layer.export_region(v.map, r, seen_whole);
    const GridRect marked = mark_holes();
    if (!marked.empty()) {
      layer.export_region(v.map, marked, seen_whole);
      scratch_.add(marked);
    }
    // Results read cells up to reach_cells() away, inside the window: near the cells
    // above, near the strips that left (a kernel or ring there now leaves the layer), and
    // near the cells the view newly reached (a ring sample there is no longer unseen).
    scratch_.add(newly_viewed);
    for (int k = 0, m = difference(old_window, window, parts); k < m; ++k)
      scratch_.add(image_rect(parts[k], 1, window.x0, window.y0, n));
    if (fill) {  // and near what the coarser layer's rings read changed: cells and strips
      const Placement::Move& cm = layer_state_[i + 1].moved;
      const CellRange coarse = window_of(map.layer(i + 1).grid());
      scratch_.add(image_rect(map.changed_cells(i + 1), coarse_scale, window.x0, window.y0, n));
      for (int k = 0, m = difference(coarse, cm.old_window, parts); k < m; ++k)
        scratch_.add(image_rect(parts[k], coarse_scale, window.x0, window.y0, n));
      for (int k = 0, m = difference(cm.old_window, coarse, parts); k < m; ++k)
        scratch_.add(image_rect(parts[k], coarse_scale, window.x0, window.y0, n));
    }
    s.classified = scratch_;
    s.classified.dilate(classifiers_[i]->reach_cells(), n, n);
    for (const GridRect& r : s.classified) classifiers_[i]->classify(v.map, r, v.hazard, v.diagnostics);
  }
  if (!placed) return false;  // the fused map is redone whole

  // The fused map reads this layer where its hazard changed, and no longer reads it on
  // the strips that left its window. Outside the window and unknown read alike, so the
  // strips that entered matter only where their hazard is not unknown: a change.
  // Each of the layer's cells covers scale x scale fused cells (config validation makes
  // resolutions whole multiples; otherwise the fused map is redone whole).
  const CellIndex scale = whole_scale(g.resolution_m(), map.layer(0).grid().resolution_m());
  if (scale == 0) return false;
  const auto refuse = [&](const GridRect& changed) {
    fused_region_.add(image_rect(global_range(changed, window.x0, window.y0, n), scale, fused_x0,
                                 fused_y0, cells)
                          .dilated(1)
                          .clipped(cells, cells));
  };
  refuse(changed_bounds(v.hazard, before_, s.classified));
  // The fused clear grid reads the ring-only flags too.
  if (ring_only) refuse(changed_bounds(v.ring_only, before_ring_, s.classified));
  CellRange parts[4];
  for (int k = 0, m = difference(old_window, window, parts); k < m; ++k)
    fused_region_.add(
        image_rect(parts[k], scale, fused_x0, fused_y0, cells).dilated(1).clipped(cells, cells));
  return true;
}

void HazardStage::run_planner(bool whole, CellIndex fused_x0, CellIndex fused_y0, int cells) {
  const DenseGrid& finest = views_.front().hazard;
  const double r = finest.resolution_m;
  PlannerMaps& p = planner_;
  const CellRange window{fused_x0, fused_x0 + cells, fused_y0, fused_y0 + cells};
  const Placement::Move move = fused_at_.move_to(fused_x0, fused_y0, cells);
  const CellRange& old_window = move.old_window;
  DenseGrid* clear = params_.footprint_centre_ring ? &p.clear : nullptr;
  if (!incremental_ || whole || !move.placed) {
    fusion_.fuse(fusion_inputs_, params_.critical_height_m, cells, r, finest.center_x_m,
                 finest.center_y_m, p.fused, p.clearance, clear);
    fusion_.footprint(p.fused, params_.footprint_radius_m, p.footprint, p.hazard_distance, clear);
    fused_region_.clear();
    fused_region_.add(GridRect::full(cells, cells));
    footprint_region_ = fused_region_;
    return;
  }
  p.fused.shift(move.drow, move.dcol, static_cast<float>(HazardClass::unknown));
  p.clearance.shift(move.drow, move.dcol, std::numeric_limits<float>::quiet_NaN());
  p.footprint.shift(move.drow, move.dcol, static_cast<float>(HazardClass::unknown));
  if (clear) {
    clear->shift(move.drow, move.dcol, 0.0f);
    clear->center_x_m = finest.center_x_m;
    clear->center_y_m = finest.center_y_m;
  }
  for (DenseGrid* d : {&p.fused, &p.clearance}) {
    d->center_x_m = finest.center_x_m;
    d->center_y_m = finest.center_y_m;
  }
  CellRange entered[4], left[4];
  const int n_entered = difference(window, old_window, entered);
  const int n_left = difference(old_window, window, left);
  for (int k = 0; k < n_entered; ++k)
    fused_region_.add(image_rect(entered[k], 1, fused_x0, fused_y0, cells).clipped(cells, cells));
  // A cell's proof reads the hazards within the proof margin: re-fuse that far around
  // every change, and beside the strips that left (a hazard there no longer counts).
  if (const int m = fusion_.proof_margin_cells(); m > 0) {
    for (int k = 0; k < n_left; ++k)
      fused_region_.add(image_rect(left[k], 1, fused_x0, fused_y0, cells).dilated(m).clipped(cells, cells));
    fused_region_.dilate(m, cells, cells);
  }
  before_ = p.fused.values;
  if (clear) before_ring_ = clear->values;
  fusion_.fuse(fusion_inputs_, params_.critical_height_m, fused_region_, p.fused, p.clearance,
               clear);

  // The footprint reads the fused map within its radius, and the map's edge.
  footprint_region_.clear();
  footprint_region_.add(changed_bounds(p.fused, before_, fused_region_));
  if (clear) footprint_region_.add(changed_bounds(*clear, before_ring_, fused_region_));
  for (int k = 0; k < n_entered; ++k)
    footprint_region_.add(image_rect(entered[k], 1, fused_x0, fused_y0, cells));
  for (int k = 0; k < n_left; ++k)
    footprint_region_.add(image_rect(left[k], 1, fused_x0, fused_y0, cells));
  const int grow = static_cast<int>(std::ceil(params_.footprint_radius_m / r)) + 1;
  footprint_region_.dilate(grow, cells, cells);
  fusion_.footprint(p.fused, params_.footprint_radius_m, footprint_region_, p.footprint,
                    p.hazard_distance, clear);
}

}  // namespace hazmap
