// The full-resolution config and the frame benchmark's code path (no timing asserted).

#include "hazmap/pipeline/frame_bench.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

TEST(FullResConfig, LoadsValidatesAndKeepsTheFlightStack) {
  const Config full = load_config(testing::source_dir() / "config/cadre_full_res.yaml");
  EXPECT_NO_THROW(validate(full));
  // Level ground at the bottom of a 1600 x 1300 image: d = 671 * 0.05 / 0.11 = 305 px.
  EXPECT_GE(full.stereo.num_disparities, 305);
  EXPECT_EQ(full.stereo.num_disparities % 16, 0);

  // Only the keys measured in pixels differ from the 0.4-scale flight config, and the 4 cm
  // layer's lateral gate, whose reach scales with the focal length: at 268 px the flight
  // config widens it to reach ~0.95 m; at 671 px the plain gate reaches ~1.25 m.
  const Config flight = load_config(testing::source_dir() / "config/cadre_flight.yaml");
  Config same = full;
  same.stereo.num_disparities = flight.stereo.num_disparities;
  same.stereo.speckle_window = flight.stereo.speckle_window;
  same.stereo.support_rows = flight.stereo.support_rows;
  ASSERT_EQ(same.map.layers.size(), flight.map.layers.size());
  EXPECT_FALSE(full.map.layers[1].max_std_ratio.has_value());
  same.map.layers[1].max_std_ratio = flight.map.layers[1].max_std_ratio;
  // The hole-free 4 cm cells, measured at both scales (docs/evaluation.md).
  EXPECT_EQ(full.map.layers[1].hole_free_coverage, flight.map.layers[1].hole_free_coverage);
  EXPECT_EQ(to_yaml(same), to_yaml(flight));
}

TEST(FrameBench, RunsThePipelineAndTheBareStereoBMOnAFrame) {
  // One 640 x 520 frame of the embedded sample with its own config: the code path of
  // `hazmap bench` at a fraction of the full-resolution cost.
  const Config config = load_config(testing::source_dir() / "config/cadre_flight.yaml");
  const Sequence sequence = load_sequence(testing::source_dir() / "data/sample");
  const std::vector<BenchFrame> frames = read_bench_frames(sequence, 1);
  ASSERT_EQ(frames.size(), 1u);

  FrameBenchOptions options;
  options.repetitions = 1;
  const FrameBenchResult r = run_frame_bench(config, sequence.calibration, frames, options);
  EXPECT_EQ(r.frames, 1);
  EXPECT_EQ(r.repetitions, 1);
  EXPECT_EQ(r.image_size, cv::Size(640, 520));
  EXPECT_EQ(r.num_disparities, config.stereo.num_disparities);
  EXPECT_EQ(r.block_size, config.stereo.block_size);
  EXPECT_GT(r.points, 1000.0);
  for (double ms : {r.stage_ms.rectify_ms, r.stage_ms.disparity_ms, r.stage_ms.points_ms,
                    r.stage_ms.map_ms, r.stage_ms.hazard_ms, r.frame_ms, r.stereo_bm_ms}) {
    EXPECT_TRUE(std::isfinite(ms));
    EXPECT_GE(ms, 0.0);
  }
  EXPECT_GT(r.frame_ms, 0.0);
  EXPECT_GT(r.stereo_bm_ms, 0.0);
  EXPECT_NEAR(r.ratio, r.frame_ms / r.stereo_bm_ms, 1e-9);  // one sample: its own ratio
  EXPECT_NE(format_frame_bench(r).find("frame / StereoBM"), std::string::npos);

  options.repetitions = 0;
  EXPECT_THROW(run_frame_bench(config, sequence.calibration, frames, options), Error);
  EXPECT_THROW(run_frame_bench(config, sequence.calibration, {}, FrameBenchOptions{}), Error);
}

}  // namespace
}  // namespace hazmap
