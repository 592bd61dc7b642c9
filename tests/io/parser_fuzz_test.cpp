// A short, seeded fuzz pass over the three input parsers a user's files reach: JDEM,
// calibration YAML (ours and OpenCV's FileStorage layout) and poses.txt. Valid files are
// mutated (bytes flipped, numbers replaced by extreme values, lines dropped, repeated or
// cut) and fed to the real parsers. Every case must either parse or throw hazmap::Error
// with one line naming the file; any other exception (bad_alloc, YAML::Exception,
// cv::Exception) fails the test, and a crash or a sanitizer report fails the whole run.
// The seed is fixed, so a failure reproduces; a time budget keeps a slow machine (the
// sanitizer build) from running long: it stops early and says how many cases ran.

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "eval/oracle_run.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/eval/grid_checks.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/sequence.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr unsigned kSeed = 20240624;
constexpr int kCasesPerParser = 400;
constexpr double kBudgetSeconds = 60.0;  // per parser, far above the ~1 s a Release build needs
// `hazmap evaluate` reads and scores a whole run per case: fewer cases, the same budget.
constexpr int kEvaluateCases = 150;

const char* const kTokens[] = {
    "1e300", "-1e300", "1e-300", "nan", "inf", "-inf", "0", "-0", "-1", "2147483647",
    "2147483648", "-2147483649", "9223372036854775808", "1e8", "100000000", "46341", "0x10",
    "3e38", "", " ", "\t", ":", "[", "]", "{", "}", ",", "#", "&a", "*a", "!!binary", "'", "\"",
    "\n", "\r\n", "- ", "? ", "data:", "rows: 3", "JDEM 1", "%YAML:1.0", "\xff\xfe", "\x00"};

class Mutator {
 public:
  explicit Mutator(unsigned seed) : rng_(seed) {}

  std::string mutate(const std::string& valid) {
    std::string s = valid;
    const size_t edits = 1 + pick(3);
    for (size_t e = 0; e < edits; ++e) {
      switch (pick(7)) {
        case 0:  // flip one byte
          if (!s.empty()) s[pick(s.size())] = static_cast<char>(pick(256));
          break;
        case 1:  // replace a number with an extreme or odd token
          replace_number(s);
          break;
        case 2:  // insert a token anywhere
          s.insert(pick(s.size() + 1), token());
          break;
        case 3:  // drop a line
          drop_line(s);
          break;
        case 4:  // repeat a line
          repeat_line(s);
          break;
        case 5:  // cut the file short
          s.resize(pick(s.size() + 1));
          break;
        default:  // swap two bytes
          if (s.size() > 1) std::swap(s[pick(s.size())], s[pick(s.size())]);
      }
    }
    return s;
  }

 private:
  size_t pick(size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  std::string token() { return std::string(kTokens[pick(std::size(kTokens))]); }

  void replace_number(std::string& s) {
    std::vector<std::pair<size_t, size_t>> numbers;  // [begin, end) of digit runs
    for (size_t i = 0; i < s.size();) {
      if (std::isdigit(static_cast<unsigned char>(s[i]))) {
        size_t j = i;
        while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' ||
                                s[j] == 'e' || s[j] == '-'))
          ++j;
        numbers.emplace_back(i, j);
        i = j;
      } else {
        ++i;
      }
    }
    if (numbers.empty()) return;
    const auto [b, e] = numbers[pick(numbers.size())];
    s.replace(b, e - b, token());
  }

  std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    for (size_t i = 0; i <= s.size(); ++i)
      if (i == s.size() || s[i] == '\n') out.push_back(s.substr(start, i - start)), start = i + 1;
    return out;
  }
  static std::string join(const std::vector<std::string>& ls) {
    std::string out;
    for (size_t i = 0; i < ls.size(); ++i) out += (i ? "\n" : "") + ls[i];
    return out;
  }
  void drop_line(std::string& s) {
    auto ls = lines(s);
    if (ls.size() > 1) ls.erase(ls.begin() + static_cast<long>(pick(ls.size())));
    s = join(ls);
  }
  void repeat_line(std::string& s) {
    auto ls = lines(s);
    const size_t i = pick(ls.size());
    ls.insert(ls.begin() + static_cast<long>(pick(ls.size() + 1)), ls[i]);
    s = join(ls);
  }

  std::mt19937_64 rng_;
};

struct Tally {
  int cases = 0, accepted = 0, rejected = 0;
};

