// The per-frame path allocates nothing once the map is built: count every operator new
// in this test binary across frames 2..N of the map, its export and the hazard filters.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>

#include "hazmap/hazard/fused_hazard.hpp"
#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/hazard/hazard_stage.hpp"
#include "hazmap/hazard/mapper.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/pipeline/frame_writer.hpp"
#include "hazmap/pipeline/pipeline.hpp"
#include "hazmap/pipeline/thread_pool.hpp"
#include "hazmap/stereo/c2f_matcher.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "test_support.hpp"

namespace {
std::atomic<long> g_news{0};
}

void* operator new(std::size_t n) {
  ++g_news;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  ++g_news;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them): left to the
// runtime, ASan's own nothrow new paired with the free() below was an alloc-dealloc
// mismatch under the sanitizer build.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++g_news;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  ++g_news;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace hazmap {
namespace {

void fill_cloud(PointCloud& cloud, std::mt19937_64& rng, double cx) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Measurement& m : cloud) {  // overwrite in place: no allocation
    const double x = cx + u(rng), y = u(rng);
    m.p_W = Eigen::Vector3f(float(x), float(y), float(0.02 * std::sin(9 * x)));
    m.cov_xx = m.cov_yy = 1e-6f;
    m.cov_xy = m.cov_xz = m.cov_yz = 0.0f;
    m.cov_zz = 4e-6f;
  }
}

void run(const std::string& insertion, bool pose) {
  MapConfig map;
  map.insertion = *enum_value<Insertion>(insertion);
  const RuleKind rules_kinds[] = {RuleKind::ccm, RuleKind::ccm, RuleKind::ccm};
  const std::pair<double, int> sizes[] = {{0.04, 64}, {0.08, 32}, {0.16, 16}};
  for (int i = 0; i < 3; ++i) {
    LayerConfig l;
    l.resolution_m = sizes[i].first;
    l.size = sizes[i].second;
    l.rule = insertion == "all_layers" && i == 0 ? RuleKind::kalman : rules_kinds[i];
    map.layers.push_back(l);
  }
  RulesConfig rules;
  rules.ccm.max_std_ratio = 2.0;  // the lateral gate on every layer (SPEC 4 fallback)
  rules.kalman.gate_sigma = 1.0;  // and the consistency gate's pass on the Kalman layer
  LayerStack stack(map, rules, pose);
  PointCloud cloud(50000);
  MapPoints points;
  std::mt19937_64 rng(1);
  std::vector<LayerGrids> grids(stack.size());
  Config config;
  config.map = map;
  config.rules = rules;
  // The view mask of hazard.partial_ring_proof: view_edge, marked every frame.
  config.hazard.partial_ring_proof = PartialRingProof::view_edge;
  const HazardParams params = resolve_hazard_params(config);
  SensorView view;  // a camera 0.3 m up on the body, pitched 30 deg down, looking ahead
  view.T_B_C.linear() << 0, -0.5, 0.866, -1, 0, 0, 0, -0.866, -0.5;
  view.T_B_C.translation() = Eigen::Vector3d(0.1, 0.0, 0.3);
  view.focal_px = 300;
  view.cx_px = 319.5;
  view.cy_px = 239.5;
  view.width_px = 640;
  view.height_px = 480;
  view.z_min_m = 0.05;
  view.z_max_m = 3.0;
  std::vector<std::unique_ptr<HazardClassifier>> classifiers;
  std::vector<HazardDiagnostics> diagnostics(stack.size());
  std::vector<DenseGrid> hazards(stack.size());
  std::vector<FusionInput> inputs;
  for (size_t i = 0; i < stack.size(); ++i) {
    classifiers.push_back(make_hazard_classifier(params.layers[i]));
    inputs.push_back({&hazards[i], params.layers[i].h_min_m});
  }
  HazardFusion fusion;
  DenseGrid fused, clearance, footprint, distance;
  // The pipeline's hazard stage, whole and incremental (SPEC 8.6).
  HazardStage whole(params, false), incremental(params, true);
  // The core's facade, as Pipeline and the Python LayerStack run it (hazard/mapper.hpp).
  Mapper mapper(config, pose);
  mapper.set_parallel(&opencv_parallel_for());  // as Pipeline runs it: on the thread pool
  long after_first = 0;
  std::size_t consistency_gated = 0;
  for (int frame = 0; frame < 6; ++frame) {
    if (frame == 1) after_first = g_news.load();
    fill_cloud(cloud, rng, 0.1 * frame);  // the robot drives 10 cm per frame: layers roll
    stack.begin_frame(0.1 * frame, 0.0, PoseNoise{0.001, 0.001, 0.001, 0.001});
    points.assign(cloud, CcmWeighting::trace);
    stack.insert(points);
    for (size_t i = 0; i < stack.size(); ++i) consistency_gated += stack.gate_counts(i).consistency_gate;
    for (size_t i = 0; i < stack.size(); ++i) {
      stack.export_layer(i, grids[i]);
      classifiers[i]->classify(grids[i], hazards[i], diagnostics[i]);
    }
    fusion.fuse(inputs, params.critical_height_m, fused_cells(params.fused_extent_m, 0.04), 0.04,
                hazards[0].center_x_m, hazards[0].center_y_m, fused, clearance);
    fusion.footprint(fused, params.footprint_radius_m, footprint, distance);
    view.T_W_B.translation() = Eigen::Vector3d(0.1 * frame, 0.0, 0.0);
    whole.run(stack, &view);
    incremental.run(stack, &view);
    mapper.insert(cloud, 0.1 * frame, 0.0, PoseNoise{0.001, 0.001, 0.001, 0.001});
    mapper.classify(&view);
  }
  EXPECT_EQ(g_news.load() - after_first, 0) << insertion << (pose ? " with pose uncertainty" : "");
  // The Kalman layer's consistency gate ran and dropped points (the terrain varies by
  // more than 1 sigma inside a 4 cm cell): its pass is part of what was measured.
  if (insertion == "all_layers") {
    EXPECT_GT(consistency_gated, 0u);
  }
}

