// JPL camera models: the model equations against independent computations (a pinhole
// projection, OpenCV's radial distortion, the fish-eye angle law), and rectification
// through them against the pinhole path: a pinhole rig written as CAHV gives the same
// rectified pair and the same map; a CAHVOR pair recovers a rendered distorted pair.

#include <cmath>
#include <fstream>
#include <random>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/camera/cahvore.hpp"
#include "hazmap/camera/rectifier.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/sim/simulate.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

Pose3d some_pose() {
  Pose3d T = Pose3d::Identity();
  T.linear() = rotation_from_rpy(-1.9, 0.1, -1.4);
  T.translation() = Eigen::Vector3d(0.3, 0.02, 0.15);
  return T;
}

Eigen::Matrix3d some_K() {
  Eigen::Matrix3d K;
  K << 268.4, 0.3, 321.2, 0, 270.1, 258.7, 0, 0, 1;
  return K;
}

/// Random points 0.5-5 m in front of the camera, within ~50 deg of its axis, in M.
std::vector<Eigen::Vector3d> points_in_view(const Pose3d& T_M_C, int n) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> lateral(-1.0, 1.0), depth(0.5, 5.0);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) {
    const double z = depth(rng);
    out.push_back(T_M_C * Eigen::Vector3d(lateral(rng) * z, lateral(rng) * z * 0.8, z));
  }
  return out;
}

TEST(Cahvore, CahvOfAPinholeProjectsLikeThePinhole) {
  const Eigen::Matrix3d K = some_K();
  const Pose3d T_M_C = some_pose();
  const CahvoreModel m = cahv_from_pinhole(K, T_M_C);
  for (const auto& P : points_in_view(T_M_C, 200)) {
    const Eigen::Vector3d q = K * (T_M_C.inverse() * P);
    Eigen::Vector2d uv;
    ASSERT_TRUE(m.project(P, uv));
    EXPECT_LT((uv - q.hnormalized()).norm(), 1e-9);
  }
  const CahvPinhole pin = cahv_pinhole(m);
  EXPECT_LT((pin.K - K).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((pin.T_M_C.matrix() - T_M_C.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Cahvore, CahvorRadialTermsAreOpenCvsRadialDistortion) {
  // O = A, r0 = 0: lambda scales by 1 + r1 tan^2 + r2 tan^4, OpenCV's 1 + k1 r^2 + k2 r^4.
  Eigen::Matrix3d K = some_K();
  K(0, 1) = 0.0;  // cv::projectPoints has no skew
  const Pose3d T_M_C = some_pose();
  CahvoreModel m = cahv_from_pinhole(K, T_M_C);
  m.kind = CahvoreKind::cahvor;
  m.R = Eigen::Vector3d(0.0, -0.08, 0.012);
  const auto points = points_in_view(T_M_C, 200);
  std::vector<cv::Point3d> p_C;
  for (const auto& P : points) {
    const Eigen::Vector3d c = T_M_C.inverse() * P;
    p_C.emplace_back(c.x(), c.y(), c.z());
  }
  cv::Mat Kcv;
  cv::eigen2cv(K, Kcv);
  std::vector<cv::Point2d> expected;
  cv::projectPoints(p_C, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), Kcv,
                    std::vector<double>{-0.08, 0.012, 0, 0, 0}, expected);
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d uv, uv_dir;
    ASSERT_TRUE(m.project(points[i], uv));
    EXPECT_LT((uv - Eigen::Vector2d(expected[i].x, expected[i].y)).norm(), 1e-8);
    ASSERT_TRUE(m.project_direction(points[i] - m.C, uv_dir));
    EXPECT_LT((uv_dir - uv).norm(), 1e-9);
    Eigen::Vector3d d;
    ASSERT_TRUE(m.unproject(uv, d));
    EXPECT_LT((d - (points[i] - m.C).normalized()).norm(), 1e-9);
  }
}

TEST(Cahvore, CahvoreReducesToCahvorAndFollowsTheFisheyeLaw) {
  const Pose3d T_M_C = some_pose();
  CahvoreModel r = cahv_from_pinhole(some_K(), T_M_C);
  r.kind = CahvoreKind::cahvor;
  r.O = (r.A + Eigen::Vector3d(0.01, -0.02, 0.005)).normalized();
  r.R = Eigen::Vector3d(0.001, -0.1, 0.02);
  CahvoreModel e = r;
  e.kind = CahvoreKind::cahvore;
  e.type = 1;
  for (const auto& P : points_in_view(T_M_C, 100)) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(r.project(P, a));
    ASSERT_TRUE(e.project(P, b));
    EXPECT_LT((a - b).norm(), 1e-9);
  }
  // Type 2 (fish-eye), no R, no E: image radius = f theta (equidistant), theta the angle
  // between the ray and A. With E: far points tend to project_direction, and unproject
  // inverts project_direction.
  CahvoreModel f = cahv_from_pinhole(Eigen::Vector3d(300, 300, 1).asDiagonal(), Pose3d::Identity());
  f.kind = CahvoreKind::cahvore;
  f.type = 2;
  for (double theta : {0.1, 0.5, 1.0, 1.4}) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(f.project(Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)), uv));
    EXPECT_NEAR(uv.x(), 300 * theta, 1e-9);
    EXPECT_NEAR(uv.y(), 0.0, 1e-12);
  }
  f.type = 3;
  f.parameter = 0.4;
  f.R = Eigen::Vector3d(0.0, -0.02, 0.001);
  f.E = Eigen::Vector3d(0.004, 0.002, -0.001);
  for (double theta : {0.2, 0.7, 1.2}) {
    const Eigen::Vector3d d(std::sin(theta) * 0.6, std::sin(theta) * 0.8, std::cos(theta));
    Eigen::Vector2d near, far, dir;
    ASSERT_TRUE(f.project(0.3 * d, near));
    ASSERT_TRUE(f.project(1e6 * d, far));
    ASSERT_TRUE(f.project_direction(d, dir));
    EXPECT_LT((far - dir).norm(), 1e-6);
    EXPECT_GT((near - dir).norm(), 1e-3);  // the moving pupil matters up close
    Eigen::Vector3d back;
    ASSERT_TRUE(f.unproject(dir, back));
    EXPECT_LT((back - d.normalized()).norm(), 1e-9);
  }
}

