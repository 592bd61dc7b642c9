// The points stage at full CADRE resolution (issue 20): a 1600 x 1300 disparity image of
// level ground seen from 15 cm, pitched down 34 deg (f = 671 px, B = 5 cm, 320
// disparities: what cadre_full_res.yaml maps), turned into the map's input two ways in
// the same run: today's reference (a cloud with double covariances, then
// MapPoints::assign) and the direct float path (build_map_points). ns per point.

#include <cmath>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/stereo/point_cloud_builder.hpp"

namespace hazmap::bench {
namespace {

constexpr int kWidth = 1600, kHeight = 1300;
constexpr double kFocalPx = 671.0, kBaselineM = 0.05, kHeightM = 0.15, kPitchDeg = 34.0;
constexpr int kMaxDisparity = 320;

struct Scene {
  StereoConfig stereo;
  SensorConfig sensor;
  StereoGeometry geometry{kFocalPx, kBaselineM, (kWidth - 1) / 2.0, (kHeight - 1) / 2.0};
  Pose3d T_B_C = Pose3d::Identity();
  cv::Mat disparity_x16{kHeight, kWidth, CV_16S, cv::Scalar(0)};

  Scene() {
    stereo.z_max_m = 3.0;
    const double p = kPitchDeg * M_PI / 180.0, c = std::cos(p), s = std::sin(p);
    Eigen::Matrix3d R;  // columns: the camera's x (right), y (down), z (forward) in B
    R.col(0) = Eigen::Vector3d(0, -1, 0);
    R.col(2) = Eigen::Vector3d(c, 0, -s);
    R.col(1) = R.col(2).cross(R.col(0));
    T_B_C.linear() = R;
    T_B_C.translation() = Eigen::Vector3d(0, 0, kHeightM);
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        const Eigen::Vector3d ray((u - geometry.cx_px) / kFocalPx, (v - geometry.cy_px) / kFocalPx, 1);
        const double down = (R * ray).z();
        if (down >= 0) continue;  // above the horizon
        const double d = kFocalPx * kBaselineM / (kHeightM / -down);
        if (d < kMaxDisparity) disparity_x16.at<short>(v, u) = static_cast<short>(std::lround(d * 16));
      }
  }
  PointCloudBuilder builder() const {
    return PointCloudBuilder(stereo, sensor, geometry, Eigen::Matrix3d::Identity(), T_B_C,
                             cv::Rect(0, 0, kWidth, kHeight));
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

const Pose3d kPose = Pose3d(Eigen::Translation3d(12.3, -4.5, 0.2) *
                            Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));

void per_point(benchmark::State& state, int points) {
  state.counters["points"] = points;
  state.counters["ns_per_point"] = benchmark::Counter(
      points, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_PointsStageCloudThenAssign(benchmark::State& state) {
  const PointCloudBuilder b = scene().builder();
  PointCloud cloud;
  MapPoints points;
  for (auto _ : state) {
    b.build(scene().disparity_x16, 0, kPose, cloud);
    points.assign(cloud, CcmWeighting::constant);
    benchmark::DoNotOptimize(points.chunk(0, 1).x);
  }
  per_point(state, points.size());
}

void BM_PointsStageDirect(benchmark::State& state) {
  const PointCloudBuilder b = scene().builder();
  MapPoints points;
  for (auto _ : state) {
    b.build_map_points(scene().disparity_x16, 0, kPose, CcmWeighting::constant, points);
    benchmark::DoNotOptimize(points.chunk(0, 1).x);
  }
  per_point(state, points.size());
}

BENCHMARK(BM_PointsStageCloudThenAssign)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PointsStageDirect)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hazmap::bench
