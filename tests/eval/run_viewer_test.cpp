// hazmap view's page (run_viewer.hpp) read back as the browser gets it: every grid of
// every frame round-trips exactly (bit for bit, NaN included) through the page's JSON and
// packed arrays; optional grids join only when every frame has them; the path comes from
// summary.json or the sequence's poses; the evaluation joins when eval/ is there; bad
// input names the file and leaves no page (nor spoils an earlier one).

#include "hazmap/eval/run_viewer.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "eval/oracle_run.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/eval/embedded_grids.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "hazmap/io/geotiff.hpp"
#include "test_support.hpp"

namespace hazmap::eval {
namespace {

namespace fs = std::filesystem;
using hazmap::testing::TempDir;

const std::vector<std::string> kFrames = {"000000", "000001", "000002"};

/// An oracle run of three frames (CCM 4 cm + Kalman 8 cm) with every grid the pipeline
/// writes, the footprint map and the fused clearance included; the rover moves 4 cm per
/// frame.
void write_run(const fs::path& run, const fs::path& seq) {
  hazmap::testing::TestWorld w;
  w.rocks = {{0.6, 0.3, 0.10}, {1.3, -0.35, 0.12}};
  std::vector<std::vector<hazmap::testing::OracleLayer>> frames;
  for (size_t f = 0; f < kFrames.size(); ++f)
    frames.push_back(
        {hazmap::testing::build_oracle_layer(w, 0.04, 40, 0.96 + 0.04 * static_cast<double>(f), 0.0, 0.03, true, 1e-4),
         hazmap::testing::build_oracle_layer(w, 0.08, 20, 0.96, 0.0, 0.05, false, 2e-4)});
  hazmap::testing::write_ground_truth(seq, w);
  hazmap::testing::write_poses(seq / "poses.txt", kFrames, {{0, 0}, {0.04, 0}, {0.08, 0}});
  hazmap::testing::write_oracle_run(run, hazmap::testing::oracle_config(), kFrames, frames);
  for (size_t f = 0; f < kFrames.size(); ++f) {
    DenseGrid footprint = frames[f][0].hazard, clearance = frames[f][0].height;
    for (float& v : footprint.values) v = v == 1.0f ? 2.0f : v;
    for (size_t i = 0; i < clearance.values.size(); ++i)
      clearance.values[i] = i % 3 == 0 ? NAN : 0.03f * static_cast<float>(i % 5);
    hazmap::testing::write_hazard_map(run, kFrames[f], "footprint_hazard.jdem", footprint);
    write_jdem(run / "frames" / kFrames[f] / "fused_clearance.jdem",
               to_jdem(clearance, "clearance", "m", kFrames[f]));
  }
}

/// summary.json as hazmap run writes it, with the frames' poses (x, y, yaw) unless
/// `record_poses` is false (a run older than that record).
void write_summary(const fs::path& run, const std::vector<Eigen::Vector3d>& poses,
                   const std::string& sequence = "", bool record_poses = true) {
  std::ofstream out(run / "summary.json");
  out << "{\n  \"finished\": true,\n  \"sequence\": " << hazmap::testing::json_string(sequence)
      << ",\n  \"frames\": [\n";
  for (size_t f = 0; f < poses.size(); ++f) {
    const double yaw = poses[f].z();
    out << (f ? ",\n" : "") << "    {\"name\": \"" << kFrames[f] << "\", \"points\": " << 1000 * f
        << ", \"written\": true, \"ms\": {\"read\": 1, \"map\": 2}";
    if (record_poses)
      out << ", \"T_W_B\": [" << poses[f].x() << ", " << poses[f].y() << ", 0, 0, 0, "
          << std::sin(yaw / 2) << ", " << std::cos(yaw / 2) << "]";
    out << "}";
  }
  out << "\n  ],\n  \"settings_yaml\": "
      << hazmap::testing::json_string(to_yaml(hazmap::testing::oracle_config())) << "\n}\n";
}

/// The text of the page's <script> element that starts with `open`.
std::string element(const std::string& page, const std::string& open) {
  const size_t at = page.find(open);
  if (at == std::string::npos) return "";
  const size_t from = at + open.size();
  return page.substr(from, page.find("</script>", from) - from);
}

YAML::Node page_data(const std::string& page) {
  return YAML::Load(element(page, "<script type=\"application/json\" id=\"run-data\">"));
}

std::vector<unsigned char> frame_buffer(const std::string& page, size_t frame) {
  return zlib_decompress(base64_decode(element(
      page, "<script type=\"application/octet-stream\" id=\"grids-" + std::to_string(frame) + "\">")));
}

/// The file a map's quantity comes from.
std::string file_of(const std::string& map, const std::string& quantity) {
  if (map == "fused") return quantity == "hazard" ? "fused_hazard.jdem" : "fused_clearance.jdem";
  if (map == "footprint") return "footprint_hazard.jdem";
  return map + "_" + quantity + ".jdem";
}

std::uint32_t bits(float v) {
  std::uint32_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

TEST(RunViewer, EmbedsEveryGridOfEveryFrameExactly) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  ViewerReport report;
  const std::string page = render_run_viewer(dir / "run", &report);
  EXPECT_EQ(report.frames, 3u);
  EXPECT_EQ(report.maps, 4u);  // L0, L1, fused, footprint
  EXPECT_FALSE(report.with_evaluation);
  EXPECT_FALSE(report.with_poses);  // the oracle's summary.json has neither poses nor sequence

  const YAML::Node data = page_data(page);
  ASSERT_TRUE(data["maps"].IsSequence()) << page.substr(0, 3000);
  std::vector<std::string> ids;
  for (const auto& m : data["maps"]) ids.push_back(m["id"].as<std::string>());
  EXPECT_EQ(ids, (std::vector<std::string>{"L0", "L1", "fused", "footprint"}));
  EXPECT_EQ(data["maps"][0]["quantities"].as<std::vector<std::string>>(),
            (std::vector<std::string>{"hazard", "height", "variance", "slope_x", "slope_y"}));
  EXPECT_EQ(data["maps"][1]["quantities"].as<std::vector<std::string>>(),
            (std::vector<std::string>{"hazard", "height", "variance"}));  // Kalman: no planes
  EXPECT_EQ(data["maps"][2]["quantities"].as<std::vector<std::string>>(),
            (std::vector<std::string>{"hazard", "clearance"}));

  size_t compared = 0, nans = 0;
  for (size_t f = 0; f < kFrames.size(); ++f) {
    const YAML::Node frame = data["frames"][f];
    EXPECT_EQ(frame["name"].as<std::string>(), kFrames[f]);
    const std::vector<unsigned char> buffer = frame_buffer(page, f);
    for (size_t m = 0; m < ids.size(); ++m) {
      const YAML::Node map = frame["maps"][m];
      for (const auto& q : map["arrays"]) {
        const std::string quantity = q.first.as<std::string>();
        const JdemGrid jdem = read_jdem(dir / "run" / "frames" / kFrames[f] / file_of(ids[m], quantity));
        EXPECT_EQ(map["rows"].as<int>(), jdem.rows);
        EXPECT_EQ(map["center_m"][0].as<double>(), jdem.center_x_m);
        PackedArray a;
        a.type = q.second[0].as<std::string>() == "f32" ? PackedType::float32 : PackedType::class8;
        a.offset = q.second[1].as<size_t>();
        a.count = q.second[2].as<size_t>();
        EXPECT_EQ(a.type == PackedType::class8, quantity == "hazard") << ids[m] << " " << quantity;
        const std::vector<float> back =
            a.type == PackedType::float32 ? unpack_float32(buffer, a) : unpack_classes(buffer, a);
        ASSERT_EQ(back.size(), jdem.values.size()) << ids[m] << " " << quantity;
        for (size_t i = 0; i < back.size(); ++i) {
          if (std::isnan(jdem.values[i])) {
            ASSERT_TRUE(std::isnan(back[i])) << ids[m] << " " << quantity << " cell " << i;
            ++nans;
          } else {
            ASSERT_EQ(bits(back[i]), bits(jdem.values[i])) << ids[m] << " " << quantity << " cell " << i;
          }
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(nans, 0u);
  EXPECT_GT(compared, 3u * (40 * 40 * 5 + 20 * 20 * 3));
  // Self-contained: no reference to anything beside the page.
  for (const char* outside : {"src=\"http", "href=\"http", "<link ", "src=\"file", "import("})
    EXPECT_EQ(page.find(outside), std::string::npos) << outside;
}

TEST(RunViewer, OptionalGridsJoinOnlyWhenEveryFrameHasThem) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  fs::remove(dir / "run" / "frames" / "000001" / "footprint_hazard.jdem");
  fs::remove(dir / "run" / "frames" / "000002" / "L0_slope_y.jdem");
  ViewerReport report;
  const YAML::Node data = page_data(render_run_viewer(dir / "run", &report));
  EXPECT_EQ(report.maps, 3u);
  EXPECT_EQ(data["maps"][2]["id"].as<std::string>(), "fused");
  EXPECT_EQ(data["maps"][0]["quantities"].as<std::vector<std::string>>(),
            (std::vector<std::string>{"hazard", "height", "variance", "slope_x"}));
}

TEST(RunViewer, ReadsGeoTiffGridsToo) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  const fs::path jdem = dir / "run" / "frames" / "000001" / "L1_height.jdem";
  const JdemGrid grid = read_jdem(jdem);
  write_geotiff(fs::path(jdem).replace_extension(".tif"), grid);  // output.format: geotiff
  fs::remove(jdem);
  const std::string page = render_run_viewer(dir / "run");
  const YAML::Node a = page_data(page)["frames"][1]["maps"][1]["arrays"]["height"];
  const std::vector<float> back =
      unpack_float32(frame_buffer(page, 1),
                     {PackedType::float32, a[1].as<size_t>(), a[2].as<size_t>()});
  ASSERT_EQ(back.size(), grid.values.size());
  for (size_t i = 0; i < back.size(); ++i)
    ASSERT_TRUE(bits(back[i]) == bits(grid.values[i]) ||
                (std::isnan(back[i]) && std::isnan(grid.values[i])))
        << "cell " << i;
}

TEST(RunViewer, PathFromSummaryJsonElseFromTheSequencePoses) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  write_summary(dir / "run", {{0.5, -0.25, M_PI / 2}, {0.54, -0.25, M_PI / 2}, {0.58, -0.2, 0.0}});
  ViewerReport report;
  YAML::Node poses = page_data(render_run_viewer(dir / "run", &report))["poses"];
  EXPECT_TRUE(report.with_poses);
  EXPECT_EQ(poses["source"].as<std::string>(), "summary.json");
  EXPECT_EQ(poses["x_m"].as<std::vector<double>>(), (std::vector<double>{0.5, 0.54, 0.58}));
  EXPECT_NEAR(poses["yaw_rad"][0].as<double>(), M_PI / 2, 1e-9);
  EXPECT_NEAR(poses["yaw_rad"][2].as<double>(), 0.0, 1e-9);

  // A run older than the T_W_B record: the poses.txt of the sequence it names.
  write_summary(dir / "run", {{9, 9, 0}, {9, 9, 0}, {9, 9, 0}}, (dir / "seq").string(), false);
  poses = page_data(render_run_viewer(dir / "run", &report))["poses"];
  EXPECT_EQ(poses["source"].as<std::string>(), (dir / "seq" / "poses.txt").string());
  EXPECT_EQ(poses["x_m"].as<std::vector<double>>(), (std::vector<double>{0.0, 0.04, 0.08}));
}

TEST(RunViewer, ShowsTheEvaluationWhenEvalHoldsOne) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  EvaluationOptions o;
  o.run_dir = dir / "run";
  o.sequence_dir = dir / "seq";
  o.error_map_frames = {"000001"};
  evaluate_run(o);
  ViewerReport report;
  const std::string page = render_run_viewer(dir / "run", &report);
  EXPECT_TRUE(report.with_evaluation);
  EXPECT_NE(page.find("<table id=\"metrics\">"), std::string::npos);
  EXPECT_NE(page.find("<td>footprint</td>"), std::string::npos);
  EXPECT_NE(page.find("data-frame=\"000001\"><img alt=\"errors 000001\" src=\"data:image/png;base64,"),
            std::string::npos);
  const YAML::Node ev = page_data(page)["eval"];
  EXPECT_EQ(ev["frames"].as<std::vector<std::string>>(), kFrames);
  EXPECT_EQ(ev["per_frame"]["hazard_recall"]["L0"].size(), 3u);
}

TEST(RunViewer, WritesRunViewHtmlAtomicallyOrWhereAsked) {
  TempDir dir;
  write_run(dir / "run", dir / "seq");
  ViewerOptions o;
  o.run_dir = dir / "run";
  const ViewerReport r = write_run_viewer(o);
  EXPECT_EQ(r.out_file, dir / "run" / "view.html");
  EXPECT_EQ(fs::file_size(r.out_file), r.page_bytes);
  o.out_file = dir / "pages" / "a.html";  // its folder is made
  EXPECT_EQ(write_run_viewer(o).out_file, dir / "pages" / "a.html");
  EXPECT_TRUE(fs::exists(dir / "pages" / "a.html"));
}

/// write_run_viewer's error, after checking that it left the page as it was.
std::string failure(const fs::path& run, const std::string& page_before) {
  ViewerOptions o;
  o.run_dir = run;
  try {
    write_run_viewer(o);
  } catch (const Error& e) {
    EXPECT_EQ(hazmap::testing::read_text(run / "view.html"), page_before);
    if (fs::is_directory(run)) {
      for (const auto& entry : fs::directory_iterator(run))
        EXPECT_EQ(entry.path().filename().string().find(".view.html"), std::string::npos)
            << "temporary left: " << entry.path();
    }
    return e.what();
  }
  ADD_FAILURE() << "no error for " << run;
  return "";
}

TEST(RunViewer, BadInputNamesTheFileAndLeavesNoPartialPage) {
  TempDir dir;
  // Not a run folder.
  fs::create_directories(dir / "empty");
  EXPECT_NE(failure(dir / "empty", "").find((dir / "empty" / "summary.json").string() + ": missing"),
            std::string::npos);
  EXPECT_NE(failure(dir / "nowhere", "").find("summary.json"), std::string::npos);

  write_run(dir / "run", dir / "seq");
  ViewerOptions o;
  o.run_dir = dir / "run";
  write_run_viewer(o);
  const std::string good = hazmap::testing::read_text(dir / "run" / "view.html");
  const fs::path frame1 = dir / "run" / "frames" / "000001";
  const auto damage = [&](const fs::path& file, const std::function<void(std::string&)>& change) {
    std::string text = hazmap::testing::read_text(file);
    const std::string before = text;
    change(text);
    std::ofstream(file, std::ios::trunc) << text;
    return before;
  };
  const auto restore = [](const fs::path& file, const std::string& text) {
    std::ofstream(file, std::ios::trunc) << text;
  };

  {  // a JDEM cut short: its last data row gone
    const fs::path file = frame1 / "L1_height.jdem";
    const std::string kept = damage(file, [](std::string& t) {
      t.erase(t.rfind('\n', t.size() - 2) + 1);
    });
    const std::string e = failure(dir / "run", good);
    EXPECT_NE(e.find(file.string()), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << "not one line: " << e;
    restore(file, kept);
  }
  {  // a hazard grid holding something else than classes
    const fs::path file = frame1 / "L0_hazard.jdem";
    const std::string kept = damage(file, [](std::string& t) {
      t.replace(t.rfind(" 1"), 2, " 7.5");
    });
    const std::string e = failure(dir / "run", good);
    EXPECT_NE(e.find(file.string() + ": value 7.5"), std::string::npos) << e;
    restore(file, kept);
  }
  {  // a grid of another size than its layer's other grids
    const fs::path file = frame1 / "L1_variance.jdem";
    const std::string kept = hazmap::testing::read_text(file);
    JdemGrid g = read_jdem(file);
    g.center_x_m += 0.08;
    write_jdem(file, g);
    const std::string e = failure(dir / "run", good);
    EXPECT_NE(e.find(file.string() + ": 20 x 20 cells"), std::string::npos) << e;
    EXPECT_NE(e.find("unlike L1_hazard.jdem"), std::string::npos) << e;
    restore(file, kept);
  }
  {  // a required grid missing
    const fs::path file = frame1 / "L0_variance.jdem";
    const std::string kept = hazmap::testing::read_text(file);
    fs::remove(file);
    EXPECT_NE(failure(dir / "run", good).find(file.string() + ": missing"), std::string::npos);
    restore(file, kept);
  }
  {  // summary.json damaged
    const fs::path file = dir / "run" / "summary.json";
    const std::string kept = damage(file, [](std::string& t) { t = t.substr(0, t.size() / 2); });
    EXPECT_NE(failure(dir / "run", good).find(file.string()), std::string::npos);
    restore(file, kept);
  }
  {  // eval/metrics.json damaged
    fs::create_directories(dir / "run" / "eval");
    std::ofstream(dir / "run" / "eval" / "metrics.json") << "{\"layers\": [";
    EXPECT_NE(failure(dir / "run", good).find((dir / "run" / "eval" / "metrics.json").string()),
              std::string::npos);
    fs::remove_all(dir / "run" / "eval");
  }
  {  // a run that wrote PNGs only
    const fs::path file = dir / "run" / "summary.json";
    const std::string kept = hazmap::testing::read_text(file);
    Config config = hazmap::testing::oracle_config();
    config.output.jdem = false;
    std::ofstream(file, std::ios::trunc)
        << "{\"settings_yaml\": " << hazmap::testing::json_string(to_yaml(config)) << "}\n";
    EXPECT_NE(failure(dir / "run", good).find(file.string() + ": the run wrote no grids"),
              std::string::npos);
    restore(file, kept);
  }
  fs::rename(dir / "run" / "frames", dir / "run" / "frames_moved");
  EXPECT_NE(failure(dir / "run", good).find((dir / "run" / "frames").string() + ": missing"),
            std::string::npos);
  fs::rename(dir / "run" / "frames_moved", dir / "run" / "frames");
  EXPECT_EQ(write_run_viewer(o).frames, 3u);  // whole again
}

}  // namespace
}  // namespace hazmap::eval
