#include "hazmap/io/sequence.hpp"

#include <fstream>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

std::string load_error(const std::filesystem::path& dir) {
  try {
    load_sequence(dir);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Sequence, LoadsPairsPosesAndCalibrationInNameOrder) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir.path(), 3);
  const Sequence seq = load_sequence(dir.path());
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_EQ(seq.frames[0].name, "000000");
  EXPECT_EQ(seq.frames[2].name, "000002");
  EXPECT_NEAR(seq.frames[2].pose.T_W_B.translation().x(), 0.08, 1e-12);
  EXPECT_TRUE(seq.calibration.rectified);
  EXPECT_EQ(seq.calibration.image_width, 64);
}

TEST(Sequence, MissingRightImageIsNamed) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir.path(), 3);
  std::filesystem::remove(dir / "right/000001.png");
  EXPECT_EQ(load_error(dir.path()), (dir / "right/000001.png").string() + ": missing (right image of " +
                                        (dir / "left/000001.png").string() + ")");
}

TEST(Sequence, FrameWithoutPoseIsNamed) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir.path(), 2);
  std::ofstream(dir / "poses.txt") << "000000 0 0 0 0 0 0 0 1\n";
  EXPECT_EQ(load_error(dir.path()), (dir / "poses.txt").string() + ": no pose for frame '000001' (" +
                                        (dir / "left/000001.png").string() + ")");
}

TEST(Sequence, MalformedPoseLineIsNamed) {
  const std::string text = "# comment\n000000 0 0 0 0 0 0 0 1\n000001 1 0 0 0 0 0 1\n";
  try {
    parse_poses(text, "poses.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "poses.txt:3: expected 9 fields (name t x y z qx qy qz qw) or 13 (+ sx sy sz "
              "syaw), found 8");
  }
  EXPECT_THROW(parse_poses("a 0 0 0 0 0 0 0 2\n", "p"), Error);          // not unit
  EXPECT_THROW(parse_poses("a 0 0 0 0 0 0 0 1\na 1 0 0 0 0 0 0 1\n", "p"), Error);  // duplicate
  EXPECT_THROW(parse_poses("a 0 0 zero 0 0 0 0 1\n", "p"), Error);
}

TEST(Sequence, PoseQuaternionAndNoiseAreParsed) {
  const auto poses = parse_poses("f 2.5 1 2 3 0 0 0.7071067811865476 0.7071067811865476 0.01 0.02 0.03 0.04\n", "p");
  ASSERT_EQ(poses.size(), 1u);
  const FramePose& p = poses[0].second;
  EXPECT_DOUBLE_EQ(p.t_s, 2.5);
  EXPECT_TRUE(p.has_noise);
  EXPECT_DOUBLE_EQ(p.noise.syaw_rad, 0.04);
  // 90 degrees about z: body x points along world y.
  const Eigen::Vector3d x_W = p.T_W_B.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x_W.y(), 1.0, 1e-12);
  EXPECT_NEAR((p.T_W_B * Eigen::Vector3d::Zero() - Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-12);
}

TEST(Sequence, FrameRangesSelectLikePythonSlices) {
  std::vector<SequenceFrame> frames(5);
  for (int i = 0; i < 5; ++i) frames[i].name = std::to_string(i);
  EXPECT_EQ(select_frames(frames, "1:3").size(), 2u);
  EXPECT_EQ(select_frames(frames, "1:3").front().name, "1");
  EXPECT_EQ(select_frames(frames, ":2").size(), 2u);
  EXPECT_EQ(select_frames(frames, "-2:").front().name, "3");
  EXPECT_THROW(select_frames(frames, "3:1"), Error);
  EXPECT_THROW(select_frames(frames, "x:1"), Error);
}

// Issue 24: x = 1e300 went on to overflow the map's cell indices (a map centred at
// -9.2e16 m, exit 0); the pose file's line now says why it is refused.
TEST(Sequence, ImplausiblePositionIsNamedWithFileAndLine) {
  try {
    parse_poses("a 0 0 0 0 0 0 0 1\nb 1 1e300 0 0 0 0 0 1\n", "poses.txt");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "poses.txt:2: frame 'b': position x = 1e+300 m is implausible: |x|, |y|, |z| must "
              "be <= 1e7 m (10 000 km, beyond any traverse)");
  }
  EXPECT_THROW(parse_poses("a 0 0 -2e7 0 0 0 0 1\n", "p"), Error);
  EXPECT_THROW(parse_poses("a 0 0 0 1e8 0 0 0 1\n", "p"), Error);
  EXPECT_NO_THROW(parse_poses("a 0 1e7 -1e7 1e7 0 0 0 1\n", "p"));
}