/// Runs `parse(text, source)` on mutations of `valid`; fails on anything but success or a
/// one-line hazmap::Error that names `source`.
template <class Parse>
Tally fuzz(const std::string& valid, const std::string& source, unsigned seed, Parse parse) {
  Mutator mutator(seed);
  Tally t;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kCasesPerParser; ++i) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
        kBudgetSeconds)
      break;
    const std::string text = mutator.mutate(valid);
    ++t.cases;
    try {
      parse(text, source);
      ++t.accepted;
    } catch (const Error& e) {
      ++t.rejected;
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << "case " << i << ": " << m;
      EXPECT_EQ(m.rfind(source, 0), 0u) << "case " << i << ": " << m;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "case " << i << ": raw " << typeid(e).name() << ": " << e.what()
                    << "\n--- input ---\n" << text;
    }
  }
  std::printf("%s: %d cases, %d accepted, %d rejected\n", source.c_str(), t.cases, t.accepted,
              t.rejected);
  return t;
}

const char* const kValidJdem =
    "JDEM 1\nquantity: height\nunits: m\nrows: 3\ncols: 4\nresolution: 0.04\n"
    "center_x: 1.2\ncenter_y: -0.4\nyaw: 0\nnodata: nan\nframe: 000012\ndata:\n"
    "0.1 0.2 nan 0.4\n-1 2 3e-3 4\n5 nan 7 8\n";

const char* const kValidCalibration =
    "image_width: 64\nimage_height: 48\n"
    "left:  {K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], D: [0.01, -0.02, 0, 0, 0]}\n"
    "right: {K: [51, 0, 30.5, 0, 51, 24.5, 0, 0, 1], D: [0.01, -0.02, 0, 0, 0]}\n"
    "R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nT: [-0.05, 0, 0]\n"
    "T_body_left:\n  translation: [0, 0.025, 0.15]\n  rpy_deg: [-90, 0, -90]\n";

const char* const kValidOpenCvCalibration =
    "%YAML:1.0\n---\nimage_width: 64\nimage_height: 48\n"
    "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
    "D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0.01, -0.02, 0., 0., 0. ]\n"
    "M2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
    "D2: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0.01, -0.02, 0., 0., 0. ]\n"
    "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
    "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.05, 0., 0. ]\n";

const char* const kValidPoses =
    "# name t x y z qx qy qz qw\n000000 0 0 0 0 0 0 0 1\n"
    "000001 0.1 0.04 0 0 0 0 0.0499792 0.9987503\n"
    "000002 0.2 0.08 0.01 0 0 0 0 1 0.01 0.01 0.001 0.002\n";

TEST(ParserFuzz, ValidSeedsParse) {
  // The mutations start from valid files: were these rejected, the pass would test nothing.
  EXPECT_NO_THROW(parse_jdem(kValidJdem, "seed.jdem"));
  EXPECT_NO_THROW(parse_poses(kValidPoses, "poses.txt"));
  testing::TempDir dir;
  std::ofstream(dir / "ours.yaml") << kValidCalibration;
  std::ofstream(dir / "opencv.yml") << kValidOpenCvCalibration;
  EXPECT_NO_THROW(load_stereo_calibration(dir / "ours.yaml"));
  EXPECT_NO_THROW(load_stereo_calibration(dir / "opencv.yml"));
}

