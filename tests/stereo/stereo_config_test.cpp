// The `stereo` keys of the configuration (SPEC 13): every matcher knob parsed,
// validated with a message naming the key, and written back by to_yaml.

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/stereo/disparity.hpp"

namespace hazmap {
namespace {

const char* kLayers = "map: {layers: [{resolution: 0.01, size: 64, rule: kalman}]}\n";

std::string error_of(const std::string& stereo_yaml) {
  try {
    parse_config(std::string(kLayers) + stereo_yaml, "s.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(StereoConfig, EveryKnobParsesAndRoundTrips) {
  const Config c = parse_config(std::string(kLayers) +
                                    "stereo: {matcher: sgbm, sgbm_mode: hh4, sgbm_p1: 100, "
                                    "sgbm_p2: 400, pre_filter_type: xsobel, pre_filter_size: 15, "
                                    "input_bits: 12, roi: [10, 20, 300, 200], disp12_max_diff: 2, "
                                    "speckle_window: 50, speckle_range: 3, rectify_alpha: 0.5, "
                                    "stride: 2, z_min: 0.2, z_max: 4}\n",
                                "s.yaml");
  const StereoConfig& s = c.stereo;
  EXPECT_EQ(s.sgbm_mode, SgbmMode::hh4);
  EXPECT_EQ(s.pre_filter_type, PreFilterType::xsobel);
  EXPECT_EQ(s.pre_filter_size, 15);
  EXPECT_EQ(s.input_bits, 12);
  EXPECT_EQ(s.roi_px, (std::array<int, 4>{10, 20, 300, 200}));
  const Config again = parse_config(to_yaml(c), "dump");
  EXPECT_EQ(again.stereo.roi_px, s.roi_px);
  EXPECT_EQ(again.stereo.pre_filter_type, s.pre_filter_type);
  EXPECT_EQ(again.stereo.pre_filter_size, s.pre_filter_size);
  EXPECT_EQ(again.stereo.input_bits, s.input_bits);
  EXPECT_EQ(again.stereo.sgbm_p2, 400);
  // Both matchers accept every mode and pre-filter the config allows.
  for (const char* mode : {"sgbm", "hh", "sgbm_3way", "hh4"}) {
    StereoConfig sgbm = s;
    sgbm.sgbm_mode = *enum_value<SgbmMode>(mode);
    EXPECT_NO_THROW(DisparityMatcher{sgbm}) << mode;
  }
  for (const char* type : {"normalized_response", "xsobel"}) {
    StereoConfig bm = s;
    bm.matcher = StereoMatcher::bm;
    bm.pre_filter_type = *enum_value<PreFilterType>(type);
    EXPECT_NO_THROW(DisparityMatcher{bm}) << type;
  }
}

TEST(StereoConfig, BadValuesNameTheKey) {
  EXPECT_NE(error_of("stereo: {pre_filter_type: sobel}\n")
                .find("key 'stereo.pre_filter_type': 'sobel' is not one of normalized_response | xsobel"),
            std::string::npos);
  EXPECT_EQ(error_of("stereo: {pre_filter_size: 4}\n"),
            "config: key 'stereo.pre_filter_size': must be odd and in [5, 255]");
  EXPECT_EQ(error_of("stereo: {input_bits: 20}\n"),
            "config: key 'stereo.input_bits': must be in [8, 16] or `auto` (detect)");
  EXPECT_NE(error_of("stereo: {roi: [1, 2, 3]}\n").find("key 'stereo.roi': expected a list of 4 numbers"),
            std::string::npos);
  EXPECT_NE(error_of("stereo: {roi: [1, 2, 3.5, 4]}\n")
                .find("key 'stereo.roi': expected 4 integers [x, y, width, height]"),
            std::string::npos);
  EXPECT_EQ(error_of("stereo: {roi: [0, -1, 30, 40]}\n"),
            "config: key 'stereo.roi': x, y, width and height must be >= 0");
}

// SPEC 3.4: the ground-band keys parse, round-trip through the resolved config, and bad
// values name their key.
TEST(StereoConfig, GroundBandKeys) {
  const Config defaults = parse_config(kLayers, "s.yaml");
  EXPECT_EQ(defaults.stereo.search, DisparitySearch::full);
  EXPECT_EQ(defaults.stereo.band_max_slope_deg, 30.0);
  EXPECT_EQ(defaults.stereo.band_max_height_m, 0.5);
  EXPECT_EQ(defaults.stereo.band_max_depth_m, 0.5);
  const Config c = parse_config(std::string(kLayers) +
                                    "stereo: {search: ground_band, band_max_slope_deg: 12.5, "
                                    "band_max_height: 0.04, band_max_depth: 0.2}\n",
                                "s.yaml");
  EXPECT_EQ(c.stereo.search, DisparitySearch::ground_band);
  const Config again = parse_config(to_yaml(c), "dump");
  EXPECT_EQ(again.stereo.search, DisparitySearch::ground_band);
  EXPECT_EQ(again.stereo.band_max_slope_deg, 12.5);
  EXPECT_EQ(again.stereo.band_max_height_m, 0.04);
  EXPECT_EQ(again.stereo.band_max_depth_m, 0.2);
  const Config set = parse_config(kLayers, "s.yaml", {"stereo.search=ground_band"});
  EXPECT_EQ(set.stereo.search, DisparitySearch::ground_band);

  EXPECT_NE(error_of("stereo: {search: band}\n")
                .find("key 'stereo.search': 'band' is not one of full | ground_band"),
            std::string::npos);
  EXPECT_EQ(error_of("stereo: {band_max_slope_deg: 90}\n"),
            "config: key 'stereo.band_max_slope_deg': must be in [0, 90)");
  EXPECT_EQ(error_of("stereo: {band_max_height: -0.1}\n"),
            "config: key 'stereo.band_max_height': must be finite and >= 0");
  EXPECT_EQ(error_of("stereo: {band_max_depth: -1}\n"),
            "config: key 'stereo.band_max_depth': must be finite and >= 0");
  // The full-search-only matcher refuses the band rather than silently searching fully.
  StereoConfig band;
  band.search = DisparitySearch::ground_band;
  EXPECT_THROW(DisparityMatcher{band}, Error);
}

}  // namespace
}  // namespace hazmap
