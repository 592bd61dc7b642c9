// Your own rover, right the first time (issue 35; issue 37 item 5): well-formed but
// wrong geometry, configuration mistakes and option mistakes a new user makes, each run
// through the real `hazmap` binary on a tiny sequence in a temporary folder. Every case
// checks the exact one-line message, the exit code, and that an earlier OUT is left
// exactly as it was (byte for byte), or, for warnings, that the run goes on and says it
// once.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include "hazmap/core/types.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/preflight_check.hpp"
#include "hazmap/pipeline/rig_geometry.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::write_text;
using testing::replaced;
using testing::snapshot;

const char* const kConfig = testing::kTinyConfig;

/// A rotation as calibration.yaml's quaternion list, scalar last, 17 digits.
std::string quaternion_text(const Eigen::Matrix3d& R, bool scalar_first = false) {
  const Eigen::Quaterniond q(R);
  char text[160];
  if (scalar_first)
    std::snprintf(text, sizeof text, "[%.17g, %.17g, %.17g, %.17g]", q.w(), q.x(), q.y(), q.z());
  else
    std::snprintf(text, sizeof text, "[%.17g, %.17g, %.17g, %.17g]", q.x(), q.y(), q.z(), q.w());
  return text;
}

/// The tiny sequence's mount (straight down from 0.625 m) as a rotation.
Eigen::Matrix3d tiny_mount() {
  return Eigen::Quaterniond(0, 0.70710678118654752, -0.70710678118654752, 0).toRotationMatrix();
}
const char* const kTinyMount =
    "quaternion: [0.70710678118654752, -0.70710678118654752, 0, 0]";

/// A case folder: the tiny sequence (SEQ = dir/seq), config.yaml, an earlier OUT.
class Case {
 public:
  Case() {
    testing::write_tiny_sequence(dir() / "seq", 3);
    write_text(dir() / "config.yaml", kConfig);
    testing::write_previous_out(dir() / "out");
  }
  fs::path dir() const { return temp_.path(); }
  std::string calibration() const { return testing::read_text(dir() / "seq/calibration.yaml"); }
  void set_calibration(const std::string& text) const { write_text(dir() / "seq/calibration.yaml", text); }
  void edit_calibration(const std::string& from, const std::string& to) const {
    set_calibration(replaced(calibration(), from, to));
  }
  /// `hazmap COMMAND` on the case with `extra`; stderr only.
  CommandResult run(const std::string& command, const std::string& extra = "") const {
    std::string args = command;
    if (command == "run" || command == "stereo" || command == "check")
      args += " --config " + (dir() / "config.yaml").string() + " --sequence " +
              (dir() / "seq").string();
    if (command == "run" || command == "stereo")
      args += " --out " + (dir() / "out").string() + " --overwrite";
    return testing::run_hazmap(args + " --quiet " + extra);
  }
  std::string fill(std::string text) const {
    for (std::size_t at; (at = text.find("{dir}")) != std::string::npos;)
      text.replace(at, 5, dir().string());
    return text;
  }

 private:
  testing::TempDir temp_;
};

/// `hazmap run` and `hazmap stereo` both refuse with exactly `message` (exit 1), OUT as it
/// was; `hazmap check` lists it as a problem (exit 1).
void expect_refused(const Case& c, const std::string& message, bool check_too = true) {
  const auto before = snapshot(c.dir() / "out");
  for (const char* command : {"run", "stereo"}) {
    SCOPED_TRACE(command);
    const CommandResult r = c.run(command);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "hazmap: error: " + c.fill(message) + "\n");
    EXPECT_EQ(snapshot(c.dir() / "out"), before) << "OUT changed";
  }
  if (!check_too) return;
  const CommandResult r = testing::run_command(
      std::string(HAZMAP_CLI) + " check --quiet --count 1 --config " +
      (c.dir() / "config.yaml").string() + " --sequence " + (c.dir() / "seq").string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("  - " + c.fill(message) + "\n"), std::string::npos) << r.output;
}

const std::string kCalib = "{dir}/seq/calibration.yaml";

