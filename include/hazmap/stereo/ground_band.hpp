#pragma once
// The disparities terrain can produce on each ray of the rectified left camera (SPEC
// 3.4), from the camera's fixed pose on the body. This is what ground-band matching
// (band_matcher.hpp) searches instead of one range for the whole image.
//
// Terrain model, in the body frame B (wheel plane z_B = 0): level ground tilted by up to
// max_slope about the point of the wheel plane below the camera, raised by obstacles up
// to max_height or lowered by depressions down to max_depth. At horizontal distance rho
// from that point a surface point therefore has
//     -max_depth - tan(max_slope) rho  <=  z_B  <=  max_height + tan(max_slope) rho.
// Tilting about the point below the camera (not the body origin) keeps rho linear along
// a ray, so each ray's interval is exact and closed form; for a camera mounted over the
// body the two points are centimetres apart.
// Along the ray p(Z) = c + Z r (Z the depth in the rectified camera, d = f B / Z) both
// bounds are linear inequalities in Z, so the visible terrain lies in one interval
// [Z_near, Z_far]: d in [f B / Z_far, f B / Z_near]. Rays that stay inside the envelope
// to infinity (above the horizon, or looking down less steeply than the slope) reach
// disparity 0. A camera inside the envelope (below max_height) has Z_near = 0: an
// obstacle may stand in front of the lens. The cap bounds that case: see GroundBand().
// Thread safety: const methods may run concurrently.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/stereo/sensor_model.hpp"
#include "hazmap/stereo/stereo_config.hpp"

namespace hazmap {

/// A closed interval of disparities [lo, hi] in pixels; empty when hi < lo.
struct DisparityInterval {
  double lo = 0.0;
  double hi = -1.0;
  bool empty() const { return !(hi >= lo); }
  /// The smallest interval holding both (the hull).
  void include(const DisparityInterval& other);
};

/// The terrain the band must admit (SPEC 3.4; `stereo.band_max_*`).
struct TerrainEnvelope {
  double max_slope_deg = 30.0;
  double max_height_m = 0.5;
  double max_depth_m = 0.5;
  static TerrainEnvelope from(const StereoConfig& stereo);
};


class GroundBand {
 public:
  /// `geometry`: the rectified pair; `T_B_Cr`: the rectified left camera in the body
  /// frame; `max_disparity_px`: the cap on every interval (> 0). Throws Error for a
  /// non-positive focal length, baseline or cap, or a slope outside [0, 90).
  GroundBand(const StereoGeometry& geometry, const Pose3d& T_B_Cr, const TerrainEnvelope& envelope,
             double max_disparity_px);

  /// Disparities of terrain on the ray through pixel (u, v), hi capped at
  /// max_disparity(). Empty when the ray meets no terrain of the envelope (e.g. steeply
  /// upwards) or only nearer than the cap.
  DisparityInterval pixel(double u, double v) const;

  /// Hull of pixel() over the pixel centres u = 0 .. width - 1 of row v.
  DisparityInterval row(int v, int width) const;

  /// row() for every row of an image of `size`.
  std::vector<DisparityInterval> rows(cv::Size size) const;

  double max_disparity() const { return max_disparity_; }
  const TerrainEnvelope& envelope() const { return envelope_; }

 private:
  StereoGeometry geometry_;
  TerrainEnvelope envelope_;
  Eigen::Matrix3d R_B_Cr_;
  double camera_height_m_ = 0.0;  ///< camera centre above the wheel plane (z_B)
  double tan_slope_ = 0.0;
  double max_disparity_ = 0.0;
};

}  // namespace hazmap
