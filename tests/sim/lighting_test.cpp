// Low sun, cast shadows, regolith albedo and imperfect cameras (issue 33): shadows land
// where geometry puts them, camera noise has the statistics of its keys, the residual row
// offset is the one asked for, and everything is deterministic per seed.

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/sim/renderer.hpp"
#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"
#include "sim_fixtures.hpp"
#include "test_support.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A camera 2 m above the ground looking straight down, 1 px = 2 mm on the ground:
// W point (x, y, 0) is seen at u = cx + 500 (x - x0), v = cy - 500 y.
struct NadirView {
  PinholeCamera camera;
  Pose3d T_W_C = Pose3d::Identity();
  double x0_m = 0.0;
  static constexpr double kHeightM = 2.0;
  static constexpr double kFocalPx = 1000.0;
  double metres_per_px() const { return kHeightM / kFocalPx; }

  explicit NadirView(double x0) : x0_m(x0) {
    camera.width_px = 301;
    camera.height_px = 41;
    camera.fx_px = camera.fy_px = kFocalPx;
    camera.cx_px = 150.0;
    camera.cy_px = 20.0;
    T_W_C.linear() << 1, 0, 0,  //
        0, -1, 0,               //
        0, 0, -1;
    T_W_C.translation() = Eigen::Vector3d(x0, 0.0, kHeightM);
  }
  double x_of_u(double u) const { return x0_m + (u - camera.cx_px) * metres_per_px(); }
};

RenderOptions plain_low_sun(double elevation_deg, double azimuth_deg) {
  RenderOptions options;
  options.texture_contrast = 0.0;  // albedo = its mean: lit ground 100 DN, shadow 0
  options.ambient = 0.0;
  options.noise_sigma_dn = 0.0;
  options.sun_elevation_deg = elevation_deg;
  options.sun_azimuth_deg = azimuth_deg;
  return options;
}

// A hemisphere of radius r on flat ground (a sphere centred on the ground) with the sun at
// elevation e: the sun ray tangent to it meets the ground r / sin(e) from its centre.
// (A cylinder of height h would cast h / tan(e) from its edge; a hemisphere's shadow tip
// is set by the tangent ray instead.) Measured on the image row through the rock's
// centre as the length of the dark run beyond the rock, in pixels.
void expect_rock_shadow_tip(bool terrain_shadows, double elevation_deg) {
  constexpr double kRadiusM = 0.1;
  constexpr double kRockXM = 1.0;
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  terrain_options.extra_rocks = {{kRockXM, 0.0, kRadiusM, 0.0}};
  const Terrain terrain = make_terrain(terrain_options);
  RenderOptions options = plain_low_sun(elevation_deg, 180.0);  // sun at -x: shadow to +x
  options.terrain_shadows = terrain_shadows;
  const Renderer renderer(terrain, options, 1);
  const NadirView view(1.3);
  const cv::Mat image = renderer.render(view.camera, view.T_W_C, 0);
  const double lit_dn = options.exposure_dn * options.ground_albedo;

  // Dark fraction summed from the rock's far edge (x = 1.1 m) outwards: the shadow's
  // length beyond the rock in pixels (partly shadowed pixels count in part).
  const int v = static_cast<int>(view.camera.cy_px);
  double dark_px = 0.0;
  for (int u = 0; u < view.camera.width_px; ++u) {
    if (view.x_of_u(u) < kRockXM + kRadiusM) continue;
    dark_px += 1.0 - image.at<unsigned char>(v, u) / lit_dn;
  }
  // Pixel u covers [x_of_u(u) - 1 mm, + 1 mm): the first pixel past 1.1 m starts there.
  int first_u = 0;
  while (view.x_of_u(first_u) < kRockXM + kRadiusM) ++first_u;
  const double shadow_end_m = view.x_of_u(first_u) - 0.5 * view.metres_per_px() +
                              dark_px * view.metres_per_px();
  const double expected_m = kRockXM + kRadiusM / std::sin(elevation_deg * kPi / 180.0);
  EXPECT_NEAR(shadow_end_m, expected_m, view.metres_per_px())
      << "terrain_shadows " << terrain_shadows << ", elevation " << elevation_deg;
  // Beyond the tip the ground is lit; just before it, dark.
  const int tip_u = static_cast<int>(std::lround(view.camera.cx_px +
                                                 (expected_m - view.x0_m) / view.metres_per_px()));
  EXPECT_EQ(image.at<unsigned char>(v, tip_u + 3), static_cast<unsigned char>(lit_dn));
  EXPECT_EQ(image.at<unsigned char>(v, tip_u - 3), 0);
}

