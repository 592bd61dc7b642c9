// Seen-cell confusion tables and reasons for unknown (issue 34): against hand-made cases
// and a second, independent count.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"
#include "hazmap/eval/seen_confusion.hpp"

namespace hazmap::eval {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

/// A camera 1 m above W's origin looking straight down, 10 x 10 pixels, f = 10 px, so
/// pixel (u, v) sees the ground point ((u - 4.5) / 10, -(v - 4.5) / 10): on a 10 x 10 GT
/// grid of 0.1 m centred at the origin, row v and column u.
struct DownCamera {
  DepthCamera camera{10.0, 10.0, 4.5, 4.5, {}};
  Pose3d T_W_C = [] {
    Pose3d T = Pose3d::Identity();
    Eigen::Matrix3d R;
    R << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // x_C = x_W, y_C = -y_W, z_C = -z_W
    T.linear() = R;
    T.translation() = Eigen::Vector3d(0, 0, 1);
    return T;
  }();
};

GroundTruth flat_truth(int n, double res) {
  GroundTruth gt;
  gt.height.reset(n, n, res, 0.0, 0.0, 0.0f);
  gt.hazard.reset(n, n, res, 0.0, 0.0, 0.0f);
  return gt;
}

TEST(SeenMap, DepthPixelsMarkTheirGroundTruthCellFromTheirFrameWithinZMax) {
  const GroundTruth gt = flat_truth(10, 0.1);
  const DownCamera cam;
  cv::Mat depth(10, 10, CV_32FC1, cv::Scalar(1.0));
  depth.at<float>(2, 3) = kNaNf;  // sky
  depth.at<float>(4, 4) = 1.5f;   // beyond z_max 1.2 (and not where the ground is: no matter)
  SeenMap seen(gt.height);
  seen.add_depth(depth, cam.camera, cam.T_W_C, 1.2, 3);
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 10; ++u) {
      const bool hit = !(v == 2 && u == 3) && !(v == 4 && u == 4);
      EXPECT_EQ(seen.first(v, u), hit ? 3 : -1) << v << "," << u;
      EXPECT_FALSE(seen.seen(v, u, 2));
    }
  // A later frame does not move a first sighting; an earlier one does.
  cv::Mat all(10, 10, CV_32FC1, cv::Scalar(1.0));
  seen.add_depth(all, cam.camera, cam.T_W_C, 1.2, 5);
  EXPECT_EQ(seen.first(2, 3), 5);
  EXPECT_EQ(seen.first(0, 0), 3);
  seen.add_depth(all, cam.camera, cam.T_W_C, 1.2, 1);
  EXPECT_EQ(seen.first(0, 0), 1);
}

TEST(SeenMap, WholeDiscIsTheLatestFirstSightingWithinTheRadiusAgainstBruteForce) {
  const GroundTruth gt = flat_truth(10, 0.1);
  const DownCamera cam;
  SeenMap seen(gt.height);
  // Frame k sees rows >= 9 - k... built one depth image per frame.
  for (int k = 0; k < 10; ++k) {
    cv::Mat depth(10, 10, CV_32FC1, cv::Scalar(kNaNf));
    for (int u = 0; u < 10; ++u) depth.at<float>(9 - k, u) = 1.0f;
    if (k == 4) depth.at<float>(9 - k, 7) = kNaNf;  // never seen
    seen.add_depth(depth, cam.camera, cam.T_W_C, 2.0, k);
  }
  const double radius = 0.22;  // pixel offsets with dr^2 + dc^2 <= 4.84
  const SeenMap disc = seen.whole_disc(radius);
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 10; ++c) {
      int latest = 0;
      for (int dr = -3; dr <= 3; ++dr)
        for (int dc = -3; dc <= 3; ++dc) {
          if (std::hypot(dr * 0.1, dc * 0.1) > radius + 1e-9) continue;
          const int rr = r + dr, cc = c + dc;
          const int f = rr < 0 || cc < 0 || rr >= 10 || cc >= 10 ? -1 : seen.first(rr, cc);
          latest = latest < 0 || f < 0 ? -1 : std::max(latest, f);
        }
      EXPECT_EQ(disc.first(r, c), latest) << r << "," << c;
    }
}

