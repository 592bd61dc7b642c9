// Bad-input suite (issue 24): each case damages one input of a valid tiny sequence in a
// temporary folder (calibration, poses, images, config, command line) and runs the real
// `hazmap` binary on it. Every case must end with a non-zero exit, exactly one line on
// stderr naming the culprit (file, line or key), and a pre-existing OUT folder exactly
// as it was (no file added, removed or changed, run.log and summary.json included), even
// with --overwrite: the earlier output is removed only after every input has passed.
// Sequence cases run through both `hazmap run` and `hazmap stereo`.

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace hazmap {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::write_text;
using testing::replaced;
using testing::snapshot;

const char* const kConfig = testing::kTinyConfig;

const char* const kCalibration =
    "image_width: 64\nimage_height: 48\nrectified: true\n"
    "left:  {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\n"
    "right: {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\n"
    "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-0.05, 0, 0]\n"
    "T_body_left: {translation: [0, 0.025, 0.15], rpy_deg: [-90, 0, -90]}\n";

// An unrectified rig: distortion, R and T are read and used.
const char* const kRawCalibration =
    "image_width: 64\nimage_height: 48\n"
    "left:  {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0.01, 0, 0, 0, 0]}\n"
    "right: {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0.01, 0, 0, 0, 0]}\n"
    "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-0.05, 0, 0]\n"
    "T_body_left: {translation: [0, 0.025, 0.15], rpy_deg: [-90, 0, -90]}\n";

// An OpenCV FileStorage calibration of the same rig with a NaN among the left distortion.
const char* const kOpenCvNanD1 =
    "%YAML:1.0\n---\nimage_width: 64\nimage_height: 48\n"
    "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
    "D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0.01, .Nan, 0., 0., 0. ]\n"
    "M2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
    "D2: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0.01, 0., 0., 0., 0. ]\n"
    "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
    "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.05, 0., 0. ]\n";

/// One bad input: `damage` edits the case folder (SEQ = dir/seq, config = dir/config.yaml),
/// `extra` is appended to the command line, `culprit` must appear in the one line.
struct Case {
  std::string name;
  std::function<void(const fs::path& dir)> damage;
  std::string culprit;  ///< with "{dir}" standing for the case folder
  std::string extra = "";
  bool stereo_too = true;  ///< also run `hazmap stereo` on it
};

/// A damage that rewrites calibration.yaml from kCalibration with one replacement.
std::function<void(const fs::path&)> calibration(const std::string& from, const std::string& to,
                                                 const char* base = kCalibration) {
  return [=](const fs::path& dir) { write_text(dir / "seq/calibration.yaml", replaced(base, from, to)); };
}
std::function<void(const fs::path&)> calibration_text(const std::string& text) {
  return [=](const fs::path& dir) { write_text(dir / "seq/calibration.yaml", text); };
}
std::function<void(const fs::path&)> poses(const std::string& text) {
  return [=](const fs::path& dir) { write_text(dir / "seq/poses.txt", text); };
}
std::function<void(const fs::path&)> config(const std::string& from, const std::string& to) {
  return [=](const fs::path& dir) { write_text(dir / "config.yaml", replaced(kConfig, from, to)); };
}
std::function<void(const fs::path&)> config_text(const std::string& text) {
  return [=](const fs::path& dir) { write_text(dir / "config.yaml", text); };
}
std::function<void(const fs::path&)> nothing() { return [](const fs::path&) {}; }

std::string png_bytes(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  cv::imencode(".png", image, bytes);
  return std::string(bytes.begin(), bytes.end());
}
cv::Mat texture(int rows, int cols, int type) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(7);
  rng.fill(m, cv::RNG::UNIFORM, 0, type == CV_16UC1 ? 65535 : 255);
  return m;
}
/// Replaces one image of the sequence with `bytes`.
std::function<void(const fs::path&)> image(const std::string& which, std::function<std::string(const std::string&)> bytes) {
  return [=](const fs::path& dir) {
    const fs::path p = dir / "seq" / which;
    write_text(p, bytes(testing::read_text(p)));
  };
}

std::string fill(std::string culprit, const fs::path& dir) {
  const auto at = culprit.find("{dir}");
  if (at != std::string::npos) culprit.replace(at, 5, dir.string());
  return culprit;
}