TEST(Lighting, RockShadowOnFlatGroundEndsWhereTheTangentRayMeetsTheGround) {
  for (const double elevation : {15.0, 25.0}) {
    expect_rock_shadow_tip(false, elevation);  // rock shadows only (sun rays vs rocks)
    expect_rock_shadow_tip(true, elevation);   // traced over the terrain and rocks
  }
}

// A crater's rim shadows its floor: with the sun at -x and elevation e, the sun ray through
// the rim crest (x = -R, z = h, relative to the centre) meets the bowl
// z = -D + (h + D) (x / R)^2 at the positive root of k x^2 + tan(e) x + tan(e) R - h - D = 0,
// k = (h + D) / R^2. Ground between the crest and that point is dark, beyond it lit.
TEST(Lighting, CraterRimShadowsTheFloorUpToTheAnalyticPoint) {
  const Crater crater{2.0, 0.0, 0.5, 0.1, 0.02};
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  terrain_options.extra_craters = {crater};
  const Terrain terrain = make_terrain(terrain_options);
  const double e = 10.0 * kPi / 180.0;
  const double k = (crater.rim_height_m + crater.depth_m) / (crater.radius_m * crater.radius_m);
  const double b = std::tan(e);
  const double c = std::tan(e) * crater.radius_m - crater.rim_height_m - crater.depth_m;
  const double expected_x = crater.x_m + (-b + std::sqrt(b * b - 4.0 * k * c)) / (2.0 * k);

  auto lit_from = [&](bool terrain_shadows) {
    RenderOptions options = plain_low_sun(10.0, 180.0);
    options.terrain_shadows = terrain_shadows;
    const Renderer renderer(terrain, options, 1);
    // Scan the floor from where it starts facing the sun (x' = -tan(e) / 2k) towards +x.
    for (double x = crater.x_m - 0.5 * b / k + 0.01; x < crater.x_m + crater.radius_m; x += 2e-4) {
      RayHit hit;
      hit.p_W = Eigen::Vector3d(x, 0.0, terrain.ground_height_m(x, 0.0));
      hit.normal_W = terrain.ground_normal_W(x, 0.0);
      if (renderer.radiance(hit, 1e-3) > 0.0) return x;
    }
    return std::numeric_limits<double>::quiet_NaN();
  };
  // Within 3 mm (the bowl is bilinear between 1 cm nodes, its normal one cell wide).
  EXPECT_NEAR(lit_from(true), expected_x, 3e-3);
  // Without terrain shadows that floor is lit (the test can tell the difference).
  EXPECT_LT(lit_from(false), expected_x - 0.1);
}

TEST(Lighting, OppositionSurgeBrightensLookingAwayFromTheSun) {
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  const Terrain terrain = make_terrain(terrain_options);
  RenderOptions options = plain_low_sun(20.0, 0.0);
  options.opposition_surge = 0.4;
  options.opposition_width_deg = 5.0;
  const Renderer renderer(terrain, options, 1);
  RayHit hit;
  hit.p_W = Eigen::Vector3d(1.0, 0.0, 0.0);
  hit.normal_W = Eigen::Vector3d::UnitZ();
  const double plain = renderer.radiance(hit, 1e-3);
  const Eigen::Vector3d towards_sun = renderer.sun_W();
  EXPECT_NEAR(renderer.radiance(hit, 1e-3, &towards_sun), 1.4 * plain, 1e-9);
  // 10 deg of phase (rotated about an axis normal to the sun direction): 1 + 0.4 exp(-2).
  const Eigen::Vector3d axis = towards_sun.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d off = Eigen::AngleAxisd(10.0 * kPi / 180.0, axis) * towards_sun;
  EXPECT_NEAR(renderer.radiance(hit, 1e-3, &off), (1.0 + 0.4 * std::exp(-2.0)) * plain, 1e-9);
}

// Regolith albedo: relative std = regolith_contrast over large areas; points closer than
// the correlation length differ far less than unrelated ones.
TEST(Lighting, RegolithAlbedoHasTheContrastAndCorrelationAsked) {
  TerrainOptions terrain_options;
  terrain_options.scenario = "flat";
  const Terrain terrain = make_terrain(terrain_options);
  RenderOptions options;
  options.sun_shading = false;
  options.albedo_model = AlbedoModel::regolith;
  options.regolith_contrast = 0.05;
  options.regolith_correlation_m = 0.05;
  const Renderer renderer(terrain, options, 7);
  auto value = [&](double x, double y) {
    RayHit hit;
    hit.p_W = Eigen::Vector3d(x, y, 0.0);
    hit.normal_W = Eigen::Vector3d::UnitZ();
    return renderer.radiance(hit, 1e-4);
  };
  double sum = 0, sum_sq = 0, near_sq = 0, far_sq = 0;
  constexpr int kN = 200;  // 200 x 200 points 0.37 m apart (an irrational step): 74 m
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      const double x = i * 0.3712;
      const double y = j * 0.3712;
      const double a = value(x, y);
      sum += a;
      sum_sq += a * a;
      near_sq += std::pow(a - value(x + 0.005, y), 2);  // a tenth of the correlation length
      far_sq += std::pow(a - value(x + 10.0, y + 10.0), 2);
    }
  }
  const double n = kN * kN;
  const double mean = sum / n;
  const double relative_std = std::sqrt(sum_sq / n - mean * mean) / mean;
  EXPECT_NEAR(mean, options.exposure_dn * options.ground_albedo, 1.0);
  // The value-noise std behind the normalisation is a measured constant: 10 %.
  EXPECT_NEAR(relative_std, 0.05, 0.005);
  EXPECT_LT(std::sqrt(near_sq / far_sq), 0.15);
}