TEST(Allocation, PerFramePathAllocatesNothingAfterTheFirstFrame) {
  run("all_layers", false);
  run("finest_then_pool", false);
  run("all_layers", true);
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

// The frame loop's share of writing (issue 20): copying a frame's grids into a writer
// slot reuses the slot's buffers once they have grown, frame after frame.
TEST(Allocation, HandingAFrameToTheWriterAllocatesNothingOnceWarm) {
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  Config config = load_config(testing::source_dir() / "config/default.yaml");
  config.map.layers.push_back(config.map.layers.front());  // and a CCM layer with slopes
  config.map.layers.back().rule = RuleKind::ccm;
  config.map.layers.back().resolution_m = 0.04;
  config.map.layers.back().size = 32;
  Pipeline pipeline(config, seq.calibration);
  const auto& f = seq.frames.front();
  pipeline.process(read_image(f.left_path), read_image(f.right_path), f.pose.T_W_B);
  OutputConfig output;
  output.queue_frames = 1;
  FrameWriter writer(testing::TempDir().path(), output);  // a folder never written: no submit
  FrameOutputs& slot = writer.acquire();
  capture_frame_outputs(pipeline, f.name, f.pose.T_W_B, slot);  // warm: buffers grow
  const long before = g_news.load();
  for (int i = 0; i < 3; ++i) capture_frame_outputs(pipeline, f.name, f.pose.T_W_B, slot);
  EXPECT_EQ(g_news.load() - before, 0);
  ASSERT_EQ(slot.layers.size(), 2u);
  EXPECT_GT(slot.layers[1].slope_x.rows, 0);
  // A copy, not a view: equal bytes in a buffer of its own.
  const std::vector<float>& held = pipeline.layers()[0].map.height.values;
  ASSERT_EQ(slot.layers[0].height.values.size(), held.size());
  EXPECT_EQ(std::memcmp(slot.layers[0].height.values.data(), held.data(), held.size() * sizeof(float)),
            0);
  EXPECT_NE(slot.layers[0].height.values.data(), pipeline.layers()[0].map.height.values.data());
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

// The points stage's direct path (issue 20) writes into MapPoints' arrays, grown once:
// frames after the first allocate nothing, whichever frame is larger.
TEST(Allocation, TheDirectPointsStageAllocatesNothingOnceWarm) {
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  const Config config = load_config(testing::source_dir() / "config/default.yaml");
  StereoFrontEnd front(config.stereo, config.sensor, seq.calibration, false);
  front.set_map_points_output(CcmWeighting::trace);
  std::vector<cv::Mat> disparities;
  for (const auto& f : {seq.frames.front(), seq.frames.back()}) {
    front.process(read_image(f.left_path), read_image(f.right_path), f.pose.T_W_B);
    disparities.push_back(front.disparity_x16().clone());
  }
  MapPoints points;
  const PointCloudBuilder& builder = front.builder();
  builder.build_map_points(disparities[0], 0, seq.frames[0].pose.T_W_B, CcmWeighting::trace, points);
  const long before = g_news.load();
  for (int i = 0; i < 4; ++i)
    builder.build_map_points(disparities[static_cast<size_t>(i % 2)], 0, seq.frames[0].pose.T_W_B,
                             CcmWeighting::trace, points);
  EXPECT_EQ(g_news.load() - before, 0);
  EXPECT_GT(points.size(), 10000);
}

// The c2f matcher sizes every buffer at construction (issue 32): a second and third
// pair allocate nothing, through pyramid, census, aggregation, checks and speckle filter,
// nor does the support check that follows it in the front end.
TEST(Allocation, TheC2fMatcherAllocatesNothingOnceWarm) {
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  const Config config = load_config(testing::source_dir() / "config/default.yaml");
  StereoFrontEnd front(config.stereo, config.sensor, seq.calibration, false);
  const auto& f = seq.frames.front();
  front.process(read_image(f.left_path), read_image(f.right_path), f.pose.T_W_B);
  const cv::Mat left = front.rectified_left().clone(), right = front.rectified_right().clone();
  C2fMatcher matcher(C2fConfig{}, 0, 160, left.size(), 100, 2);
  // The support check after it (row strips in parallel) too.
  SupportCheck support(32, 0.25, 1.0);
  cv::Mat disparity;
  matcher.compute(left, right, disparity);
  support.apply(disparity, 0);  // min_disparity 0
  const long before = g_news.load();
  for (int i = 0; i < 2; ++i) {
    matcher.compute(left, right, disparity);
    support.apply(disparity, 0);  // min_disparity 0
  }
  EXPECT_EQ(g_news.load() - before, 0);
  EXPECT_GT(cv::countNonZero(disparity > 0), static_cast<int>(disparity.total() / 2));
}

}  // namespace
}  // namespace hazmap