class BadInputs {
 public:
  BadInputs() {
    testing::write_tiny_sequence(base_ / "seq", 3);
    write_text(base_ / "config.yaml", kConfig);
  }

  /// Runs the case through `command` (run or stereo).
  void check(const Case& c, const std::string& command) {
    SCOPED_TRACE(c.name + " (" + command + ")");
    const fs::path dir = temp_ / ("case" + std::to_string(++count_));
    fs::copy(base_, dir, fs::copy_options::recursive);
    c.damage(dir);
    // A previous run's OUT, which a failed run must leave exactly as it is.
    testing::write_previous_out(dir / "out");
    write_text(dir / "out/stereo_summary.json", "{}\n");
    const auto before = snapshot(dir / "out");
    const CommandResult r = testing::run_hazmap(
        command + " --config " + (dir / "config.yaml").string() + " --sequence " +
        (dir / "seq").string() + " --out " + (dir / "out").string() + " --quiet --overwrite " +
        fill(c.extra, dir));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_GT(r.exit_code, 0) << "killed by a signal or a sanitizer: " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(fill(c.culprit, dir)), std::string::npos)
        << "expected '" << fill(c.culprit, dir) << "' in: " << r.output;
    EXPECT_EQ(snapshot(dir / "out"), before) << "OUT changed";
    fs::remove_all(dir);
    ++checked_;
  }

  void run_all(const std::vector<Case>& cases) {
    for (const Case& c : cases) {
      check(c, "run");
      if (c.stereo_too) check(c, "stereo");
    }
  }
  int checked() const { return checked_; }

 private:
  testing::TempDir temp_;
  fs::path base_ = temp_ / "base";
  int count_ = 0, checked_ = 0;
};

