// The README, run as written (issue 35): the quick start's commands, extracted from
// README.md itself, each run from the repository's top folder with fewer frames, into a
// temporary folder, and expected to exit 0 as the README says; and the calibration
// template's worked example, loaded from the README's text and checked against the
// geometry it claims.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/rig_geometry.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;

std::string readme() { return testing::read_text(testing::source_dir() / "README.md"); }

/// The fenced blocks of `language` between the headings `from` and `to`.
std::vector<std::string> blocks(const std::string& text, const std::string& from,
                                const std::string& to, const std::string& language) {
  std::vector<std::string> out;
  const std::size_t begin = text.find(from);
  const std::size_t end = text.find(to, begin);
  if (begin == std::string::npos || end == std::string::npos) return out;
  const std::string fence = "```" + language + "\n";
  for (std::size_t at = text.find(fence, begin); at != std::string::npos && at < end;
       at = text.find(fence, at)) {
    const std::size_t body = at + fence.size();
    const std::size_t close = text.find("```\n", body);
    out.push_back(text.substr(body, close - body));
    at = close + 4;
  }
  return out;
}

/// A block's commands: continuation lines joined, comments dropped.
std::vector<std::string> commands(const std::string& block) {
  std::vector<std::string> out;
  std::istringstream lines(block);
  std::string line, joined;
  while (std::getline(lines, line)) {
    const std::size_t hash = line.find(" #");
    if (hash != std::string::npos) line.resize(hash);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    const bool more = !line.empty() && line.back() == '\\';
    if (more) line.pop_back();
    joined += line;
    if (more) continue;
    if (joined.find_first_not_of(' ') != std::string::npos) out.push_back(joined);
    joined.clear();
  }
  return out;
}

std::vector<std::string> words(const std::string& command) {
  std::istringstream in(command);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// The command as the test runs it: the built binary, outputs under `tmp`, few frames.
std::string adapted(const std::string& command, const fs::path& tmp) {
  std::vector<std::string> w = words(command);
  const std::string sub = w.size() > 1 ? w[1] : "";
  bool frames = false, count = false;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == "build/hazmap") w[i] = HAZMAP_CLI;
    if (w[i].rfind("out/", 0) == 0) w[i] = (tmp / w[i]).string();
    if (w[i].rfind("/tmp/", 0) == 0) w[i] = (tmp / w[i].substr(5)).string();
    if (w[i] == "--frames" && i + 1 < w.size()) {
      frames = true;
      if (sub == "simulate") w[i + 1] = "3";
      if (sub == "bench") w[i + 1] = "1";
    }
    if (w[i] == "--count" && i + 1 < w.size()) count = true, w[i + 1] = "1";
  }
  std::string out;
  for (const std::string& x : w) out += (out.empty() ? "" : " ") + x;
  if ((sub == "run" || sub == "stereo") && !frames) out += " --frames 0:2";
  if (sub == "simulate" && !frames) out += " --frames 3";
  if (sub == "check" && !count) out += " --count 1";
  if (sub == "bench") out += " --frames 1 --repetitions 1";
  return out + " --quiet";
}

TEST(ReadmeWalkthrough, QuickStartCommandsExitAsDocumented) {
  const std::vector<std::string> found =
      blocks(readme(), "## Quick start", "## Your own rover in 5 steps", "bash");
  ASSERT_EQ(found.size(), 2u) << "the quick start's two command blocks";
  const bool shared = fs::is_directory(testing::source_dir() / "../shared/data");
  testing::TempDir tmp;
  int ran = 0;
  for (const std::string& block : found)
    for (const std::string& c : commands(block)) {
      if (c.rfind("tools/", 0) == 0) continue;  // installs and builds: what made HAZMAP_CLI
      ASSERT_EQ(c.rfind("build/hazmap", 0), 0u) << "not a hazmap command: " << c;
      if (c.find("../shared/data") != std::string::npos && !shared) continue;
      if (c == "build/hazmap --help") {
        EXPECT_EQ(testing::run_command(std::string(HAZMAP_CLI) + " --help").exit_code, 0);
        ++ran;
        continue;
      }
      const std::string line = "cd " + testing::source_dir().string() + " && " +
                               adapted(c, tmp.path()) + " 2>&1";
      const testing::CommandResult r = testing::run_command(line);
      EXPECT_EQ(r.exit_code, 0) << c << "\nran: " << line << "\n" << r.output;
      ++ran;
    }
  EXPECT_GE(ran, 11);
}

TEST(ReadmeWalkthrough, CalibrationWorkedExampleIsWhatItSays) {
  const std::string text = readme();
  const std::vector<std::string> yaml =
      blocks(text, "`calibration.yaml`, a worked example", "`rpy_deg` is not", "yaml");
  ASSERT_EQ(yaml.size(), 1u);
  testing::TempDir dir;
  std::ofstream(dir / "calibration.yaml") << yaml[0];
  const StereoCalibration c = load_stereo_calibration(dir / "calibration.yaml");
  EXPECT_EQ(c.body_pose_source, BodyPoseSource::rpy_deg);
  EXPECT_TRUE(c.T_B_C.translation().isApprox(Eigen::Vector3d(0.1, 0.03, 0.2), 1e-12));
  // Forward (+x_B), 25 deg down, image right = -y_B: the axes built independently.
  const double p = 25 * M_PI / 180;
  const Eigen::Matrix3d R = c.T_B_C.linear();
  EXPECT_TRUE(R.col(2).isApprox(Eigen::Vector3d(std::cos(p), 0, -std::sin(p)), 1e-12)) << R;
  EXPECT_TRUE(R.col(0).isApprox(Eigen::Vector3d(0, -1, 0), 1e-12)) << R;
  const CameraView v = camera_view(R, c);
  EXPECT_NEAR(v.axis_elevation_deg, -25.0, 1e-9);
  EXPECT_NEAR(v.roll_deg, 0.0, 1e-9);
  EXPECT_TRUE(v.plausible());
  // The quaternion in the comment is the same rotation (to its 6 printed digits).
  std::smatch m;
  ASSERT_TRUE(std::regex_search(yaml[0], m, std::regex(
      R"(quaternion: \[([-0-9.]+), ([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\])")));
  const Eigen::Quaterniond q(std::stod(m[4]), std::stod(m[1]), std::stod(m[2]), std::stod(m[3]));
  EXPECT_NEAR(q.norm(), 1.0, 1e-6);
  EXPECT_LT((q.normalized().toRotationMatrix() - R).cwiseAbs().maxCoeff(), 2e-6);
  // The geometry guards pass it on a level body.
  Sequence seq;
  seq.calibration = c;
  SequenceFrame f;
  f.name = "000000";
  seq.frames.push_back(f);
  EXPECT_TRUE(check_rig_geometry(seq, seq.frames).empty());
}

}  // namespace
}  // namespace hazmap