// Noise keys: a flat, uniformly lit patch seen by a camera with gain, offset, shot and read
// noise. Over many renders the pixel std is sqrt(signal / electrons_per_dn + read^2)
// (plus 1/12 DN^2 of rounding), the mean gain * exposure * L + offset.
TEST(CameraResponse, NoiseStatisticsMatchTheKeys) {
  const testing::UniformFlatScene scene(2.0, 1);  // radiance exposure * albedo = 100 DN
  const Renderer& renderer = scene.renderer;
  CameraResponse response;
  response.gain = 1.2;
  response.exposure = 1.25;  // signal 150 DN
  response.offset_dn = 10.0;
  response.electrons_per_dn = 2.0;
  const NadirView view(1.0);
  constexpr int kRenders = 40;
  double sum = 0, sum_sq = 0, n = 0;
  for (int k = 0; k < kRenders; ++k) {
    const cv::Mat image = renderer.render(view.camera, view.T_W_C, 100 + k, response);
    ASSERT_EQ(image.type(), CV_8UC1);
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        const double x = image.at<unsigned char>(v, u);
        sum += x;
        sum_sq += x * x;
        n += 1;
      }
    }
  }
  const double signal = 1.2 * 1.25 * 100.0;
  const double mean = sum / n;
  const double stddev = std::sqrt(sum_sq / n - mean * mean);
  const double expected = std::sqrt(signal / 2.0 + 2.0 * 2.0 + 1.0 / 12.0);
  EXPECT_NEAR(mean, signal + 10.0, 0.1);
  EXPECT_NEAR(stddev, expected, 0.05 * expected);
  // Without shot noise the same patch shows the read noise alone.
  response.electrons_per_dn = 0.0;
  cv::Scalar m, s;
  cv::meanStdDev(renderer.render(view.camera, view.T_W_C, 7, response), m, s);
  EXPECT_NEAR(s[0], std::sqrt(4.0 + 1.0 / 12.0), 0.05 * 2.0);
}

TEST(CameraResponse, SaturationVignettingAndTwelveBits) {
  const testing::UniformFlatScene scene(0.0);
  const Renderer& renderer = scene.renderer;
  const NadirView view(1.0);
  CameraResponse bright;
  bright.gain = 3.0;  // 300 DN: clipped to 255
  const cv::Mat clipped = renderer.render(view.camera, view.T_W_C, 1, bright);
  EXPECT_EQ(cv::countNonZero(clipped != 255), 0);

  CameraResponse vignetted;
  vignetted.vignetting = 0.3;  // corners at 70 %: 70 DN, centre 100 DN
  const cv::Mat v = renderer.render(view.camera, view.T_W_C, 1, vignetted);
  EXPECT_EQ(v.at<unsigned char>(20, 150), 100);
  EXPECT_NEAR(v.at<unsigned char>(0, 0), 100.0 * (1.0 - 0.3 * (150.0 * 150.0 + 20.0 * 20.0) /
                                                            (150.5 * 150.5 + 20.5 * 20.5)),
              0.5);

  CameraResponse twelve;
  twelve.bits = 12;
  twelve.gain = 16.384;  // 1638.4 DN of 4095 -> 1638, stored as 1638 x 16
  const cv::Mat t = renderer.render(view.camera, view.T_W_C, 1, twelve);
  ASSERT_EQ(t.type(), CV_16UC1);
  EXPECT_EQ(t.at<std::uint16_t>(20, 150), 1638 * 16);
}

// ---------------------------------------------------------------------------------------
// Through simulate_sequence

SimulationOptions low_sun_options() {
  SimulationOptions options = testing::small_options();
  options.scenario = "craters";
  apply_lunar_polar_light(options.render);
  options.left_response.electrons_per_dn = 4.0;
  options.right_response.electrons_per_dn = 4.0;
  options.right_response.gain = 1.1;
  options.left_response.vignetting = 0.2;
  options.row_offset_px = 0.7;
  return options;
}

