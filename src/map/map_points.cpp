#include "hazmap/map/map_points.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

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

namespace {

// A Measurement is nine floats (x y z, then the covariance's upper triangle) and a cloud
// a contiguous array of them: four records are 36 floats, nine whole vectors.
static_assert(sizeof(Measurement) == 9 * sizeof(float), "Measurement: nine floats, no padding");
constexpr int kFields = 9;

/// The columns MapPoints keeps, one point at a time. The four-lane path below makes the
/// same operations in the same order (a division and a square root are exact in IEEE
/// arithmetic; there is no FMA here to fuse the rest), so both give the same bits.
struct Columns {
  float *x, *y, *z, *inv_var_z, *var_z, *lateral_var;
  void set(int i, const Measurement& m) const {
    x[i] = m.p_W.x();
    y[i] = m.p_W.y();
    z[i] = m.p_W.z();
    inv_var_z[i] = 1.0f / m.cov_zz;
    var_z[i] = m.cov_zz;
    // The major axis of the horizontal covariance: max(xx, yy) alone halves the variance
    // of a ray seen at 45 deg to the axes and lets far points through the gate.
    const float half_sum = 0.5f * (m.cov_xx + m.cov_yy), half_gap = 0.5f * (m.cov_xx - m.cov_yy);
    lateral_var[i] = half_sum + std::sqrt(half_gap * half_gap + m.cov_xy * m.cov_xy);
  }
};

#if defined(__SSE2__)
/// Field `f` of the four records loaded in v[0..8]: record j's field is float 9 j + f,
/// lane (9 j + f) % 4 of vector (9 j + f) / 4; three shuffles gather the four lanes.
template <int f>
[[gnu::always_inline]] inline __m128 column(const __m128* v) {
  constexpr int a = f, b = kFields + f, c = 2 * kFields + f, d = 3 * kFields + f;
  const __m128 ab = _mm_shuffle_ps(v[a / 4], v[b / 4], _MM_SHUFFLE(b % 4, b % 4, a % 4, a % 4));
  const __m128 cd = _mm_shuffle_ps(v[c / 4], v[d / 4], _MM_SHUFFLE(d % 4, d % 4, c % 4, c % 4));
  return _mm_shuffle_ps(ab, cd, _MM_SHUFFLE(2, 0, 2, 0));
}

/// Columns of points [0, n - n % 4), four at a time: a transpose in registers instead of
/// a scalar load per field, and one vector division and square root per four points
/// (the scalar loop spent most of its time in them). Returns the points done.
int set_columns4(const Measurement* records, int n, const Columns& out) {
  const float* a = reinterpret_cast<const float*>(records);
  const __m128 half = _mm_set1_ps(0.5f), one = _mm_set1_ps(1.0f);
  int i = 0;
  for (; i + 4 <= n; i += 4, a += 4 * kFields) {
    __m128 v[kFields];
    for (int k = 0; k < kFields; ++k) v[k] = _mm_loadu_ps(a + 4 * k);
    const __m128 xx = column<3>(v), xy = column<4>(v), yy = column<6>(v), zz = column<8>(v);
    _mm_storeu_ps(out.x + i, column<0>(v));
    _mm_storeu_ps(out.y + i, column<1>(v));
    _mm_storeu_ps(out.z + i, column<2>(v));
    _mm_storeu_ps(out.inv_var_z + i, _mm_div_ps(one, zz));
    _mm_storeu_ps(out.var_z + i, zz);
    const __m128 half_sum = _mm_mul_ps(half, _mm_add_ps(xx, yy));
    const __m128 half_gap = _mm_mul_ps(half, _mm_sub_ps(xx, yy));
    const __m128 root =
        _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(half_gap, half_gap), _mm_mul_ps(xy, xy)));
    _mm_storeu_ps(out.lateral_var + i, _mm_add_ps(half_sum, root));
  }
  return i;
}
#else
int set_columns4(const Measurement*, int, const Columns&) { return 0; }
#endif

}  // namespace

void MapPoints::assign(const PointCloud& cloud, CcmWeighting weighting) {
  size_ = static_cast<int>(cloud.size());
  const std::size_t padded = cloud.size() + PointChunk::kPad;
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_}) v->resize(padded, 0.0f);
  unit_weights_ = std::min(unit_weights_, size_);  // a smaller frame shrank the arrays
  const Columns out{x_.data(), y_.data(), z_.data(), inv_var_z_.data(), var_z_.data(), lateral_var_.data()};
  for (int i = set_columns4(cloud.data(), size_, out); i < size_; ++i)
    out.set(i, cloud[static_cast<std::size_t>(i)]);
  unit_ccm_weight_ = weighting == CcmWeighting::constant;
  if (weighting == CcmWeighting::constant) {
    fill_unit_weights();
  } else {
    for (int i = 0; i < size_; ++i) ccm_weight_[i] = ccm_weight(weighting, cloud[static_cast<std::size_t>(i)]);
    unit_weights_ = 0;
  }
}

void MapPoints::fill_unit_weights() {
  // Only past what an earlier frame left at 1: in a run with constant weights the array
  // is written once, not once per frame (4 bytes per point less to write).
  if (unit_weights_ < size_) std::fill(ccm_weight_.begin() + unit_weights_, ccm_weight_.begin() + size_, 1.0f);
  unit_weights_ = std::max(unit_weights_, size_);
}

MapPoints::Fill MapPoints::begin_fill(std::size_t max_points) {
  const std::size_t padded = max_points + PointChunk::kPad;
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_})
    if (v->size() < padded) v->resize(padded, 0.0f);
  size_ = 0;
  unit_weights_ = 0;  // the producer may write any weight
  return {x_.data(), y_.data(), z_.data(), inv_var_z_.data(), var_z_.data(), lateral_var_.data(),
          ccm_weight_.data()};
}

void MapPoints::end_fill(int count, bool unit_ccm_weight) {
  size_ = count;
  unit_ccm_weight_ = unit_ccm_weight;
  if (unit_ccm_weight) fill_unit_weights();
  // Chunks read up to kPad floats past the last point: keep them finite and inert.
  for (auto* v : {&x_, &y_, &z_, &inv_var_z_, &ccm_weight_, &lateral_var_, &var_z_})
    std::fill(v->begin() + size_, v->begin() + size_ + PointChunk::kPad, 0.0f);
  unit_weights_ = std::min(unit_weights_, size_);  // the padding is 0
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
