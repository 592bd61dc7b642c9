#include "hazmap/map/map_points.hpp"

#include <algorithm>
#include <cmath>

namespace hazmap {

float ccm_weight(CcmWeighting weighting, const Measurement& m) {
  if (weighting == CcmWeighting::constant) return 1.0f;
  const double xx = m.cov_xx, xy = m.cov_xy, xz = m.cov_xz, yy = m.cov_yy, yz = m.cov_yz,
               zz = m.cov_zz;
  const double value = weighting == CcmWeighting::trace
                           ? xx + yy + zz
                           : xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) +
                                 xz * (xy * yz - yy * xz);
  return static_cast<float>(1.0 / value);
}

void MapPoints::assign(const PointCloud& cloud, CcmWeighting weighting) {
  size_ = static_cast<int>(cloud.size());
  const std::size_t padded = cloud.size() + PointChunk::kPad;
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_}) v->resize(padded, 0.0f);
  for (int i = 0; i < size_; ++i) {
    const Measurement& m = cloud[static_cast<std::size_t>(i)];
    x_[i] = m.p_W.x();
    y_[i] = m.p_W.y();
    z_[i] = m.p_W.z();
    inv_var_z_[i] = 1.0f / m.cov_zz;
    var_z_[i] = m.cov_zz;
    // The major axis of the horizontal covariance: max(xx, yy) alone halves the variance
    // of a ray seen at 45 deg to the axes and lets far points through the gate.
    const float half_sum = 0.5f * (m.cov_xx + m.cov_yy), half_gap = 0.5f * (m.cov_xx - m.cov_yy);
    lateral_var_[i] = half_sum + std::sqrt(half_gap * half_gap + m.cov_xy * m.cov_xy);
  }
  unit_ccm_weight_ = weighting == CcmWeighting::constant;
  if (weighting == CcmWeighting::constant)
    std::fill(ccm_weight_.begin(), ccm_weight_.begin() + size_, 1.0f);
  else
    for (int i = 0; i < size_; ++i) ccm_weight_[i] = ccm_weight(weighting, cloud[static_cast<std::size_t>(i)]);
}

MapPoints::Fill MapPoints::begin_fill(std::size_t max_points) {
  const std::size_t padded = max_points + PointChunk::kPad;
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_})
    if (v->size() < padded) v->resize(padded, 0.0f);
  size_ = 0;
  return {x_.data(), y_.data(), z_.data(), inv_var_z_.data(), var_z_.data(), lateral_var_.data(),
          ccm_weight_.data()};
}

void MapPoints::end_fill(int count, bool unit_ccm_weight) {
  size_ = count;
  unit_ccm_weight_ = unit_ccm_weight;
  if (unit_ccm_weight) std::fill(ccm_weight_.begin(), ccm_weight_.begin() + size_, 1.0f);
  // Chunks read up to kPad floats past the last point: keep them finite and inert.
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_})
    std::fill(v->begin() + size_, v->begin() + size_ + PointChunk::kPad, 0.0f);
}

PointChunk MapPoints::chunk(int begin, int count) const {
  PointChunk c;
  c.x = x_.data() + begin;
  c.y = y_.data() + begin;
  c.z = z_.data() + begin;
  c.inv_var_z = inv_var_z_.data() + begin;
  c.ccm_weight = ccm_weight_.data() + begin;
  c.unit_ccm_weight = unit_ccm_weight_;
  c.lateral_var = lateral_var_.data() + begin;
  c.var_z = var_z_.data() + begin;
  c.size = count;
  return c;
}

}  // namespace hazmap
