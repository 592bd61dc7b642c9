#pragma once
// Ground truth from a scanned point cloud in W (`hazmap ground-truth`, SPEC 13): the
// gt_height / gt_hazard pair `hazmap evaluate` reads (SPEC 9, 10), on the same aligned
// grid layout `hazmap simulate` writes and with the same obstacle definition
// (eval/ground_truth.hpp: obstacle height = surface - local ground, >= 0).
//
// Height of a cell (resolution r):
//   - >= 1 point in the cell: the least-squares plane through the cell's points,
//     evaluated at the cell centre and clamped to the points' z range (3+ points spread
//     over the cell), otherwise their mean: the surface at the centre, not the mean of
//     where the scanner happened to hit.
//   - no point: filled only where the scan is dense around the cell: the points within
//     `fill_radius_m` of the centre must lie in all four quadrants around it (the cell is a
//     hole between samples, not the edge of a shadow or of the scan); then the plane
//     through those points at the centre, clamped to their z range. Otherwise NaN.
// Local ground (a scan does not say which points are rock):
//   1. the lower envelope at scale R = `ground_radius_m`: a morphological opening of the
//      height grid by a disc of radius R (erosion then dilation; NaN cells take no part).
//      It removes every bump narrower than 2R and follows the ground where it is
//      smoother than that;
//   2. ground cells: height - envelope <= `ground_tolerance_m`; there ground = height
//      (obstacle height exactly 0);
//   3. other cells (obstacles): ground interpolated harmonically (Laplace's equation,
//      Gauss-Seidel) from the ground cells around them, so a plane is recovered exactly
//      under a rock; an obstacle region touching no ground cell keeps the envelope.
//   Obstacle height = obstacle_height_m(height, ground).
// So an obstacle is what stands more than ground_tolerance_m above the ground and is
// narrower than 2R. Convex ground relief sharper than that (a crater's rim crest at the
// default R) is counted as obstacle, unlike in `hazmap simulate`, which knows its ground.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hazmap/io/jdem.hpp"

namespace hazmap {

struct CloudGroundTruthOptions {
  double resolution_m = 0.01;
  /// Gap filling radius; <= 0 means 3 cells (3 * resolution_m). 0 < r < resolution/2: no filling.
  double fill_radius_m = 0.0;
  double ground_radius_m = 0.15;     ///< R: obstacles narrower than 2R are found
  double ground_tolerance_m = 0.003; ///< relief above the envelope still called ground
  /// Optional crop in W ([x0, x1] x [y0, y1]); all zero: the cloud's bounding box.
  double x0_m = 0.0, x1_m = 0.0, y0_m = 0.0, y1_m = 0.0;
};

/// Throws Error naming the option (as its command-line flag) if unusable.
void validate(const CloudGroundTruthOptions& options);

struct CloudGroundTruth {
  JdemGrid height;  ///< gt_height: surface height [m], NaN unknown
  JdemGrid hazard;  ///< gt_hazard: obstacle height above the local ground [m], NaN unknown
  std::size_t points = 0;         ///< points inside the grid
  std::size_t cells_measured = 0; ///< cells with points
  std::size_t cells_filled = 0;   ///< cells filled from the neighbourhood
  std::size_t cells_unknown = 0;  ///< NaN cells
  std::size_t cells_obstacle = 0; ///< cells with obstacle height > 0
};

/// The grids for `points` (W, metres). Throws Error if no point lies in the crop.
CloudGroundTruth cloud_ground_truth(const std::vector<Eigen::Vector3d>& points,
                                    const CloudGroundTruthOptions& options);

/// Writes DIR/gt_height.jdem, DIR/gt_hazard.jdem and DIR/ground_truth.yaml (what was done,
/// for people: source cloud, options, cell counts), creating DIR. Atomic per file.
void write_cloud_ground_truth(const std::filesystem::path& dir, const CloudGroundTruth& gt,
                              const CloudGroundTruthOptions& options,
                              const std::string& source_cloud);

}  // namespace hazmap