TEST(OwnRover, BaselineInMillimetres) {
  Case c;
  c.edit_calibration("T: [-0.05, 0, 0]", "T: [-50, 0, 0]");
  expect_refused(c, kCalib + ": key 'T': baseline |T| = 50 m is outside 0.01-2 m, the range of a "
                             "rover's stereo pair; T is in metres: 50 looks like millimetres (0.05 m)");
}

TEST(OwnRover, BaselineInCentimetres) {
  Case c;
  c.edit_calibration("T: [-0.05, 0, 0]", "T: [-5, 0, 0]");
  expect_refused(c, kCalib + ": key 'T': baseline |T| = 5 m is outside 0.01-2 m, the range of a "
                             "rover's stereo pair; T is in metres: 5 looks like centimetres (0.05 m)");
}

TEST(OwnRover, BaselineOfFiveMillimetres) {
  Case c;
  c.edit_calibration("T: [-0.05, 0, 0]", "T: [-0.005, 0, 0]");
  expect_refused(c, kCalib + ": key 'T': baseline |T| = 0.005 m is outside 0.01-2 m, the range of "
                             "a rover's stereo pair; T is in metres");
}

TEST(OwnRover, FocalLengthInMillimetres) {
  Case c;
  c.set_calibration(replaced(replaced(c.calibration(), "K: [50, 0, 31.5, 0, 50,", "K: [4, 0, 31.5, 0, 4,"),
                             "K: [50, 0, 31.5, 0, 50,", "K: [4, 0, 31.5, 0, 4,"));
  expect_refused(c, kCalib + ": key 'left.K': fx = 4 px gives a 166 deg field of view across the "
                             "64 px image (plausible: 2-160 deg): K is in pixels; a focal length "
                             "in millimetres must be divided by the pixel pitch (f_px = f_mm / "
                             "pitch_mm)");
}

TEST(OwnRover, FocalLengthOfALargerImage) {
  Case c;
  c.set_calibration(replaced(replaced(c.calibration(), "K: [50, 0, 31.5, 0, 50,", "K: [5000, 0, 31.5, 0, 5000,"),
                             "K: [50, 0, 31.5, 0, 50,", "K: [5000, 0, 31.5, 0, 5000,"));
  expect_refused(c, kCalib + ": key 'left.K': fx = 5000 px gives a 0.73 deg field of view across "
                             "the 64 px image (plausible: 2-160 deg): K must be in pixels of these "
                             "images (written for a larger image, or in other units?)");
}

// The natural guess for a forward camera pitched 30 deg down, [0, 30, 0], looks at the sky.
TEST(OwnRover, RpyTakenForTheCamerasOwnPitch) {
  Case c;
  c.edit_calibration(kTinyMount, "rpy_deg: [0, 30, 0]");
  expect_refused(c, kCalib + ": key 'T_body_left': the left camera is mounted so that its optical "
                             "axis points 60 deg above the horizon and no pixel looks below it; "
                             "rpy_deg is not the camera's own pitch: rpy_deg rotates the camera's "
                             "axes (x right, y down, z forward) into the body's (x forward, y left, "
                             "z up): a forward camera pitched down theta is rpy_deg: [-(90 + "
                             "theta), 0, -90], quaternion [qx, qy, qz, qw] scalar last "
                             "(docs/conventions.md)");
}