TEST(SeenMap, WithRingIsTheLatestFirstSightingOverThePixelAndItsRingSamples) {
  const GroundTruth gt = flat_truth(10, 0.1);
  const DownCamera cam;
  SeenMap seen(gt.height);
  for (int k = 0; k < 10; ++k) {  // frame k sees row 9 - k, but for one pixel
    cv::Mat depth(10, 10, CV_32FC1, cv::Scalar(kNaNf));
    for (int u = 0; u < 10; ++u) depth.at<float>(9 - k, u) = 1.0f;
    if (k == 4) depth.at<float>(9 - k, 7) = kNaNf;  // never seen
    seen.add_depth(depth, cam.camera, cam.T_W_C, 2.0, k);
  }
  // 8 samples 0.2 m out on 0.1 m pixels: 2 pixels along the axes, (1, 1) on the
  // diagonals (0.141 m, rounded to the pixel holding the point), written out by hand.
  const int ring[8][2] = {{0, 2}, {1, 1}, {2, 0}, {1, -1}, {0, -2}, {-1, -1}, {-2, 0}, {-1, 1}};
  const SeenMap with = seen.with_ring(0.2, 8);
  int never = 0;
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 10; ++c) {
      int latest = seen.first(r, c);
      for (const auto& d : ring) {
        const int rr = r + d[0], cc = c + d[1];
        const int f = rr < 0 || cc < 0 || rr >= 10 || cc >= 10 ? -1 : seen.first(rr, cc);
        latest = latest < 0 || f < 0 ? -1 : std::max(latest, f);
      }
      EXPECT_EQ(with.first(r, c), latest) << r << "," << c;
      never += latest < 0;
    }
  // Within 2 pixels of the border, or a ring sample on the pixel never seen: never.
  // The 6 x 6 interior less (5, 7) itself and the 5 interior pixels whose ring holds it.
  EXPECT_EQ(never, 100 - 36 + 6);
  EXPECT_EQ(with.first(5, 5), -1);  // its sample (5, 7)
  EXPECT_EQ(with.first(4, 4), 7);   // rows 2..6: row 2, seen at frame 7, last
  EXPECT_THROW(seen.with_ring(-0.1, 8), Error);
  EXPECT_THROW(seen.with_ring(0.2, 0), Error);
}

