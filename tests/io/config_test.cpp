#include "hazmap/io/config.hpp"

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

const char* kMinimal = R"(
map:
  layers:
    - {resolution: 0.01, size: 128, rule: kalman, hazard: {kernel: 7}}
    - {resolution: 0.04, size: 64, rule: kalman}
)";

std::string config_error(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  try {
    parse_config(yaml, "test.yaml", sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ShippedDefaultLoads) {
  const Config c = load_config(testing::source_dir() / "config/default.yaml");
  ASSERT_EQ(c.map.layers.size(), 1u);
  EXPECT_EQ(c.map.layers[0].rule, RuleKind::kalman);
  EXPECT_DOUBLE_EQ(c.map.layers[0].resolution_m, 0.01);
  EXPECT_EQ(c.map.layers[0].hazard.kernel, 7);
  EXPECT_EQ(c.stereo.matcher, StereoMatcher::bm);
}

TEST(Config, DefaultsFillMissingSections) {
  const Config c = parse_config(kMinimal, "t");
  EXPECT_EQ(c.stereo.num_disparities, 128);
  EXPECT_DOUBLE_EQ(c.sensor.disparity_error_px, 0.25);
  EXPECT_DOUBLE_EQ(c.hazard.max_slope_deg, 20.0);
  EXPECT_TRUE(c.hazard.incremental);  // SPEC 8.6
}

TEST(Config, UnknownKeyIsNamedWithItsPathAndLine) {
  const std::string msg = config_error(std::string(kMinimal) + "stereo:\n  blok_size: 9\n");
  EXPECT_EQ(msg, "test.yaml:7: unknown key 'stereo.blok_size'; did you mean 'stereo.block_size'?");
}

TEST(Config, DuplicateKeysAreNamedWithTheirPathAndLine) {
  // A duplicate would otherwise be silently resolved to one of its values.
  EXPECT_EQ(config_error("stereo:\n  block_size: 9\n  block_size: 11\n"),
            "test.yaml:3: duplicate key 'stereo.block_size'");
  EXPECT_EQ(config_error("hazard: {k_sigma: 3}\nhazard: {k_sigma: 0}\n"),
            "test.yaml:2: duplicate key 'hazard'");
  EXPECT_NE(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: kalman, size: 16}\n")
                .find("duplicate key 'map.layers.0.size'"),
            std::string::npos);
  // The same key in two different maps is no duplicate.
  EXPECT_NO_THROW(parse_config(
      std::string(kMinimal) + "rules: {kalman: {gate_sigma: 0}, omg: {gate_sigma: 0}}\n", "t"));
}

TEST(Config, UnknownKeyInsideALayerIsNamed) {
  const std::string msg =
      config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: kalman, colour: red}\n");
  EXPECT_NE(msg.find("unknown key 'map.layers.0.colour'"), std::string::npos) << msg;
}

TEST(Config, WrongTypeIsNamed) {
  const std::string msg = config_error(std::string(kMinimal) + "stereo: {block_size: eleven}\n");
  EXPECT_NE(msg.find("key 'stereo.block_size': expected an integer, found 'eleven'"),
            std::string::npos)
      << msg;
}

TEST(Config, ImpossibleValuesAreNamed) {
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 127, rule: kalman}\n"),
            "config: key 'map.layers.0.size': must be even and >= 2");
  EXPECT_NE(config_error(std::string(kMinimal) + "sensor: {pointing_error_px: -1}\n")
                .find("'sensor.pointing_error_px'"),
            std::string::npos);
  const std::string multiple = config_error(
      "map:\n  layers:\n    - {resolution: 0.04, size: 8, rule: kalman}\n"
      "    - {resolution: 0.06, size: 8, rule: kalman}\n");
  EXPECT_NE(multiple.find("'map.layers.1.resolution': must be an integer multiple"),
            std::string::npos)
      << multiple;
  EXPECT_NE(config_error(std::string(kMinimal) +
                         "sensor: {pointing_error_px: 0}\nrules: {ccm: {weighting: det}}\n")
                .find("'rules.ccm.weighting': 'det' needs sensor.pointing_error_px > 0"),
            std::string::npos);
  EXPECT_NE(config_error(std::string(kMinimal) + "sensor: {model: cone}\n")
                .find("'sensor.model': 'cone' is not one of axis | ray"),
            std::string::npos);
  for (const char* bad : {"occlusion_reach: -1", "occlusion_margin: -0.01", "occlusion_fill: 11"}) {
    const std::string key = std::string(bad).substr(0, std::string(bad).find(':'));
    EXPECT_NE(config_error(std::string(kMinimal) + "stereo: {" + bad + "}\n")
                  .find("'stereo." + key + "'"),
              std::string::npos)
        << bad;
  }
}