TEST(BadInput, Calibration) {
  const std::string file = "{dir}/seq/calibration.yaml";
  const std::vector<Case> cases = {
      {"baseline 1e300", calibration("T: [-0.05", "T: [-1e300"), file + ": key 'T': baseline"},
      {"baseline 200 m", calibration("T: [-0.05", "T: [-200"), file + ": key 'T': baseline"},
      {"focal 1e300", calibration("K: [50, 0, 31.5, 0, 50", "K: [1e300, 0, 31.5, 0, 50"),
       file + ": key 'left.K': fx"},
      {"fy 1e9", calibration("0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\nright",
                             "0, 1e9, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\nright"),
       file + ": key 'left.K': fy"},
      {"cx 3e38", calibration("50, 0, 31.5", "50, 0, 3e38"), file + ": key 'left.K': principal"},
      {"cy -1e9", calibration("0, 50, 23.5, 0, 0, 1], D: [0, 0, 0, 0, 0]}\nright",
                              "0, 50, -1e9, 0, 0, 1], D: [0, 0, 0, 0, 0]}\nright"),
       file + ": key 'left.K': principal"},
      {"skew 1e8", calibration("K: [50, 0, 31.5", "K: [50, 1e8, 31.5"), file + ": key 'left.K': skew"},
      {"right K differs (rectified)",
       calibration("right: {K: [50, 0, 31.5", "right: {K: [51, 0, 31.5"),
       file + ": key 'right.K': must equal left.K"},
      {"NaN distortion", calibration("D: [0.01", "D: [.nan", kRawCalibration),
       file + ":3: key 'left.D'"},
      {"infinite K", calibration("K: [50, 0, 31.5", "K: [.inf, 0, 31.5"), file + ":4: key 'left.K'"},
      {"zero width", calibration("image_width: 64", "image_width: 0"), file + ": key 'image_width'"},
      {"negative height", calibration("image_height: 48", "image_height: -48"),
       file + ": key 'image_height'"},
      {"width beyond int", calibration("image_width: 64", "image_width: 1e12"), "image_width"},
      {"width not a number", calibration("image_width: 64", "image_width: wide"), "image_width"},
      {"K missing", calibration("left:  {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], ", "left:  {"),
       "left.K"},
      {"K of 8 numbers", calibration("K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]", "K: [50, 0, 31.5, 0, 50, 23.5, 0, 0]"),
       "left.K"},
      {"D of 3 numbers", calibration("D: [0.01, 0, 0, 0, 0]", "D: [0.01, 0, 0]", kRawCalibration),
       "left.D"},
      {"R not a rotation", calibration("R: [1, 0, 0", "R: [2, 0, 0", kRawCalibration), "key 'R'"},
      {"R of NaN", calibration("R: [1, 0, 0", "R: [.nan, 0, 0", kRawCalibration), "key 'R'"},
      {"zero baseline", calibration("T: [-0.05", "T: [0"), "key 'T'"},
      {"positive baseline (rectified)", calibration("T: [-0.05", "T: [0.05"), "key 'T'"},
      {"positive baseline (raw)", calibration("T: [-0.05", "T: [0.05", kRawCalibration),
       file + ": key 'T'"},
      {"distortion on rectified", calibration("D: [0, 0", "D: [0.1, 0"), "key 'left.D'"},
      {"duplicate key", calibration("R: [1", "T: [-0.05, 0, 0]\nR: [1"), file + ":"},
      {"unknown key", calibration("R: [1", "focus: 3\nR: [1"), "unknown key 'focus'"},
      {"invalid YAML", calibration("R: [1, 0, 0,", "R: [1, 0, 0,, ]]"), file + ":"},
      {"empty file", calibration_text(""), file},
      {"binary junk", calibration_text(std::string("\x89PNG\r\n\x1a\n\0\0", 10)), file},
      {"top level a list", calibration_text("- 1\n- 2\n"), file},
      {"missing file", [](const fs::path& d) { fs::remove(d / "seq/calibration.yaml"); }, file},
      {"a folder", [](const fs::path& d) {
         fs::remove(d / "seq/calibration.yaml");
         fs::create_directories(d / "seq/calibration.yaml");
       }, file},
      {"non-unit quaternion",
       calibration("rpy_deg: [-90, 0, -90]", "quaternion: [0, 0, 0, 2]"), "quaternion"},
      {"rpy and quaternion", calibration("rpy_deg: [-90, 0, -90]", "rpy_deg: [0, 0, 0], quaternion: [0, 0, 0, 1]"),
       "quaternion"},
      {"camera 1e300 m off the body",
       calibration("translation: [0, 0.025", "translation: [1e300, 0.025"), "T_body_left"},
      {"rectified not a bool", calibration("rectified: true", "rectified: maybe"), "rectified"},
      {"calibration size differs from the images", calibration("image_width: 64", "image_width: 128"),
       "{dir}/seq/left/000000.png: image is 64x48, the calibration says 128x48"},
      {"OpenCV layout, not a map", calibration_text("%YAML:1.0\n-\n"), file},
      {"OpenCV layout without M1", calibration_text("%YAML:1.0\n---\nimage_width: 64\n"),
       file + ": key 'M1'"},
      // Issue 37: named as the file spells the key (D1), not as the calibration's left.D.
      {"OpenCV layout, NaN in D1", calibration_text(kOpenCvNanD1),
       "hazmap: error: " + file + ": key 'D1': holds a value that is not a finite number\n"},
  };
  BadInputs b;
  b.run_all(cases);
  EXPECT_EQ(b.checked(), 2 * static_cast<int>(cases.size()));
}

