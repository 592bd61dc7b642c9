#include "hazmap/map/point_chunk.hpp"

#include <algorithm>

namespace hazmap {

PointChunk::PointChunk() {
  for (float* a : {x, y, z, inv_var_z, ccm_weight, lateral_var}) std::fill(a, a + kStride, 0.0f);
}

void PointChunk::fill(const Measurement* points, int count) {
  size = count;
  for (int i = 0; i < count; ++i) {
    const Measurement& m = points[i];
    x[i] = m.p_W.x();
    y[i] = m.p_W.y();
    z[i] = m.p_W.z();
    inv_var_z[i] = m.inv_var_z;
    ccm_weight[i] = m.ccm_weight;
    lateral_var[i] = m.lateral_var;
  }
}

}  // namespace hazmap
