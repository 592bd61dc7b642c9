#include "hazmap/io/images.hpp"

#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {

cv::Mat read_image(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": image not found");
  cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty()) throw Error(path.string() + ": cannot decode image");
  return image;
}

void to_gray8(const cv::Mat& in, cv::Mat& out) {
  cv::Mat grey;
  if (in.channels() == 3) {
    cv::cvtColor(in, grey, cv::COLOR_BGR2GRAY);
  } else if (in.channels() == 4) {
    cv::cvtColor(in, grey, cv::COLOR_BGRA2GRAY);
  } else if (in.channels() == 1) {
    grey = in;
  } else {
    throw Error("image has " + std::to_string(in.channels()) + " channels");
  }
  if (grey.depth() == CV_8U) {
    if (grey.data != out.data) grey.copyTo(out);
  } else if (grey.depth() == CV_16U) {
    grey.convertTo(out, CV_8U, 1.0 / 256.0);
  } else {
    throw Error("unsupported image depth (expected 8 or 16 bit)");
  }
}

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) throw Error(path.string() + ": PNG encoding failed");
  write_file_atomically(path, bytes);
}

}  // namespace hazmap
