// The points stage's direct path (PointCloudBuilder::build_map_points, issue 20) against
// today's path (build the cloud with double covariances, then MapPoints::assign): same
// points in the same order, every field within float rounding, for every CCM weighting,
// with the stride, the below-ground and the steep-ray checks in play.

#include <cmath>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// |a - b| within `rel` of |b| (and a tiny absolute floor for values near 0).
::testing::AssertionResult close(float a, float b, float rel) {
  if (std::abs(a - b) <= rel * std::abs(b) + 1e-12f) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b;
}

/// Returns the points both paths dropped as below ground.
std::size_t compare(const std::vector<std::string>& sets, CcmWeighting weighting) {
  const Config c = load_config(testing::source_dir() / "config/default.yaml", sets);
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  const SequenceFrame& frame = seq.frames.back();  // a moved, turned pose
  const cv::Mat left = read_image(frame.left_path), right = read_image(frame.right_path);

  StereoFrontEnd reference(c.stereo, c.sensor, seq.calibration, false);
  reference.process(left, right, frame.pose.T_W_B);
  const MapPoints expected(reference.cloud(), weighting);

  StereoFrontEnd direct(c.stereo, c.sensor, seq.calibration, false);
  direct.set_map_points_output(weighting);
  direct.process(left, right, frame.pose.T_W_B);
  const MapPoints& got = direct.map_points();

  EXPECT_GT(expected.size(), 10000);
  EXPECT_EQ(got.size(), expected.size());
  if (got.size() != expected.size()) return 0;
  EXPECT_EQ(direct.points_below_ground(), reference.points_below_ground());
  int checked = 0;
  for (int start = 0; start < got.size(); start += PointChunk::kCapacity) {
    const int count = std::min(PointChunk::kCapacity, got.size() - start);
    const PointChunk g = got.chunk(start, count), x = expected.chunk(start, count);
    EXPECT_EQ(g.unit_ccm_weight, x.unit_ccm_weight);
    for (int i = 0; i < count; ++i, ++checked) {
      // Positions: float rounding of metres-scale sums, 2 micrometres.
      bool ok = std::abs(g.x[i] - x.x[i]) <= 2e-6f && std::abs(g.y[i] - x.y[i]) <= 2e-6f &&
                std::abs(g.z[i] - x.z[i]) <= 2e-6f;
      // Variances: closed forms against products of rounded entries, 1e-5 relative.
      ok = ok && close(g.var_z[i], x.var_z[i], 1e-5f) && close(g.inv_var_z[i], x.inv_var_z[i], 1e-5f) &&
           close(g.lateral_var[i], x.lateral_var[i], 1e-4f);
      // det of rounded entries loses more: 1e-3.
      ok = ok && (g.unit_ccm_weight || close(g.ccm_weight[i], x.ccm_weight[i], 1e-3f));
      if (!ok) {
        ADD_FAILURE() << "point " << start + i << ": (" << g.x[i] << ", " << g.y[i] << ", " << g.z[i]
                      << ") var_z " << g.var_z[i] << " lateral " << g.lateral_var[i] << " w "
                      << g.ccm_weight[i] << " against (" << x.x[i] << ", " << x.y[i] << ", "
                      << x.z[i] << ") " << x.var_z[i] << " " << x.lateral_var[i] << " "
                      << x.ccm_weight[i];
        return 0;
      }
    }
  }
  EXPECT_EQ(checked, expected.size());
  // The cloud, asked for after a map-points frame, is the reference's exactly.
  const PointCloud& lazy = direct.cloud();
  EXPECT_EQ(lazy.size(), reference.cloud().size());
  if (lazy.size() != reference.cloud().size()) return 0;
  for (size_t i = 0; i < lazy.size(); i += 997) {
    EXPECT_EQ(lazy[i].p_W, reference.cloud()[i].p_W);
    EXPECT_EQ(lazy[i].cov_zz, reference.cloud()[i].cov_zz);
  }
  return reference.points_below_ground();
}

TEST(MapPointsPath, EqualsTheCloudPathWithConstantWeights) {
  EXPECT_EQ(compare({}, CcmWeighting::constant), 0u);  // the sample's points are all above
}

TEST(MapPointsPath, EqualsTheCloudPathWithTraceAndDetWeightsAndAStride) {
  compare({"stereo.stride=2"}, CcmWeighting::trace);
  compare({"stereo.stride=3"}, CcmWeighting::det);
}

TEST(MapPointsPath, EqualsTheCloudPathWithTheGroundChecksBiting) {
  // Tight below-ground limits so that both checks drop points on the sample's terrain.
  EXPECT_GT(compare({"stereo.max_below_ground=0.01", "stereo.below_ground_tolerance=0.002",
                     "stereo.max_depression_slope_deg=10"},
                    CcmWeighting::constant),
            1000u);
}

TEST(MapPointsPath, TheRayModelKeepsTheCloudPath) {
  const Config c = load_config(testing::source_dir() / "config/default.yaml", {"sensor.model=ray"});
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  StereoFrontEnd front(c.stereo, c.sensor, seq.calibration, false);
  EXPECT_THROW(front.set_map_points_output(CcmWeighting::constant), Error);
}

}  // namespace
}  // namespace hazmap