TEST(BadInput, Poses) {
  const std::string file = "{dir}/seq/poses.txt";
  const std::string ok = "000000 0 0 0 0 0 0 0 1\n000001 1 0.04 0 0 0 0 0 1\n";
  const std::vector<Case> cases = {
      {"8 fields", poses(ok + "000002 2 0.08 0 0 0 0 1\n"), file + ":3: expected 9 fields"},
      {"10 fields", poses(ok + "000002 2 0.08 0 0 0 0 0 1 1\n"), file + ":3: expected 9 fields"},
      {"not a number", poses(ok + "000002 2 x 0 0 0 0 0 1\n"), file + ":3: field 3"},
      {"x = 1e300", poses(ok + "000002 2 1e300 0 0 0 0 0 1\n"), file + ":3: frame '000002': position x"},
      {"z = -1e8", poses(ok + "000002 2 0 0 -1e8 0 0 0 1\n"), file + ":3: frame '000002': position z"},
      {"nan", poses(ok + "000002 2 nan 0 0 0 0 0 1\n"), file + ":3: field 3"},
      {"inf", poses(ok + "000002 2 0 inf 0 0 0 0 1\n"), file + ":3: field 4"},
      {"1e400 overflows", poses(ok + "000002 2 0 1e400 0 0 0 0 1\n"), file + ":3: field 4"},
      {"non-unit quaternion", poses(ok + "000002 2 0 0 0 0 0 0 2\n"), file + ":3: quaternion"},
      {"zero quaternion", poses(ok + "000002 2 0 0 0 0 0 0 0\n"), file + ":3: quaternion"},
      {"second pose", poses(ok + "000001 2 0.08 0 0 0 0 0 1\n000002 2 0 0 0 0 0 0 1\n"),
       file + ":3: second pose for frame '000001'"},
      {"frame without pose", poses(ok), file + ": no pose for frame '000002'"},
      {"negative noise", poses(ok + "000002 2 0 0 0 0 0 0 1 -0.1 0 0 0\n"), file + ":3: pose noise"},
      {"empty", poses(""), file + ": no pose for frame '000000'"},
      {"only comments", poses("# nothing\n"), file + ": no pose for frame '000000'"},
      {"binary junk", poses(std::string("\x01\x02\x03 \xff\n", 6)), file + ":1:"},
      {"missing", [](const fs::path& d) { fs::remove(d / "seq/poses.txt"); }, file},
      {"a folder", [](const fs::path& d) {
         fs::remove(d / "seq/poses.txt");
         fs::create_directories(d / "seq/poses.txt");
       }, file},
  };
  BadInputs b;
  b.run_all(cases);
  EXPECT_EQ(b.checked(), 2 * static_cast<int>(cases.size()));
}

TEST(BadInput, Images) {
  // Frame 000002 is damaged: it must be found before frames 000000 and 000001 are written.
  const std::string left = "{dir}/seq/left/000002.png", right = "{dir}/seq/right/000002.png";
  auto half = [](const std::string& b) { return b.substr(0, b.size() / 2); };
  const std::vector<Case> cases = {
      {"truncated left", image("left/000002.png", half), left + ": PNG file cut short"},
      {"truncated right", image("right/000002.png", half), right + ": PNG file cut short"},
      {"cut inside the header", image("left/000002.png", [](const std::string& b) { return b.substr(0, 20); }),
       left + ": PNG file cut short inside its header"},
      {"last byte missing", image("left/000002.png", [](const std::string& b) { return b.substr(0, b.size() - 1); }),
       left + ": PNG file cut short"},
      {"empty", image("left/000002.png", [](const std::string&) { return std::string(); }),
       left + ": not a PNG file"},
      {"text", image("left/000002.png", [](const std::string&) { return std::string("hello\n"); }),
       left + ": not a PNG file"},
      {"JPEG named .png", image("left/000002.png", [](const std::string&) {
         std::vector<unsigned char> jpg;
         cv::imencode(".jpg", texture(48, 64, CV_8UC1), jpg);
         return std::string(jpg.begin(), jpg.end());
       }), left + ": not a PNG file"},
      {"zero width in IHDR", image("left/000002.png", [](std::string b) {
         b[16] = b[17] = b[18] = b[19] = 0;
         return b;
       }), left + ": damaged PNG header"},
      {"huge size in IHDR", image("left/000002.png", [](std::string b) {
         b[16] = 0x00, b[17] = 0x10, b[20] = 0x00, b[21] = 0x10;  // 1048576 x 1048576
         return b;
       }), left + ": PNG claims"},
      {"bad bit depth in IHDR", image("left/000002.png", [](std::string b) {
         b[24] = 3;
         return b;
       }), left + ": damaged PNG header"},
      {"1 x 1", image("left/000002.png", [](const std::string&) { return png_bytes(texture(1, 1, CV_8UC1)); }),
       left + ": image is 1x1, the calibration says 64x48"},
      {"mis-sized right", image("right/000002.png", [](const std::string&) { return png_bytes(texture(48, 32, CV_8UC1)); }),
       right + ": image is 32x48, the calibration says 64x48"},
      {"transposed", image("left/000002.png", [](const std::string&) { return png_bytes(texture(64, 48, CV_8UC1)); }),
       left + ": image is 48x64"},
      {"16-bit left, 8-bit right", image("left/000002.png", [](const std::string&) { return png_bytes(texture(48, 64, CV_16UC1)); }),
       right + ": 64x48 8-bit grey, but its left image"},
      {"colour right, grey left", image("right/000002.png", [](const std::string&) { return png_bytes(texture(48, 64, CV_8UC3)); }),
       right + ": 64x48 8-bit RGB, but its left image"},
      {"missing right", [](const fs::path& d) { fs::remove(d / "seq/right/000002.png"); }, right + ": missing"},
      {"missing left", [](const fs::path& d) { fs::remove(d / "seq/left/000002.png"); }, left + ": missing"},
      {"right is a folder", [](const fs::path& d) {
         fs::remove(d / "seq/right/000002.png");
         fs::create_directories(d / "seq/right/000002.png");
       }, right + ": missing"},
      {"no left folder", [](const fs::path& d) { fs::remove_all(d / "seq/left"); }, "{dir}/seq/left: image folder not found"},
      {"no images", [](const fs::path& d) {
         for (const char* side : {"left", "right"})
           for (const auto& e : fs::directory_iterator(d / "seq" / side)) fs::remove(e.path());
       }, "{dir}/seq/left: no PNG images"},
  };
  BadInputs b;
  b.run_all(cases);
  EXPECT_EQ(b.checked(), 2 * static_cast<int>(cases.size()));
}