TEST(ParserFuzz, JdemGivesAGridOrOneLineNamingTheFile) {
  const Tally t = fuzz(kValidJdem, "fuzz.jdem", kSeed,
                       [](const std::string& text, const std::string& source) {
                         const JdemGrid g = parse_jdem(text, source);
                         EXPECT_EQ(g.values.size(), static_cast<size_t>(g.rows) * g.cols);
                       });
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

TEST(ParserFuzz, PosesGivePosesOrOneLineNamingTheFile) {
  const Tally t = fuzz(kValidPoses, "poses.txt", kSeed + 1,
                       [](const std::string& text, const std::string& source) {
                         for (const auto& [name, pose] : parse_poses(text, source))
                           EXPECT_TRUE(pose.T_W_B.matrix().allFinite()) << name;
                       });
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

template <class Check>
Tally fuzz_calibration(const char* valid, const std::string& file, unsigned seed, Check check) {
  testing::TempDir dir;
  const std::filesystem::path path = dir / file;
  return fuzz(valid, path.string(), seed, [&](const std::string& text, const std::string&) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    check(load_stereo_calibration(path));
  });
}

void expect_sane(const StereoCalibration& c) {
  EXPECT_GT(c.image_width, 0);
  EXPECT_GT(c.image_height, 0);
  EXPECT_TRUE(c.left.K.allFinite() && c.right.K.allFinite() && c.T.allFinite());
}

TEST(ParserFuzz, CalibrationGivesACalibrationOrOneLineNamingTheFile) {
  const Tally t = fuzz_calibration(kValidCalibration, "calibration.yaml", kSeed + 2, expect_sane);
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

TEST(ParserFuzz, OpenCvCalibrationGivesACalibrationOrOneLineNamingTheFile) {
  const Tally t =
      fuzz_calibration(kValidOpenCvCalibration, "stereo_calib.yml", kSeed + 3, expect_sane);
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

const char* const kValidHazardJdem =
    "JDEM 1\nquantity: hazard\nunits: class\nrows: 3\ncols: 4\nresolution: 0.04\n"
    "center_x: 1.2\ncenter_y: -0.4\nyaw: 0\nnodata: nan\nframe: 000012\ndata:\n"
    "0 1 2 nan\n1 1 2 0\n2 nan 1 1\n";

// Issue 37: a hazard grid holding -inf reached an int conversion in the evaluation.
TEST(ParserFuzz, HazardGridGivesClassesOrOneLineNamingTheFile) {
  const Tally t = fuzz(kValidHazardJdem, "fuzz_hazard.jdem", kSeed + 4,
                       [](const std::string& text, const std::string& source) {
                         const JdemGrid g = parse_jdem(text, source);
                         eval::check_hazard_classes(g, source);
                         HazardClass c;
                         for (const float v : g.values) EXPECT_TRUE(eval::hazard_class_of(v, &c)) << v;
                       });
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

// `hazmap evaluate`'s inputs, one file of a small valid run mutated per case: the layer
// grids, the fused map, the ground truth and the poses. Each case scores (finite metrics)
// or throws one line naming a file, and a failed case writes nothing into OUT.
TEST(ParserFuzz, EvaluateGivesMetricsOrOneLineNamingAFile) {
  namespace fs = std::filesystem;
  testing::TempDir dir;
  const fs::path run = dir / "run", seq = dir / "seq", out = dir / "out";
  testing::TestWorld w;
  w.rows = w.cols = 60;
  w.rocks = {{1.0, 0.1, 0.08}};
  const std::vector<testing::OracleLayer> layers = {
      testing::build_oracle_layer(w, 0.04, 12, 1.0, 0.0, 0.03, true, 1e-4),
      testing::build_oracle_layer(w, 0.08, 6, 1.0, 0.0, 0.05, false, 1e-4)};
  testing::write_ground_truth(seq, w);
  testing::write_poses(seq / "poses.txt", {"000000"}, {{0.0, 0.0}});
  testing::write_oracle_run(run, testing::oracle_config(), {"000000"}, {layers});
  const fs::path frame = run / "frames" / "000000";
  const std::vector<fs::path> targets = {
      frame / "L0_hazard.jdem", frame / "L1_hazard.jdem", frame / "fused_hazard.jdem",
      frame / "L0_height.jdem", frame / "L0_slope_x.jdem", frame / "L1_variance.jdem",
      seq / "gt_hazard.jdem",   seq / "gt_height.jdem",    seq / "poses.txt"};
  std::vector<std::string> originals;
  for (const fs::path& p : targets) originals.push_back(testing::read_text(p));
  eval::EvaluationOptions options;
  options.run_dir = run;
  options.sequence_dir = seq;
  options.out_dir = out;
  options.error_map_frames = {"all"};
  ASSERT_NO_THROW(eval::evaluate_run(options));  // the valid run scores
  fs::remove_all(out);

  Mutator mutator(kSeed + 5);
  Tally t;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kEvaluateCases; ++i) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
        kBudgetSeconds)
      break;
    const size_t k = static_cast<size_t>(i) % targets.size();
    const std::string text = mutator.mutate(originals[k]);
    std::ofstream(targets[k], std::ios::binary | std::ios::trunc) << text;
    ++t.cases;
    try {
      const eval::RunEvaluation ev = eval::evaluate_run(options);
      ++t.accepted;
      EXPECT_EQ(ev.sums.size(), 1u);
      EXPECT_TRUE(fs::exists(out / "metrics.csv"));
    } catch (const Error& e) {
      ++t.rejected;
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << "case " << i << ": " << m;
      EXPECT_NE(m.find(dir.path().string()), std::string::npos) << "case " << i << ": " << m;
      EXPECT_FALSE(fs::exists(out)) << "case " << i << " wrote into OUT before failing: " << m;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "case " << i << " (" << targets[k] << "): raw " << typeid(e).name() << ": "
                    << e.what();
    }
    fs::remove_all(out);
    std::ofstream(targets[k], std::ios::binary | std::ios::trunc) << originals[k];
  }
  std::printf("evaluate: %d cases, %d accepted, %d rejected\n", t.cases, t.accepted, t.rejected);
  EXPECT_GT(t.accepted, 0);
  EXPECT_GT(t.rejected, 0);
}

}  // namespace
}  // namespace hazmap