// A forward camera pitched down theta, its quaternion written [qw, qx, qy, qz], reads as
// a level camera turned theta to the side: a plausible mount until the ground is seen.
// The first frame's ground tells the two apart: `run` warns with the hint, `check` lists
// it as a problem.
TEST(OwnRover, QuaternionWrittenScalarFirst) {
  testing::TempDir dir;
  fs::copy(testing::source_dir() / "data/sample", dir / "seq", fs::copy_options::recursive);
  std::string calibration = testing::read_text(dir / "seq/calibration.yaml");
  const std::string right = "quaternion: [-0.624596573818, 0.624596573818, -0.33148019545, 0.33148019545]";
  calibration = replaced(calibration, right,
                         "quaternion: [0.33148019545, -0.624596573818, 0.624596573818, -0.33148019545]");
  write_text(dir / "seq/calibration.yaml", calibration);
  const std::string config = (testing::source_dir() / "config/default.yaml").string();
  const std::string hint =
      "; T_body_left's quaternion looks written scalar first: read so, the ground would be tilted "
      "0.2 deg; hazmap reads [qx, qy, qz, qw]";
  CommandResult r = testing::run_command(std::string(HAZMAP_CLI) + " run --quiet --frames 0:1 --config " +
                                         config + " --sequence " + (dir / "seq").string() +
                                         " --out " + (dir / "out").string() + " 2>&1 1>/dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find("frame 000000: the ground fitted to the points is tilted 34."), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(hint + " (a rover really"), std::string::npos) << r.output;
  r = testing::run_command(std::string(HAZMAP_CLI) + " check --count 1 --config " + config +
                           " --sequence " + (dir / "seq").string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(hint + "\n"), std::string::npos) << r.output;
  // Written the right way round: no warning, verdict OK.
  write_text(dir / "seq/calibration.yaml", replaced(calibration,
      "quaternion: [0.33148019545, -0.624596573818, 0.624596573818, -0.33148019545]", right));
  r = testing::run_command(std::string(HAZMAP_CLI) + " check --count 1 --config " + config +
                           " --sequence " + (dir / "seq").string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(OwnRover, CameraUpsideDown) {
  Case c;
  // The tiny mount turned 180 deg about a forward-looking camera's axis: rotate it to
  // look forward first (20 deg down), then about its own z.
  const Eigen::Matrix3d forward = rotation_from_rpy(-110 * M_PI / 180, 0, -90 * M_PI / 180);
  const Eigen::Matrix3d upside_down = forward * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  c.edit_calibration(kTinyMount, "quaternion: " + quaternion_text(upside_down));
  expect_refused(c, kCalib + ": key 'T_body_left': the left camera is mounted so that its image "
                             "is rolled 180 deg (the image's down points up; optical axis 20 deg "
                             "below the horizon); rpy_deg rotates the camera's axes (x right, y "
                             "down, z forward) into the body's (x forward, y left, z up): a forward "
                             "camera pitched down theta is rpy_deg: [-(90 + theta), 0, -90], "
                             "quaternion [qx, qy, qz, qw] scalar last (docs/conventions.md)");
}

// Issue 37 item 5: a calibration that tilts the fitted ground 124 deg ran to exit 0 with a
// warning. The guard stops it before the first frame; `check` measures the tilt it would
// have given and lists the guard's line as a problem.
TEST(OwnRover, MountThatTiltsTheGround124Degrees) {
  Case c;
  const Eigen::Matrix3d tilted =
      Eigen::AngleAxisd(124 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() * tiny_mount();
  c.edit_calibration(kTinyMount, "quaternion: " + quaternion_text(tilted));
  expect_refused(c, kCalib + ": key 'T_body_left': the left camera is mounted so that its optical "
                             "axis points 34 deg above the horizon and no pixel looks below it; "
                             "the quaternion looks written scalar first ([qw, qx, qy, qz]): hazmap "
                             "reads [qx, qy, qz, qw]; move the first number to the end");
  const Sequence seq = load_sequence(c.dir() / "seq");
  PreflightOptions o;
  o.max_frames = 1;
  const PreflightReport r = preflight_check(load_config(c.dir() / "config.yaml"), seq, o);
  ASSERT_EQ(r.frames.size(), 1u);
  ASSERT_TRUE(r.frames[0].ground.found) << format_report(r);
  EXPECT_NEAR(r.frames[0].tilt_w_deg, 124.0, 0.5);
}

TEST(OwnRover, PoseQuaternionWrittenScalarFirst) {
  Case c;
  std::string poses = testing::read_text(c.dir() / "seq/poses.txt");
  poses = replaced(poses, "000000 0 0 0 0 0 0 0 1", "000000 0 0 0 0 1 0 0 0");
  write_text(c.dir() / "seq/poses.txt", poses);
  expect_refused(c, "{dir}/seq/poses.txt: frame '000000': the body is tilted 180 deg from level, so "
                    "the left camera is wrong way round in W: its optical axis points 90 deg above "
                    "the horizon and no pixel looks below it; the quaternion looks written scalar "
                    "first (qw qx qy qz): poses.txt wants qx qy qz qw");
}

TEST(OwnRover, BodyPoseAbsentIsSaidOnceAndRuns) {
  Case c;
  c.edit_calibration("T_body_left: {translation: [0, 0.025, 0.625], " + std::string(kTinyMount) + "}\n", "");
  const CommandResult r = c.run("run");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // Said first and once; the first frame's ground then reads as upside down (179.8 deg).
  const std::string said = c.fill(kCalib + ": T_body_left is absent: the identity is used (the left "
                                           "camera at the body origin, looking up z_B), which sees no "
                                           "ground; give the camera's pose on the rover "
                                           "(docs/conventions.md)\n");
  EXPECT_EQ(r.output.rfind(said, 0), 0u) << r.output;
  EXPECT_EQ(r.output.find(said, 1), std::string::npos) << r.output;
}

TEST(OwnRover, PrincipalPointFarFromTheCentreIsAWarning) {
  Case c;
  c.set_calibration(replaced(replaced(c.calibration(), "50, 0, 31.5, 0, 50, 23.5", "50, 0, 60, 0, 50, 23.5"),
                             "50, 0, 31.5, 0, 50, 23.5", "50, 0, 60, 0, 50, 23.5"));
  const CommandResult r = c.run("run");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, c.fill(kCalib + ": key 'left.K': principal point (60, 23.5) px is far from "
                                      "the centre of the 64 x 48 px image: K written for another "
                                      "image size, or cx and cy swapped?\n" +
                             kCalib + ": key 'right.K': principal point (60, 23.5) px is far from "
                                      "the centre of the 64 x 48 px image: K written for another "
                                      "image size, or cx and cy swapped?\n"));
}

// A run whose frames give no point ends non-zero with the drop counts and the setting.
TEST(OwnRover, NoPointEndsNonZeroNamingTheSetting) {
  struct NoPoints {
    std::string set, message;
  };
  const NoPoints cases[] = {
      {"stereo.z_max=0.3",
       "no frame gave a point (3 frames, 9216 pixels): no disparity 25.5 %, beyond stereo.z_max "
       "74.5 %, nearer than stereo.z_min 0.0 %, unsupported 0.0 %, below the ground 0.0 %, "
       "occluded 0.0 %; most likely wrong: stereo.z_max, or T if it is not in metres"},
      {"stereo.z_min=2",
       "no frame gave a point (3 frames, 9216 pixels): no disparity 25.5 %, beyond stereo.z_max "
       "0.0 %, nearer than stereo.z_min 74.5 %, unsupported 0.0 %, below the ground 0.0 %, "
       "occluded 0.0 %; most likely wrong: stereo.z_min"},
  };
  for (const NoPoints& n : cases) {
    SCOPED_TRACE(n.set);
    Case c;
    const CommandResult r = c.run("run", "--set " + n.set);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "hazmap: error: " + n.message + "\n");
    // The frames are written (all unknown) and the summary says why: no points.
    EXPECT_NE(testing::read_text(c.dir() / "out/summary.json").find("\"points_total\": 0"),
              std::string::npos);
  }
}

// --set: errors are --set errors, with did-you-mean for keys and list indices; both
// spellings of a list element work.
TEST(OwnRover, SetMistakes) {
  struct SetCase {
    std::string set, message;
  };
  const SetCase cases[] = {
      {"map.layer.0.size=256",
       "--set map.layer.0.size=256: unknown key 'map.layer'; did you mean 'map.layers'?"},
      {"stereo.z_maxx=3", "--set stereo.z_maxx=3: unknown key 'stereo.z_maxx'; did you mean 'stereo.z_max'?"},
      {"stero.z_max=3", "--set stero.z_max=3: unknown key 'stero'; did you mean 'stereo'?"},
      {"map.layers.2.size=64",
       "--set map.layers.2.size=64: 'map.layers.2' is not an element of a list of 1 (indices 0 to 0)"},
      {"map.layers[2].size=64",
       "--set map.layers[2].size=64: 'map.layers.2' is not an element of a list of 1 (indices 0 to 0)"},
      {"map.layers.0.sise=64",
       "--set map.layers.0.sise=64: unknown key 'map.layers.0.sise'; did you mean 'map.layers.0.size'?"},
  };
  Case c;
  const auto before = snapshot(c.dir() / "out");
  for (const SetCase& s : cases) {
    SCOPED_TRACE(s.set);
    const CommandResult r = c.run("run", "--set " + s.set);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "hazmap: error: " + s.message + "\n");
    EXPECT_EQ(snapshot(c.dir() / "out"), before) << "OUT changed";
  }
  // The README's spelling is the dotted one's twin.
  const CommandResult ok = c.run("run", "--set map.layers[0].size=32");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(testing::read_text(c.dir() / "out/summary.json").find("\"size\": 32"), std::string::npos);
}

TEST(OwnRover, ConfigFileTypoSuggestsTheKey) {
  Case c;
  write_text(c.dir() / "config.yaml", replaced(kConfig, "z_max: 10", "z_mx: 10"));
  const auto before = snapshot(c.dir() / "out");
  const CommandResult r = c.run("run");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output, c.fill("hazmap: error: {dir}/config.yaml:1: unknown key 'stereo.z_mx'; did "
                             "you mean 'stereo.z_max'?\n"));
  EXPECT_EQ(snapshot(c.dir() / "out"), before) << "OUT changed";
}

// Options: one prefix, the command's own help named, exit 2; --quiet everywhere; stereo
// takes an EuRoC folder's poses options.
TEST(OwnRover, OptionMistakes) {
  Case c;
  const auto before = snapshot(c.dir() / "out");
  CommandResult r = c.run("run", "--bogus 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "hazmap: error: unknown option --bogus (see hazmap run --help)\n");
  r = c.run("stereo", "--poses x.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, c.fill("hazmap: error: --poses applies to ASL/EuRoC folders; {dir}/seq is "
                             "not one (no mav0/cam0 and mav0/cam1) (see hazmap stereo --help)\n"));
  r = testing::run_command(std::string(HAZMAP_CLI) + " frobnicate 2>&1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "hazmap: error: unknown command 'frobnicate' (see hazmap --help)\n");
  EXPECT_EQ(snapshot(c.dir() / "out"), before) << "OUT changed";
  // view --quiet: the page, and not a word.
  ASSERT_EQ(c.run("run").exit_code, 0);
  r = testing::run_command(std::string(HAZMAP_CLI) + " view --quiet " + (c.dir() / "out").string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output, "");
  EXPECT_TRUE(fs::is_regular_file(c.dir() / "out/view.html"));
}

// Every option a command accepts is in the top-level help (option errors send users there).
TEST(OwnRover, TopLevelHelpListsEveryOption) {
  const std::string help = testing::run_command(std::string(HAZMAP_CLI) + " --help").output;
  for (const char* command : {"run", "check", "stereo", "simulate", "evaluate", "calibrate",
                              "import-euroc", "ground-truth", "view", "bench"}) {
    SCOPED_TRACE(command);
    const std::string usage =
        testing::run_command(std::string(HAZMAP_CLI) + " " + command + " --help").output;
    // Each "--name" in the command's help (option lines and usage) must be in the top level.
    for (std::size_t at = 0; (at = usage.find("--", at)) != std::string::npos;) {
      std::size_t end = at + 2;
      while (end < usage.size() && (std::isalnum(static_cast<unsigned char>(usage[end])) || usage[end] == '-'))
        ++end;
      const std::string option = usage.substr(at, end - at);
      at = end;
      if (option.size() <= 2 || option == "--help") continue;
      EXPECT_NE(help.find(option), std::string::npos) << option;
    }
  }
}

// `hazmap check` tells the truth when the configuration does not fit the data.
TEST(OwnRoverCheck, FullResolutionSearchOnSmallImagesIsAProblem) {
  const Sequence seq = load_sequence(testing::source_dir() / "data/sample");
  PreflightOptions o;
  o.max_frames = 1;
  const PreflightReport r =
      preflight_check(load_config(testing::source_dir() / "config/cadre_full_res.yaml"), seq, o);
  EXPECT_EQ(r.blanked_share, 0.0);  // stereo.match_left_border: no band is blank
  bool found = false;
  for (const std::string& p : r.problems)
    found = found || p.rfind("the disparity search [0, 320) px spans 50 % of the 640 px wide "
                             "image (> 30 %): every pixel is searched that far, at that cost, "
                             "and far nearer than the ground: lower stereo.num_disparities (the "
                             "config may be for larger images, e.g. full-resolution ones)", 0) == 0;
  EXPECT_TRUE(found) << format_report(r);
  // OpenCV's blank band: 320 of 640 columns without disparity.
  const PreflightReport blank = preflight_check(
      load_config(testing::source_dir() / "config/cadre_full_res.yaml",
                  {"stereo.match_left_border=false"}),
      seq, o);
  EXPECT_NEAR(blank.blanked_share, 0.5, 0.01);
  found = false;
  for (const std::string& p : blank.problems)
    found = found || p.rfind("the disparity search [0, 320) px leaves the leftmost 320 px, 50 % of "
                             "the 640 px wide image, without disparity (> 30 %): lower "
                             "stereo.num_disparities (the config may be for larger images, e.g. "
                             "full-resolution ones)", 0) == 0;
  EXPECT_TRUE(found) << format_report(blank);
  // The sample's own config: a quarter of the width, as designed, and OK.
  const PreflightReport ok =
      preflight_check(load_config(testing::source_dir() / "config/default.yaml"), seq, o);
  EXPECT_EQ(ok.blanked_share, 0.0);
  EXPECT_TRUE(ok.problems.empty()) << format_report(ok);
}

TEST(OwnRoverCheck, RoverConfigOnEurocNamesTheBodyFrame) {
  const fs::path dir = testing::source_dir() / "../shared/data/euroc_v1_01_micro";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "no shared EuRoC data";
  const CommandResult r = testing::run_command(
      std::string(HAZMAP_CLI) + " check --count 2 --config " +
      (testing::source_dir() / "config/default.yaml").string() + " --sequence " + dir.string() +
      " --poses " + (dir / "poses_leftcam_gt.csv").string() +
      " --pose-frame left_camera --set map.layers.0.size=128 2>&1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.find("verdict: OK"), std::string::npos) << r.output;
  for (const char* line :
       {"  - the body origin is 0.9", " m above the ground fitted to the points (more than 0.10 m), "
        "but the config takes z_B = 0 as the ground under the wheels (stereo.max_below_ground)",
        "  - the ground fitted to the points is tilted 11", "deg from the body's x-y plane (more "
        "than hazard.max_slope_deg 20.0)", "  - only 0.0", "% of the points land in layer 0: its window is 1.28 m"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
}

// The guard's rpy rule, against an independent construction of the camera's axes.
TEST(OwnRover, ForwardCameraRpyPutsTheAxesWhereTheyBelong) {
  for (double pitch : {0.0, 20.0, 30.0, 45.0}) {
    const Eigen::Vector3d rpy = forward_camera_rpy_deg(pitch);
    const Eigen::Matrix3d R = rotation_from_rpy(rpy.x() * M_PI / 180, rpy.y() * M_PI / 180, rpy.z() * M_PI / 180);
    const double p = pitch * M_PI / 180;
    // Optical axis forward and down by the pitch; image right = -y_B; image down below the axis.
    EXPECT_TRUE(R.col(2).isApprox(Eigen::Vector3d(std::cos(p), 0, -std::sin(p)), 1e-12)) << pitch;
    EXPECT_TRUE(R.col(0).isApprox(Eigen::Vector3d(0, -1, 0), 1e-12)) << pitch;
    EXPECT_TRUE(R.col(1).isApprox(Eigen::Vector3d(-std::sin(p), 0, -std::cos(p)), 1e-12)) << pitch;
  }
}

}  // namespace
}  // namespace hazmap
