// The hole-free test looks at a layer's cells only as deep as the layer takes points
// (Pipeline: SensorView::layer_depth_limit_m): at that depth a point at the image centre
// has the layer's lateral gate as its lateral sigma in W. Checked against the sensor
// model's covariance rotated into W and an eigen-solver, on the shipped flight config.

#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/pipeline/pipeline.hpp"
#include "hazmap/stereo/sensor_model.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

TEST(LayerDepthLimit, EachGatedLayerEndsWhereItsGateDropsTheImageCentre) {
  const Config config = load_config(testing::source_dir() / "config/cadre_flight.yaml");
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  const Pipeline pipeline(config, seq.calibration);
  const SensorView& view = pipeline.sensor_view();
  const StereoGeometry& g = pipeline.rectifier().geometry();
  ASSERT_EQ(view.layer_depth_limit_m.size(), config.map.layers.size());
  const auto lateral_std = [&](double z) {
    const Eigen::Matrix3d C = config.sensor.model == SensorModel::ray
                                  ? covariance_ray(g, g.cx_px, g.cy_px, g.focal_px * g.baseline_m / z,
                                                   config.sensor.pointing_error_px, config.sensor.disparity_error_px)
                                  : covariance_axis(g, z, config.sensor.pointing_error_px,
                                                    config.sensor.disparity_error_px);
    const Eigen::Matrix3d W = view.T_B_C.linear() * C * view.T_B_C.linear().transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(W.topLeftCorner<2, 2>());
    return std::sqrt(eig.eigenvalues().maxCoeff());
  };
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    SCOPED_TRACE("layer " + std::to_string(i));
    const double gate = gate_std_m(config.map.layers[i], config.rules);
    const double limit = view.layer_depth_limit_m[i];
    if (gate <= 0) {
      EXPECT_EQ(limit, 0.0);
      continue;
    }
    if (limit >= config.stereo.z_max_m) {  // the gate never bites within the depth range
      EXPECT_LE(lateral_std(config.stereo.z_max_m), gate);
      continue;
    }
    EXPECT_LT(lateral_std(0.999 * limit), gate);
    EXPECT_GT(lateral_std(1.001 * limit), gate);
  }
  // The 4 cm layer (max_std_ratio 1.5) takes points to about a metre (the config's
  // comment: ~0.95 m of ground ahead of the camera; this is depth at the image centre).
  EXPECT_GT(view.layer_depth_limit_m[1], 0.8);
  EXPECT_LT(view.layer_depth_limit_m[1], 1.3);
}

}  // namespace
}  // namespace hazmap