TEST(BadInput, Config) {
  const std::string file = "{dir}/config.yaml";
  const std::vector<Case> cases = {
      {"num_disparities 1048576", config("num_disparities: 16", "num_disparities: 1048576"),
       "key 'stereo.num_disparities'"},
      {"num_disparities 80 > width 64", config("num_disparities: 16", "num_disparities: 80"),
       "key 'stereo.num_disparities'"},
      {"num_disparities 17", config("num_disparities: 16", "num_disparities: 17"),
       "key 'stereo.num_disparities'"},
      {"num_disparities beyond int", config("num_disparities: 16", "num_disparities: 1e12"),
       "stereo.num_disparities"},
      {"roi outside the image", config("z_max: 10", "z_max: 10, roi: [100, 0, 10, 10]"),
       "key 'stereo.roi'"},
      {"roi larger than the image", config("z_max: 10", "z_max: 10, roi: [0, 0, 1000, 1000]"),
       "key 'stereo.roi'"},
      {"roi negative", config("z_max: 10", "z_max: 10, roi: [-1, 0, 10, 10]"), "stereo.roi"},
      {"roi of 3 numbers", config("z_max: 10", "z_max: 10, roi: [0, 0, 10]"), "stereo.roi"},
      {"stride 0", config("z_max: 10", "z_max: 10, stride: 0"), "stereo.stride"},
      {"stride INT_MAX", config("z_max: 10", "z_max: 10, stride: 2147483647"), "stereo.stride"},
      {"block_size 4", config("block_size: 5", "block_size: 4"), "stereo.block_size"},
      {"matcher foo", config("z_max: 10", "z_max: 10, matcher: foo"), "matcher"},
      {"z_max below z_min", config("z_max: 10", "z_max: 0.01, z_min: 0.5"), "stereo.z_max"},
      {"rectify_alpha 2", config("z_max: 10", "z_max: 10, rectify_alpha: 2"), "stereo.rectify_alpha"},
      {"input_bits 7", config("z_max: 10", "z_max: 10, input_bits: 7"), "stereo.input_bits"},
      {"unknown stereo key", config("z_max: 10", "z_max: 10, zmax: 3"), "unknown key 'stereo.zmax'"},
      {"duplicate key", config("z_max: 10", "z_max: 10, z_max: 11"), "duplicate key"},
      {"invalid YAML", config_text("stereo: {num_disparities: 16\n"), file + ":"},
      {"a list, not a map", config_text("- 1\n"), file},
      {"missing", [](const fs::path& d) { fs::remove(d / "config.yaml"); }, file + ": cannot open"},
      {"a folder", [](const fs::path& d) {
         fs::remove(d / "config.yaml");
         fs::create_directories(d / "config.yaml");
       }, file + ": is a folder"},
      {"--set unknown key", nothing(), "stereo.nope", "--set stereo.nope=1"},
      {"--set without =", nothing(), "--set stereo.stride", "--set stereo.stride"},
      {"--set bad value", nothing(), "stereo.stride", "--set stereo.stride=[1"},
      {"layer size 46342", config("size: 16", "size: 46342"), "map.layers.0.size", "", false},
      {"layer size 50000", config("size: 16", "size: 50000"), "map.layers.0.size", "", false},
      {"layer size odd", config("size: 16", "size: 15"), "map.layers.0.size", "", false},
      {"layer beyond memory", config("size: 16", "size: 46340"),
       "key 'map.layers': layer 0: 46340^2 cells need about", "", false},
      {"resolution 1e-300", config("resolution: 0.01", "resolution: 1e-300"),
       "map.layers.0.resolution", "", false},
      {"resolution negative", config("resolution: 0.01", "resolution: -0.01"),
       "map.layers.0.resolution", "", false},
      {"kernel even", config("kernel: 3", "kernel: 4"), "map.layers.0.hazard.kernel", "", false},
      {"no layers", config_text("stereo: {num_disparities: 16, block_size: 5}\nmap: {layers: []}\n"),
       "map.layers", "", false},
      {"unknown rule", config("rule: kalman", "rule: magic"), "map.layers.0.rule", "", false},
      {"max_slope 90", config_text(std::string(kConfig) + "hazard: {max_slope_deg: 90}\n"),
       "hazard.max_slope_deg", "", false},
      {"wheelbase 1e9", config_text(std::string(kConfig) + "hazard: {wheelbase: 1e9}\n"),
       "hazard.wheelbase", "", false},
      {"every_n 0", config_text(std::string(kConfig) + "output: {every_n: 0}\n"), "output.every_n",
       "", false},
      {"fused_extent 1e300", config_text(std::string(kConfig) + "hazard: {fused_extent: 1e300}\n"),
       "hazard.fused_extent", "", false},
  };
  BadInputs b;
  b.run_all(cases);
  int expected = 0;
  for (const Case& c : cases) expected += c.stereo_too ? 2 : 1;
  EXPECT_EQ(b.checked(), expected);
}