// Issue 22: the fingerprint `hazmap evaluate` compares. It must tell two trajectories
// apart by any change that could move a map cell, and nothing else.
TEST(Sequence, PosesFingerprintChangesWithOnePoseOnly) {
  const std::string base =
      "000000 0 0 0 0 0 0 0 1\n000001 1 0.04 0 0 0 0 0 1\n000002 2 0.08 0.01 0 0 0 0.2 "
      "0.9797958971132712\n";
  const auto fp = [](const std::string& text) { return poses_fingerprint(parse_poses(text, "p")); };
  const std::uint64_t reference = fp(base);
  // One position moved by 1 mm, one heading turned, one frame renamed, noise added: each
  // is another sequence.
  EXPECT_NE(fp("000000 0 0 0 0 0 0 0 1\n000001 1 0.041 0 0 0 0 0 1\n000002 2 0.08 0.01 0 0 0 "
               "0.2 0.9797958971132712\n"),
            reference);
  EXPECT_NE(fp("000000 0 0 0 0 0 0 0 1\n000001 1 0.04 0 0 0 0 0.01 0.99995\n000002 2 0.08 0.01 "
               "0 0 0 0.2 0.9797958971132712\n"),
            reference);
  EXPECT_NE(fp("000000 0 0 0 0 0 0 0 1\n000009 1 0.04 0 0 0 0 0 1\n000002 2 0.08 0.01 0 0 0 "
               "0.2 0.9797958971132712\n"),
            reference);
  EXPECT_NE(fp("000000 0 0 0 0 0 0 0 1 0.01 0.01 0.01 0.01\n000001 1 0.04 0 0 0 0 0 1\n000002 "
               "2 0.08 0.01 0 0 0 0.2 0.9797958971132712\n"),
            reference);
  EXPECT_NE(fp("000000 0 0 0 0 0 0 0 1\n000001 1 0.04 0 0 0 0 0 1\n"), reference);  // one fewer
  // The same poses written otherwise: another line order, comments, other timestamps
  // (unused by the mapping), -q for q, and digits beyond a double's round trip.
  EXPECT_EQ(fp("# reordered\n000002 7 0.08 0.01 0 -0 -0 -0.2 -0.9797958971132712\n000000 0 "
               "0 0 0 0 0 0 1\n000001 1 0.0400000000000001 0 0 0 0 0 1\n"),
            reference);
  // Written as summary.json stores it, and read back.
  EXPECT_EQ(fingerprint_hex(0x00ab0000000000cdull), "00ab0000000000cd");
  EXPECT_EQ(parse_fingerprint_hex(fingerprint_hex(reference)), reference);
  EXPECT_FALSE(parse_fingerprint_hex("12345"));
  EXPECT_FALSE(parse_fingerprint_hex("zz00000000000000"));
}

TEST(Sequence, LoadedSequenceFingerprintsEveryRecordOfPosesTxt) {
  testing::TempDir dir;
  testing::write_tiny_sequence(dir.path(), 3);
  const Sequence seq = load_sequence(dir.path());
  ASSERT_TRUE(seq.poses_fingerprint.has_value());
  EXPECT_EQ(*seq.poses_fingerprint, read_poses_fingerprint(dir.path()));
  EXPECT_EQ(fingerprint_of(seq), poses_fingerprint(seq.frames));  // one pose per frame here
  // A pose without images is part of the sequence's record, and needs no images to read.
  std::ofstream(dir / "poses.txt", std::ios::app) << "000099 99 3.96 0 0 0 0 0 1\n";
  const Sequence more = load_sequence(dir.path());
  EXPECT_EQ(more.frames.size(), 3u);
  EXPECT_NE(*more.poses_fingerprint, *seq.poses_fingerprint);
  std::filesystem::remove_all(dir / "left");
  EXPECT_EQ(read_poses_fingerprint(dir.path()), *more.poses_fingerprint);
  // A Sequence assembled in code fingerprints its frames.
  Sequence built;
  built.frames = seq.frames;
  EXPECT_EQ(fingerprint_of(built), fingerprint_of(seq));
  EXPECT_THROW(read_poses_fingerprint(dir / "absent"), Error);
}

}  // namespace
}  // namespace hazmap
