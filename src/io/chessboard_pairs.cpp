#include "hazmap/io/chessboard_pairs.hpp"

#include <algorithm>
#include <map>

#include <spdlog/spdlog.h>

#include "hazmap/camera/grey_pair.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/images.hpp"

namespace fs = std::filesystem;

namespace hazmap {
namespace {

bool is_image_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  for (const char* e : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm"})
    if (ext == e) return true;
  return false;
}

/// Images of `dir` keyed by name: the stem, minus `prefix` when one is given (files not
/// starting with it are ignored).
std::map<std::string, fs::path> images_by_name(const fs::path& dir, const std::string& prefix) {
  std::map<std::string, fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file() || !is_image_file(entry.path())) continue;
    const std::string stem = entry.path().stem().string();
    if (stem.rfind(prefix, 0) != 0) continue;
    out.emplace(stem.substr(prefix.size()), entry.path());
  }
  return out;
}

}  // namespace

std::vector<ChessboardPairFiles> find_chessboard_pairs(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": image folder not found");
  std::map<std::string, fs::path> lefts = images_by_name(dir / "left", "");
  std::map<std::string, fs::path> rights = images_by_name(dir / "right", "");
  if (lefts.empty()) {
    lefts = images_by_name(dir, "left");
    rights = images_by_name(dir, "right");
  }
  std::vector<ChessboardPairFiles> pairs;
  for (const auto& [name, left] : lefts) {
    const auto it = rights.find(name);
    if (it == rights.end()) {
      spdlog::warn("{}: no right image to pair with, skipped", left.string());
      continue;
    }
    pairs.push_back({name, left, it->second});
  }
  if (pairs.empty())
    throw Error(dir.string() + ": no image pairs (expected left/<name> + right/<name>, or "
                               "left<tag> + right<tag> images)");
  return pairs;
}

ChessboardCalibration calibrate_chessboard_pairs(const fs::path& dir, const ChessboardOptions& o) {
  std::vector<ChessboardView> views;
  std::vector<std::string> rejected;
  cv::Size size;
  cv::Mat grey_left, grey_right;
  GreyPairConverter grey;  // colour and 10/12/16-bit boards as the stereo path sees them
  for (const ChessboardPairFiles& pair : find_chessboard_pairs(dir)) {
    grey.convert(read_image(pair.left), read_image(pair.right), grey_left, grey_right);
    if (size.area() == 0) size = grey_left.size();
    for (const auto* p : {&pair.left, &pair.right}) {
      const cv::Size s = p == &pair.left ? grey_left.size() : grey_right.size();
      if (s != size)
        throw Error(p->string() + ": image is " + std::to_string(s.width) + "x" +
                    std::to_string(s.height) + ", the first pair's is " +
                    std::to_string(size.width) + "x" + std::to_string(size.height));
    }
    ChessboardView view;
    view.name = pair.name;
    if (!detect_chessboard_pair(grey_left, grey_right, o, view)) {
      spdlog::info("pair {}: board not found in both images, skipped", pair.name);
      rejected.push_back(pair.name);
      continue;
    }
    views.push_back(std::move(view));
  }
  ChessboardCalibration result = calibrate_stereo(views, size, o);
  result.rejected = rejected;
  // A chessboard knows nothing of the rover: T_body_left is for the user to give.
  result.calibration.body_pose_source = BodyPoseSource::absent;
  return result;
}

}  // namespace hazmap