TEST(Config, OcclusionKeysHaveDefaultsAndRoundTrip) {
  const Config c = parse_config(kMinimal, "t");
  EXPECT_DOUBLE_EQ(c.stereo.occlusion_reach, 2.0);
  EXPECT_DOUBLE_EQ(c.stereo.occlusion_margin_m, 0.01);
  EXPECT_DOUBLE_EQ(c.stereo.occlusion_fill_m, 0.03);
  const Config set = parse_config(kMinimal, "t",
                                  {"stereo.occlusion_reach=0", "stereo.occlusion_margin=0.02",
                                   "stereo.occlusion_fill=0"});
  const Config again = parse_config(to_yaml(set), "dump");
  EXPECT_EQ(again.stereo.occlusion_reach, 0.0);
  EXPECT_DOUBLE_EQ(again.stereo.occlusion_margin_m, 0.02);
  EXPECT_EQ(again.stereo.occlusion_fill_m, 0.0);
}

TEST(Config, SetOverridesNestedKeysAndListElements) {
  const Config c = parse_config(kMinimal, "t",
                                {"stereo.matcher=sgbm", "map.layers.1.size=32",
                                 "rules.kalman.time_inflation=0", "sensor.model=ray"});
  EXPECT_EQ(c.stereo.matcher, StereoMatcher::sgbm);
  EXPECT_EQ(c.map.layers[1].size, 32);
  EXPECT_EQ(c.rules.kalman.time_inflation_m2, 0.0);
  EXPECT_EQ(c.sensor.model, SensorModel::ray);
}

TEST(Config, SetOfUnknownKeyOrBadIndexFails) {
  EXPECT_NE(config_error(kMinimal, {"stereo.nope=1"}).find("unknown key 'stereo.nope'"),
            std::string::npos);
  EXPECT_NE(config_error(kMinimal, {"map.layers.5.size=8"}).find("map.layers.5"),
            std::string::npos);
  EXPECT_NE(config_error(kMinimal, {"novalue"}).find("expected KEY=VALUE"), std::string::npos);
}

// A value given on the command line has no line in the file: its error names the
// assignment, while the file's own keys keep their lines.
TEST(Config, ErrorsInSetValuesNameTheAssignment) {
  EXPECT_EQ(config_error(kMinimal, {"stereo.search=groundband"}),
            "--set stereo.search=groundband: key 'stereo.search': 'groundband' is not one of "
            "full | ground_band");
  EXPECT_EQ(config_error(kMinimal, {"map.layers.1.size=x"}),
            "--set map.layers.1.size=x: key 'map.layers.1.size': expected an integer, found 'x'");
  EXPECT_EQ(config_error(kMinimal, {"stereo.nope=1"}), "--set stereo.nope=1: unknown key 'stereo.nope'");
  // A whole map set on the command line: its keys are the assignment's.
  EXPECT_EQ(config_error(kMinimal, {"rules.ccm={min_points: many}"}),
            "--set rules.ccm={min_points: many}: key 'rules.ccm.min_points': expected an "
            "integer, found 'many'");
  // The file's keys beside a --set one keep their file and line.
  const std::string file = "stereo:\n  z_max: 5\n  block_size: x\n" + std::string(kMinimal);
  EXPECT_EQ(config_error(file, {"stereo.z_max=4"}),
            "test.yaml:3: key 'stereo.block_size': expected an integer, found 'x'");
}

TEST(Config, DumpReparsesToTheSameValues) {
  const Config c = parse_config(kMinimal, "t",
                                {"stereo.block_size=15", "hazard.wheelbase=0.4", "hazard.incremental=false"});
  const Config again = parse_config(to_yaml(c), "dump");
  EXPECT_EQ(again.stereo.block_size, 15);
  EXPECT_DOUBLE_EQ(again.hazard.wheelbase_m, 0.4);
  EXPECT_FALSE(again.hazard.incremental);
  ASSERT_EQ(again.map.layers.size(), 2u);
  EXPECT_DOUBLE_EQ(again.map.layers[1].resolution_m, 0.04);
  EXPECT_EQ(to_yaml(again), to_yaml(c));
}

}  // namespace
}  // namespace hazmap

