#pragma once
// Points as the pipeline produces them: one frame of a CADRE-like camera (15 cm above
// flat-ish ground, pitched down 34 deg) in image scan-line order, with axis-model
// covariance. Deterministic.

#include "hazmap/map/measurement.hpp"

namespace hazmap::bench {

/// Fills `cloud` with the ground points of a width x height image (f scales with width,
/// as CADRE's 671 px at 1600), body at (x0, 0) looking along +x, up to `max_range_m`.
void scanline_ground_points(PointCloud& cloud, int width, int height, double x0_m,
                            double max_range_m);

}  // namespace hazmap::bench