TEST(BadInput, CommandLine) {
  const std::vector<Case> cases = {
      {"--frames selecting nothing", nothing(), "--frames 5:2", "--frames 5:2"},
      {"--frames not numbers", nothing(), "--frames a:b", "--frames a:b"},
      {"--frames without colon", nothing(), "--frames 3", "--frames 3"},
      {"unknown option", nothing(), "unknown option --bogus", "--bogus 1"},
      {"stray argument", nothing(), "unexpected argument 'stray'", "stray"},
      {"sequence is missing", [](const fs::path& d) { fs::remove_all(d / "seq"); },
       "{dir}/seq: sequence folder not found"},
  };
  BadInputs b;
  b.run_all(cases);
  EXPECT_EQ(b.checked(), 2 * static_cast<int>(cases.size()));
}

// A frame damaged after the up-front check (here: its pixels, which the check does not
// decode) stops the run at that frame with one line naming it; the frames before it are
// complete. The earlier run's summary.json went with --overwrite, and the failed run
// writes none: no summary describes frames it did not make.
TEST(BadInput, FrameDamagedInsideStopsTheRunAtThatFrame) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir / "seq", 3);
  write_text(dir / "config.yaml", kConfig);
  fs::create_directories(dir / "out");
  write_text(dir / "out/summary.json", "{\"previous\": 1}\n");
  // Flip a byte inside the pixel data: signature, IHDR and IEND stay intact.
  const fs::path bad = dir / "seq/left/000002.png";
  std::string bytes = testing::read_text(bad);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5a);
  write_text(bad, bytes);
  const CommandResult r = testing::run_command(
      std::string(HAZMAP_CLI) + " run --quiet --config " + (dir / "config.yaml").string() +
      " --sequence " + (dir / "seq").string() + " --out " + (dir / "out").string() +
      " --overwrite 2>&1 1>/dev/null");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;  // no libpng line
  EXPECT_NE(r.output.find(bad.string() + ": damaged PNG file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(frame 000002, 3 of 3, stopped the run;"), std::string::npos) << r.output;
  for (const char* frame : {"000000", "000001"})
    EXPECT_TRUE(fs::is_regular_file(dir / "out/frames" / frame / "fused_hazard.jdem")) << frame;
  EXPECT_FALSE(fs::exists(dir / "out/frames/000002"));
  EXPECT_FALSE(fs::exists(dir / "out/summary.json"));
}

}  // namespace
}  // namespace hazmap