/// A pinhole rig (no distortion) as a JPL calibration in the body frame (M = B).
StereoCalibration as_models(const StereoCalibration& pinhole, CahvoreKind kind,
                            const Eigen::Vector3d& radial) {
  Pose3d T_CR_CL = Pose3d::Identity();
  T_CR_CL.linear() = pinhole.R;
  T_CR_CL.translation() = pinhole.T;
  StereoCalibration c;
  c.image_width = pinhole.image_width;
  c.image_height = pinhole.image_height;
  c.models = {cahv_from_pinhole(pinhole.left.K, pinhole.T_B_C),
              cahv_from_pinhole(pinhole.right.K, pinhole.T_B_C * T_CR_CL.inverse())};
  for (auto& m : c.models) {
    m.kind = kind;
    m.R = radial;
  }
  derive_from_models(c, "test");
  return c;
}

sim::SimulationOptions scene(int frames) {
  sim::SimulationOptions o;
  o.scenario = "rocks";
  o.seed = 21;
  o.frames = frames;
  o.scale = 0.4;
  o.render.noise_sigma_dn = 0.0;
  o.png_compression = 1;
  return o;
}

void copy_sequence(const fs::path& from, const fs::path& to, const StereoCalibration& calib) {
  fs::create_directories(to);
  fs::copy(from / "left", to / "left", fs::copy_options::recursive);
  fs::copy(from / "right", to / "right", fs::copy_options::recursive);
  fs::copy_file(from / "poses.txt", to / "poses.txt");
  save_stereo_calibration(to / "calibration.yaml", calib);
}