/// The independent count: every GT pixel of a 2 x 2 block shares one 0.2 m map cell, so
/// the table is a sum over map cells of their seen pixels.
TEST(SeenConfusion, CountsEqualAHandCountOverMapCells) {
  GroundTruth gt = flat_truth(10, 0.1);
  // Obstacles (h_min 3 cm): 5 cm (hazard), 7 cm (tall), 1 cm (neither), NaN (no GT).
  gt.hazard.at(1, 1) = 0.05f;
  gt.hazard.at(1, 2) = 0.07f;
  gt.hazard.at(6, 6) = 0.01f;
  gt.hazard.at(8, 8) = kNaNf;
  DenseGrid map;
  map.reset(5, 5, 0.2, 0.0, 0.0, 0.0f);  // cell (i, j) holds GT rows 2i, 2i+1, cols 2j, 2j+1
  DenseGrid reasons;
  reasons.reset(5, 5, 0.2, 0.0, 0.0, 0.0f);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      map.at(i, j) = float((i + 2 * j) % 3);  // unknown / traversable / hazard
      if (map.at(i, j) == 0.0f) reasons.at(i, j) = float(i == 0 ? kReasonRingIncomplete
                                                               : kReasonRingIncomplete | kReasonStepMargin);
    }
  // Seen: frame 0 sees columns 0-5, frame 1 the rest; score at frame 0.
  SeenMap seen(gt.height);
  const DownCamera cam;
  cv::Mat d0(10, 10, CV_32FC1, cv::Scalar(kNaNf)), d1(10, 10, CV_32FC1, cv::Scalar(kNaNf));
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 10; ++u) (u < 6 ? d0 : d1).at<float>(v, u) = 1.0f;
  seen.add_depth(d0, cam.camera, cam.T_W_C, 2.0, 0);
  seen.add_depth(d1, cam.camera, cam.T_W_C, 2.0, 1);
  const SeenSums s = score_seen(map, &reasons, gt, seen, 0, Pose3d::Identity(), 0.03);

  SeenSums want;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j)  // map columns 0-2 hold the GT columns 0-5
      for (int r = 2 * i; r < 2 * i + 2; ++r)
        for (int c = 2 * j; c < 2 * j + 2; ++c) {
          const float o = gt.hazard.at(r, c);
          if (std::isnan(o)) continue;
          const int label = int(map.at(i, j));
          const unsigned bits = unsigned(reasons.at(i, j));
          for (int t : {0, 1, 2}) {
            const bool in = t == 0 ? o <= 0.0f : t == 1 ? o >= 0.03f : o >= 0.06f;
            if (!in) continue;
            ++want.count[t][label];
            if (label != 0) continue;
            for (int b = 0; b < kUnknownReasonCount; ++b)
              if (bits >> b & 1u) {
                ++want.reason_any[t][b];
                if (bits == (1u << b)) ++want.reason_sole[t][b];
              }
          }
        }
  for (int t = 0; t < 3; ++t) {
    for (int l = 0; l < 3; ++l) EXPECT_EQ(s.count[t][l], want.count[t][l]) << t << " " << l;
    for (int b = 0; b < kUnknownReasonCount; ++b) {
      EXPECT_EQ(s.reason_any[t][b], want.reason_any[t][b]) << t << " bit " << b;
      EXPECT_EQ(s.reason_sole[t][b], want.reason_sole[t][b]) << t << " bit " << b;
    }
  }
  // And by hand: 60 seen pixels (columns 0-5; the 1 cm obstacle and the NaN lie beyond):
  // 58 free, 2 obstacles, 1 tall.
  EXPECT_EQ(s.total(kTruthFree), 58u);
  EXPECT_EQ(s.total(kTruthHazard), 2u);
  EXPECT_EQ(s.total(kTruthTall), 1u);
  // GT (1, 1) and (1, 2): map cell (0, 0) unknown and (0, 1) hazard ((0 + 2) % 3 = 2).
  EXPECT_EQ(s.count[kTruthHazard][0], 1u);
  EXPECT_EQ(s.count[kTruthHazard][2], 1u);
  EXPECT_EQ(s.count[kTruthTall][2], 1u);
  // Row 0 of the map: ring incomplete alone (sole); rows 1-4: never sole.
  EXPECT_EQ(s.reason_sole[kTruthFree][4], s.reason_any[kTruthFree][4] - s.reason_any[kTruthFree][7]);
  EXPECT_DOUBLE_EQ(s.area_m2(kTruthFree), 58 * (0.1 * 0.1));
  // Frame 1 sees everything: 100 pixels minus the NaN one, the 1 cm obstacle and the two
  // obstacles.
  const SeenSums all = score_seen(map, nullptr, gt, seen, 1, Pose3d::Identity(), 0.03);
  EXPECT_EQ(all.total(kTruthFree), 96u);
  EXPECT_EQ(all.reason_unrecorded[kTruthFree], all.count[kTruthFree][0]);
  // Near: a disc of 0.15 m around (-0.45, 0.45) (GT pixel (0, 0)'s centre) holds the
  // pixels (0, 0), (0, 1), (1, 0) and (1, 1), whose centres lie 0, 0.1, 0.1, 0.141 away.
  const NearRegion near{-0.45, 0.45, 0.15};
  const SeenSums n = score_seen(map, &reasons, gt, seen, 0, Pose3d::Identity(), 0.03, &near);
  EXPECT_EQ(n.total(kTruthFree), 3u);
  EXPECT_EQ(n.total(kTruthHazard), 1u);
}

