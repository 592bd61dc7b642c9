#pragma once
// A 3-D point in the world frame with its covariance: the map's only input.

#include <algorithm>
#include <vector>

#include <Eigen/Core>

namespace hazmap {

struct Measurement {
  Eigen::Vector3f p_W;  ///< metres, world frame
  /// Upper triangle of the world-frame covariance [m^2]: xx xy xz yy yz zz.
  float cov_xx, cov_xy, cov_xz, cov_yy, cov_yz, cov_zz;
  /// Derived once per point by prepare_measurements(), so that no layer divides per point.
  float inv_var_z;    ///< 1 / cov_zz: Kalman and OMG weight
  float ccm_weight;   ///< CCM weight (constant 1, 1/trace or 1/det of the covariance)
  float lateral_var;  ///< max(cov_xx, cov_yy): the CCM gate compares it per layer

  float height_variance() const { return cov_zz; }
};

/// One frame's points; the buffer is reused from frame to frame.
using PointCloud = std::vector<Measurement>;

/// CCM point weighting (SPEC 4, rules.ccm.weighting).
enum class CcmWeighting { constant, trace, det };

/// Fills the derived fields of every point (one pass, no allocation).
inline void prepare_measurements(PointCloud& cloud, CcmWeighting weighting) {
  for (Measurement& m : cloud) {
    m.inv_var_z = 1.0f / m.cov_zz;
    m.lateral_var = std::max(m.cov_xx, m.cov_yy);
    switch (weighting) {
      case CcmWeighting::constant: m.ccm_weight = 1.0f; break;
      case CcmWeighting::trace: m.ccm_weight = 1.0f / (m.cov_xx + m.cov_yy + m.cov_zz); break;
      case CcmWeighting::det: {
        const double det = double(m.cov_xx) * (double(m.cov_yy) * m.cov_zz - double(m.cov_yz) * m.cov_yz) -
                           double(m.cov_xy) * (double(m.cov_xy) * m.cov_zz - double(m.cov_yz) * m.cov_xz) +
                           double(m.cov_xz) * (double(m.cov_xy) * m.cov_yz - double(m.cov_yy) * m.cov_xz);
        m.ccm_weight = static_cast<float>(1.0 / det);
        break;
      }
    }
  }
}

}  // namespace hazmap