namespace hazmap {
namespace {

TEST(Config, EveryShippedConfigLoadsAndMatchesTheThesisTables) {
  for (const char* name : {"default.yaml", "cadre_flight.yaml", "thesis_pwc.yaml", "thesis_ccm.yaml"})
    EXPECT_NO_THROW(load_config(testing::source_dir() / "config" / name)) << name;
  const Config flight = load_config(testing::source_dir() / "config/cadre_flight.yaml");
  ASSERT_EQ(flight.map.layers.size(), 4u);
  EXPECT_EQ(flight.map.layers[0].rule, RuleKind::kalman);
  for (size_t i = 1; i < 4; ++i) EXPECT_EQ(flight.map.layers[i].rule, RuleKind::ccm);
  // SPEC 11 / thesis 8.1: only the coarsest layer covers 10 m; the 1 cm layer is small
  // (1.28-2.56 m), so that it maps only points whose noise suits it.
  EXPECT_GE(flight.map.layers.back().resolution_m * flight.map.layers.back().size, 10.0 - 1e-9);
  const double fine_extent = flight.map.layers[0].resolution_m * flight.map.layers[0].size;
  EXPECT_GE(fine_extent, 1.28 - 1e-9);
  EXPECT_LE(fine_extent, 2.56 + 1e-9);
  const Config pwc = load_config(testing::source_dir() / "config/thesis_pwc.yaml");
  const double thresholds[] = {0.025, 0.073, 0.30, 0.70};
  const int kernels[] = {7, 5, 5, 3};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(pwc.map.layers[i].rule, RuleKind::omg);
    EXPECT_DOUBLE_EQ(pwc.map.layers[i].hazard.roughness_threshold_m.value_or(-1), thresholds[i]);
    EXPECT_EQ(pwc.map.layers[i].hazard.kernel, kernels[i]);
  }
  const Config ccm = load_config(testing::source_dir() / "config/thesis_ccm.yaml");
  ASSERT_EQ(ccm.map.layers.size(), 5u);
  for (const auto& l : ccm.map.layers) EXPECT_NEAR(l.hazard.h_min_m.value_or(-1), 0.75 * l.resolution_m, 1e-12);
}

// Issue 24: values that become loop steps, indices or sizes are bounded, with the reason.
TEST(Config, StrideResolutionAndLayerSizeAreBounded) {
  // stride 2^31 - 1 overflowed the pixel loop's `u += step` and crashed the run.
  EXPECT_EQ(config_error(kMinimal, {"stereo.stride=2147483647"}),
            "config: key 'stereo.stride': must be in [1, 4096] (a larger stride keeps at most "
            "one pixel of a 4096 px image)");
  EXPECT_EQ(config_error(kMinimal, {"stereo.stride=4096"}), "");
  // 1e-300 m made llround(x / r) overflow in the rolling grid.
  for (const char* r : {"1e-300", "0.00005", "1e300", "2000", "0", "-0.01"}) {
    const std::string msg = config_error(
        "map:\n  layers:\n    - {resolution: " + std::string(r) + ", size: 8, rule: kalman}\n");
    EXPECT_EQ(msg.rfind("config: key 'map.layers.0.resolution': must be in [1e-4, 1000] m", 0), 0u)
        << r << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.0001, size: 8, rule: kalman}\n"),
            "");
  // Radii become a reach in cells (radius / r as int): 1e300 overflowed the conversion.
  EXPECT_EQ(config_error(kMinimal, {"hazard.footprint_radius=1e300"}),
            "config: key 'hazard.footprint_radius': must be finite, in [0, 100] m (a reach in "
            "cells must fit an int), or `auto` (wheelbase / 2)");
  EXPECT_EQ(config_error(kMinimal, {"hazard.wheelbase=1e300"}),
            "config: key 'hazard.wheelbase': must be in (0, 100] m (a reach in cells must fit an "
            "int)");
  // 46342^2 cells do not fit the layers' int slots (46341 is odd, already refused).
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 46342, rule: kalman}\n"),
            "config: key 'map.layers.0.size': must be <= 46340 (a layer's size^2 cells are "
            "addressed with 32-bit indices)");
}

}  // namespace
}  // namespace hazmap