TEST(SeenConfusion, PooledSumsAddAndFieldsAreFractionsOfTheirClass) {
  SeenSums a, b;
  a.pixel_area_m2 = b.pixel_area_m2 = 1e-4;
  a.count[kTruthFree][1] = 8;
  a.count[kTruthFree][0] = 2;
  a.reason_any[kTruthFree][4] = 2;
  a.reason_sole[kTruthFree][4] = 1;
  b.count[kTruthFree][2] = 10;
  a += b;
  EXPECT_EQ(a.total(kTruthFree), 20u);
  EXPECT_DOUBLE_EQ(a.fraction(kTruthFree, 1), 0.4);
  EXPECT_TRUE(std::isnan(a.fraction(kTruthHazard, 2)));
  const auto f = seen_fields(a);
  const auto get = [&](const std::string& k) {
    for (const auto& [name, v] : f)
      if (name == k) return v;
    ADD_FAILURE() << "no field " << k;
    return 0.0;
  };
  EXPECT_DOUBLE_EQ(get("free_m2"), 20e-4);
  EXPECT_DOUBLE_EQ(get("free_traversable"), 0.4);
  EXPECT_DOUBLE_EQ(get("free_unknown"), 0.1);
  EXPECT_DOUBLE_EQ(get("free_hazard"), 0.5);
  EXPECT_DOUBLE_EQ(get("unknown_free_ring_incomplete"), 1.0);
  EXPECT_DOUBLE_EQ(get("unknown_free_ring_incomplete_sole"), 0.5);
  EXPECT_EQ(f.size(), seen_fields(SeenSums{}).size());
}

TEST(SeenConfusion, FusedReasonsCombineTheVouchingLayersAndNameACoarseProof) {
  // Fused 4 x 4 at 0.1 m; a fine layer (h_min 2 cm) over the left half only and a coarse
  // one (h_min 12 cm) over everything.
  DenseGrid fused, fine, fine_reasons, coarse;
  fused.reset(4, 4, 0.1, 0.0, 0.0, 0.0f);
  fused.at(0, 0) = 1.0f;  // known: no reasons
  fine.reset(4, 2, 0.1, -0.1, 0.0, 0.0f);
  fine_reasons.reset(4, 2, 0.1, -0.1, 0.0, float(kReasonRingIncomplete));
  fine.at(1, 1) = 2.0f;  // a hazard on the fine layer (the fused map would say hazard; not here)
  coarse.reset(2, 2, 0.2, 0.0, 0.0, 1.0f);  // traversable everywhere
  const std::vector<ReasonLayer> layers = {{&fine, &fine_reasons, 0.02}, {&coarse, nullptr, 0.12}};
  const DenseGrid bits = fused_unknown_reasons(layers, 0.03, fused);
  EXPECT_EQ(bits.at(0, 0), 0.0f);
  EXPECT_EQ(bits.at(2, 0), float(kReasonRingIncomplete | kReasonNoVouchingLayer));
  EXPECT_EQ(bits.at(1, 1), float(kReasonNoVouchingLayer));  // fine says hazard, not unknown
  EXPECT_EQ(bits.at(2, 3), float(kReasonOutside | kReasonNoVouchingLayer));
}

TEST(SeenConfusion, MismatchedSeenMapIsAnError) {
  const GroundTruth gt = flat_truth(10, 0.1);
  const SeenMap other(flat_truth(8, 0.1).height);
  DenseGrid map;
  map.reset(5, 5, 0.2, 0.0, 0.0, 0.0f);
  EXPECT_THROW(score_seen(map, nullptr, gt, other, 0, Pose3d::Identity(), 0.03), Error);
  const SeenMap seen(gt.height);
  EXPECT_THROW(score_seen(map, nullptr, gt, seen, 0, Pose3d::Identity(), 0.0), Error);
}

}  // namespace
}  // namespace hazmap::eval