TEST(Cahvore, PinholeRigAsCahvGivesTheSameRectifiedPairAndMap) {
  TempDir dir;
  sim::SimulationOptions o = scene(3);
  o.rig_errors.misalignment_rpy_deg = sim::RigErrors::typical_misalignment_rpy_deg();
  o.rig_errors.misalignment_m = sim::RigErrors::typical_misalignment_m();
  sim::simulate_sequence(o, dir / "pinhole");
  const StereoCalibration pin = load_stereo_calibration(dir / "pinhole" / "calibration.yaml");
  ASSERT_FALSE(pin.rectified);
  copy_sequence(dir / "pinhole", dir / "cahv", as_models(pin, CahvoreKind::cahv, {0, 0, 0}));
  // Written and read back: the same rig.
  const StereoCalibration cahv = load_stereo_calibration(dir / "cahv" / "calibration.yaml");
  ASSERT_EQ(cahv.models.size(), 2u);
  EXPECT_LT((cahv.R - pin.R).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((cahv.T - pin.T).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((cahv.left.K - pin.left.K).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((cahv.T_B_C.matrix() - pin.T_B_C.matrix()).cwiseAbs().maxCoeff(), 1e-12);

  const Rectifier a(pin, 0.0), b(cahv, 0.0);
  EXPECT_NEAR(a.geometry().focal_px, b.geometry().focal_px, 1e-9);
  EXPECT_NEAR(a.geometry().baseline_m, b.geometry().baseline_m, 1e-12);
  EXPECT_NEAR(a.geometry().cx_px, b.geometry().cx_px, 1e-9);
  EXPECT_LT((a.R1() - b.R1()).cwiseAbs().maxCoeff(), 1e-12);
  const cv::Mat left = cv::imread((dir / "pinhole" / "left" / "000001.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat right = cv::imread((dir / "pinhole" / "right" / "000001.png").string(), cv::IMREAD_GRAYSCALE);
  cv::Mat al, ar, bl, br;
  a.rectify(left, right, al, ar);
  b.rectify(left, right, bl, br);
  const cv::Rect roi = a.valid_roi() & b.valid_roi();
  double worst_left = 0, worst_right = 0;
  cv::Mat diff;
  cv::absdiff(al(roi), bl(roi), diff);
  cv::minMaxLoc(diff, nullptr, &worst_left);
  const int differing = cv::countNonZero(diff);
  cv::absdiff(ar(roi), br(roi), diff);
  cv::minMaxLoc(diff, nullptr, &worst_right);
  std::printf("CAHV vs pinhole rectified pair: %d left pixels differ, worst %g / %g DN\n",
              differing, worst_left, worst_right);
  EXPECT_LE(std::max(worst_left, worst_right), 1.0);  // same 1/32 px tables up to rounding ties

  // The whole pipeline: the same height map to 1 mm.
  for (const char* name : {"pinhole", "cahv"}) {
    const auto r = testing::run_command(std::string(HAZMAP_CLI) + " run --config " +
                                        (testing::source_dir() / "config" / "default.yaml").string() +
                                        " --sequence " + (dir / name).string() + " --out " +
                                        (dir / (std::string(name) + "_run")).string() + " --quiet 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const JdemGrid ha = read_jdem(dir / "pinhole_run" / "frames" / "000002" / "L0_height.jdem");
  const JdemGrid hb = read_jdem(dir / "cahv_run" / "frames" / "000002" / "L0_height.jdem");
  ASSERT_EQ(ha.values.size(), hb.values.size());
  int both = 0, one = 0;
  double worst_m = 0;
  for (size_t i = 0; i < ha.values.size(); ++i) {
    const bool ka = std::isfinite(ha.values[i]), kb = std::isfinite(hb.values[i]);
    if (ka && kb) {
      ++both;
      worst_m = std::max(worst_m, double(std::abs(ha.values[i] - hb.values[i])));
    } else {
      one += ka != kb;
    }
  }
  std::printf("CAHV vs pinhole: %d cells known in both, %d in one only, worst %.3f mm\n", both,
              one, worst_m * 1e3);
  EXPECT_GT(both, 1000);
  EXPECT_LE(one, both / 1000);
  EXPECT_LT(worst_m, 1e-3);
}

TEST(Cahvore, CahvorRectificationRecoversARenderedDistortedPair) {
  // The same scene rendered through an ideal pinhole pair and through lenses with
  // radial distortion k1, k2 (the simulator's Brown model = CAHVOR with O = A, r0 = 0).
  TempDir dir;
  const double k1 = -0.08, k2 = 0.012;
  sim::SimulationOptions o = scene(1);
  sim::simulate_sequence(o, dir / "ideal");
  o.rig_errors.distortion = {k1, k2, 0.0, 0.0, 0.0};
  sim::simulate_sequence(o, dir / "distorted");
  StereoCalibration pin = load_stereo_calibration(dir / "ideal" / "calibration.yaml");
  pin.rectified = false;  // through stereoRectify like the models, so both share P and R1
  const StereoCalibration cahvor = as_models(pin, CahvoreKind::cahvor, {0.0, k1, k2});
  const Rectifier a(pin, 0.0), b(cahvor, 0.0);
  ASSERT_LT((a.R1() - b.R1()).cwiseAbs().maxCoeff(), 1e-12);
  auto read = [&](const char* seq, const char* side) {
    return cv::imread((dir / seq / side / "000000.png").string(), cv::IMREAD_GRAYSCALE);
  };
  cv::Mat al, ar, bl, br;
  a.rectify(read("ideal", "left"), read("ideal", "right"), al, ar);
  b.rectify(read("distorted", "left"), read("distorted", "right"), bl, br);
  const cv::Rect roi = b.valid_roi();
  EXPECT_GT(roi.area(), 0.8 * 640 * 520);  // barrel distortion: most of the image stays
  cv::Mat diff;
  cv::absdiff(al(roi), bl(roi), diff);
  const double mean = cv::mean(diff)[0];
  cv::Mat sorted;
  cv::sort(diff.reshape(1, 1), sorted, cv::SORT_ASCENDING);
  const int p99 = sorted.at<uchar>(0, static_cast<int>(0.99 * (sorted.cols - 1)));
  std::printf("CAHVOR-rectified distorted render vs ideal render: mean %.2f DN, 99%% %d DN\n",
              mean, p99);
  EXPECT_LT(mean, 1.5);
  EXPECT_LE(p99, 8);
  // Most of that is two renderings resampled differently: OpenCV's own undistortion of
  // the distorted render (K, D = k1 k2, the same R1 and rectified camera) is the same
  // image as the CAHVOR rectifier's, pixel for pixel.
  cv::Mat Kcv, R1cv, map1, map2, opencv_left;
  cv::eigen2cv(pin.left.K, Kcv);
  cv::eigen2cv(b.R1(), R1cv);
  const StereoGeometry& g = b.geometry();
  const cv::Matx33d P(g.focal_px, 0, g.cx_px, 0, g.focal_px, g.cy_px, 0, 0, 1);
  cv::initUndistortRectifyMap(Kcv, std::vector<double>{k1, k2, 0, 0, 0}, R1cv, P,
                              cv::Size(640, 520), CV_16SC2, map1, map2);
  cv::remap(read("distorted", "left"), opencv_left, map1, map2, cv::INTER_LINEAR);
  cv::absdiff(opencv_left(roi), bl(roi), diff);
  double worst_vs_opencv = 0;
  cv::minMaxLoc(diff, nullptr, &worst_vs_opencv);
  std::printf("CAHVOR vs OpenCV rectification of the distorted render: %d pixels differ, "
              "worst %g DN\n", cv::countNonZero(diff), worst_vs_opencv);
  EXPECT_LE(worst_vs_opencv, 1.0);

  // Geometry, independent of the images: where OpenCV puts a direction in the distorted
  // image, rectify_points finds the rectified pixel the ideal rectifier gives it.
  cv::Mat K;
  cv::eigen2cv(pin.left.K, K);
  std::vector<cv::Point3d> rays;
  for (double x = -0.9; x <= 0.9; x += 0.3)
    for (double y = -0.7; y <= 0.7; y += 0.35) rays.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> raw_d, raw_ideal;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K,
                    std::vector<double>{k1, k2, 0, 0, 0}, raw_d);
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cv::Mat(), raw_ideal);
  std::vector<cv::Point2f> in_d(raw_d.begin(), raw_d.end()), in_i(raw_ideal.begin(), raw_ideal.end());
  std::vector<cv::Point2f> out_d, out_i;
  b.rectify_points(StereoSide::left, in_d, out_d);
  a.rectify_points(StereoSide::left, in_i, out_i);
  for (size_t i = 0; i < rays.size(); ++i) EXPECT_LT(cv::norm(out_d[i] - out_i[i]), 1e-3) << i;
}

TEST(Cahvore, ReadsPdsLabelGroups) {
  TempDir dir;
  // A CAHVORE group as PDS3 labels write it (components over several lines, units,
  // quoted names), after other groups, followed by END and image bytes.
  {
    std::ofstream(dir / "left.LBL")
        << "PDS_VERSION_ID = PDS3\nGROUP = ROVER_COORDINATE_SYSTEM\n ORIGIN_OFFSET_VECTOR = "
           "(1, 2, 3)\nEND_GROUP = ROVER_COORDINATE_SYSTEM\n"
           "GROUP = GEOMETRIC_CAMERA_MODEL_PARMS\n"
           " MODEL_TYPE = \"CAHVORE\"\n"
           " MODEL_COMPONENT_ID = (\"C\",\"A\",\"H\",\"V\",\"O\",\"R\",\"E\",\"T\",\"P\")\n"
           " MODEL_COMPONENT_1 = ( 0.1 <m>, 0.2 <m>,\n    -1.5 <m> )\n"
           " MODEL_COMPONENT_2 = ( 1.0, 0.0, 0.0 )\n"
           " MODEL_COMPONENT_3 = ( 512.0, 800.0, 0.0 )\n"
           " MODEL_COMPONENT_4 = ( 512.0, 0.0, 800.0 )\n"
           " MODEL_COMPONENT_5 = ( 0.999998, 0.002, 0.0 )\n"
           " MODEL_COMPONENT_6 = ( 0.0, -0.02,\n 0.001 )\n"
           " MODEL_COMPONENT_7 = ( 0.001, 0.0, 0.0 )\n"
           " MODEL_COMPONENT_8 = 3.0\n MODEL_COMPONENT_9 = 0.5\n"
           "END_GROUP = GEOMETRIC_CAMERA_MODEL_PARMS\nEND\n\x01\x02binary";
    std::ofstream(dir / "bad.LBL") << "GROUP = GEOMETRIC_CAMERA_MODEL\n MODEL_TYPE = CAHVOR\n"
                                      " MODEL_COMPONENT_1 = (0, 0, zero)\nEND_GROUP\nEND\n";
    std::ofstream(dir / "short.LBL") << "GROUP = GEOMETRIC_CAMERA_MODEL\n MODEL_TYPE = CAHVOR\n"
                                        " MODEL_COMPONENT_1 = (0, 0, 0)\nEND_GROUP\nEND\n";
  }
  const CahvoreModel m = read_pds_camera_model(dir / "left.LBL");
  EXPECT_EQ(m.kind, CahvoreKind::cahvore);
  EXPECT_EQ(m.C, Eigen::Vector3d(0.1, 0.2, -1.5));
  EXPECT_EQ(m.H, Eigen::Vector3d(512.0, 800.0, 0.0));
  EXPECT_EQ(m.R, Eigen::Vector3d(0.0, -0.02, 0.001));
  EXPECT_EQ(m.E, Eigen::Vector3d(0.001, 0.0, 0.0));
  EXPECT_EQ(m.type, 3);
  EXPECT_EQ(m.parameter, 0.5);
  auto error_of = [&](const char* file) {
    try {
      read_pds_camera_model(dir / file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("bad.LBL").find("bad.LBL:3: MODEL_COMPONENT_1: not a number: 'zero'"),
            std::string::npos) << error_of("bad.LBL");
  EXPECT_NE(error_of("short.LBL").find("short.LBL: camera model group lacks MODEL_COMPONENT_2"),
            std::string::npos) << error_of("short.LBL");

  // calibration.yaml may point at labels; the model must be the one camera_model names.
  std::ofstream(dir / "right.LBL") << testing::read_text(dir / "left.LBL");
  {
    std::ofstream(dir / "calibration.yaml")
        << "image_width: 1024\nimage_height: 1024\ncamera_model: cahvore\n"
           "left: {pds_label: left.LBL}\nright: {C: [0.1, 0.5, -1.5], A: [1, 0, 0], "
           "H: [512, 800, 0], V: [512, 0, 800], O: [0.999998, 0.002, 0], R: [0, -0.02, 0.001], "
           "E: [0.001, 0, 0], type: 3, parameter: 0.5}\n";
  }
  const StereoCalibration c = load_stereo_calibration(dir / "calibration.yaml");
  EXPECT_EQ(c.models[0].C, m.C);
  EXPECT_NEAR(c.T.x(), -0.3, 1e-12);  // right camera 0.3 m along +y: M is x forward, y right, z down
  {
    std::ofstream(dir / "calibration.yaml")
        << "image_width: 1024\nimage_height: 1024\ncamera_model: cahvor\n"
           "left: {pds_label: left.LBL}\nright: {pds_label: right.LBL}\n";
  }
  try {
    load_stereo_calibration(dir / "calibration.yaml");
    ADD_FAILURE() << "a CAHVORE label accepted as cahvor";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds a cahvore model, camera_model says cahvor"),
              std::string::npos) << e.what();
  }
}

TEST(Cahvore, CalibrationFileErrorsNameFileAndKey) {
  TempDir dir;
  const std::string head = "image_width: 64\nimage_height: 48\ncamera_model: cahvor\n";
  const std::string cam = "{C: [0, 0, 0], A: [1, 0, 0], H: [32, -50, 0], V: [24, 0, -50], "
                          "O: [1, 0, 0], R: [0, 0, 0]}";
  const struct {
    std::string text, expect;
  } cases[] = {
      {head + "left: " + cam + "\n", "key 'right': missing required key"},
      {head + "left: {C: [0, 0], A: [1, 0, 0]}\nright: " + cam + "\n", "left.C"},
      {head + "left: {C: [0, 0, 0], A: [1, 0, 0], H: [32, -50, 0], V: [24, 0, -50]}\nright: " +
           cam + "\n",
       "left.O"},
      {"image_width: 64\nimage_height: 48\ncamera_model: cahvx\nleft: " + cam + "\nright: " + cam +
           "\n",
       "unknown camera model 'cahvx'"},
      {head + "left: " + cam + "\nright: " + cam + "\n", "baseline must be non-zero"},
      {head + "left: {C: [0, 0, 0], A: [1, 0, 0.1], H: [32, -50, 0], V: [24, 0, -50], O: [1, 0, "
              "0], R: [0, 0, 0]}\nright: " + cam + "\n",
       "A must be a unit vector"},
  };
  for (const auto& c : cases) {
    { std::ofstream(dir / "calibration.yaml") << c.text; }
    try {
      load_stereo_calibration(dir / "calibration.yaml");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("calibration.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find(c.expect), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace hazmap