class LowSunSimulation : public ::testing::Test {
 protected:
  testing::TempDir tmp_;
  const std::filesystem::path& root_ = tmp_.path();
};

TEST_F(LowSunSimulation, SameSeedSameBytesOtherSeedOtherImages) {
  SimulationOptions options = low_sun_options();
  simulate_sequence(options, root_ / "a");
  simulate_sequence(options, root_ / "b");
  options.seed = 2;
  simulate_sequence(options, root_ / "c");
  for (const char* file : {"left/000000.png", "right/000001.png", "simulation.yaml",
                           "calibration.yaml", "poses.txt"}) {
    EXPECT_EQ(testing::read_text(root_ / "a" / file), testing::read_text(root_ / "b" / file)) << file;
  }
  EXPECT_NE(testing::read_text(root_ / "a" / "left/000000.png"), testing::read_text(root_ / "c" / "left/000000.png"));
  // Every setting is recorded.
  const std::string yaml = testing::read_text(root_ / "a" / "simulation.yaml");
  for (const char* key : {"terrain_shadows: true", "ambient: 0,", "model: regolith",
                          "opposition_surge: 0.3", "row_offset_px: 0.7", "electrons_per_dn: 4",
                          "vignetting: 0.2", "gain: 1.1", "elevation_deg: 8"}) {
    EXPECT_NE(yaml.find(key), std::string::npos) << key;
  }
}

// The residual row offset, measured back by phase correlation of the right images rendered
// with and without it: a scene point at row y in the left image is at y - offset in the
// right one, so the right image moves up by the offset.
TEST_F(LowSunSimulation, RowOffsetIsTheOneAsked) {
  SimulationOptions options;
  options.scenario = "rocks";
  options.scale = 0.25;
  options.frames = 1;
  options.terrain_size_m = 6.0;
  options.render.noise_sigma_dn = 0.0;
  simulate_sequence(options, root_ / "plain");
  options.row_offset_px = 1.6;
  simulate_sequence(options, root_ / "offset");
  // Calibration is the nominal one: the offset is a residual error.
  EXPECT_EQ(testing::read_text(root_ / "plain" / "calibration.yaml"),
            testing::read_text(root_ / "offset" / "calibration.yaml"));
  auto ground = [&](const char* dir) {
    cv::Mat image = cv::imread((root_ / dir / "right/000000.png").string(), cv::IMREAD_GRAYSCALE);
    cv::Mat f;
    image.convertTo(f, CV_64F);
    return f;
  };
  // Gauss-Newton on a vertical shift s: offset(x, y) = plain(x, y - s), over the ground
  // below the horizon, away from the borders.
  const cv::Mat plain = ground("plain");
  const cv::Mat offset = ground("offset");
  const cv::Rect roi(40, 160, 320, 160);
  cv::Mat map_x(plain.size(), CV_32F), map_y(plain.size(), CV_32F);
  double s = 0.0;
  for (int iteration = 0; iteration < 20; ++iteration) {
    for (int v = 0; v < plain.rows; ++v) {
      for (int u = 0; u < plain.cols; ++u) {
        map_x.at<float>(v, u) = static_cast<float>(u);
        map_y.at<float>(v, u) = static_cast<float>(v - s);
      }
    }
    cv::Mat warped, gy;
    cv::remap(plain, warped, map_x, map_y, cv::INTER_CUBIC);
    cv::Sobel(warped, gy, CV_64F, 0, 1, 3, 1.0 / 8.0);
    // d warped / d s = -d plain / d y.
    const cv::Mat r = offset(roi) - warped(roi);
    const cv::Mat g = -gy(roi);
    s += g.dot(r) / g.dot(g);
  }
  // The right image moves up by the offset: content of row y appears at y - 1.6.
  EXPECT_NEAR(s, -1.6, 0.05);
}

TEST(PolarRig, GeometryOfThePolarTraversePair) {
  const StereoRig rig = make_polar_rig(1.0);
  EXPECT_EQ(rig.camera.width_px, 2048);
  EXPECT_EQ(rig.camera.height_px, 2048);
  EXPECT_EQ(rig.camera.fx_px, 1457.0);
  EXPECT_EQ(rig.baseline_m, 0.4);
  EXPECT_TRUE(rig.T_B_CL.translation().isApprox(Eigen::Vector3d(0.0, 0.2, 1.3)));
  const Eigen::Vector3d axis_B = rig.T_B_CL.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::asin(-axis_B.z()) * 180.0 / kPi, 28.0, 1e-9);
  EXPECT_TRUE(rig.rectified());
  EXPECT_EQ(make_rig("polar", 0.5).camera.width_px, 1024);
  EXPECT_THROW(make_rig("mars", 1.0), Error);
}

}  // namespace
}  // namespace hazmap::sim
