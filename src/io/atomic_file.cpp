#include "hazmap/io/atomic_file.hpp"

#include <atomic>
#include <cstdio>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

std::filesystem::path temporary_name(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  return path.parent_path() / ("." + path.filename().string() + ".tmp" +
                               std::to_string(::getpid()) + "_" + std::to_string(counter++));
}

void write_bytes_atomically(const std::filesystem::path& path, const char* data, size_t size) {
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) throw Error(path.parent_path().string() + ": cannot create folder: " + ec.message());
  const std::filesystem::path tmp = temporary_name(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(tmp.string() + ": cannot open for writing");
    out.write(data, static_cast<std::streamsize>(size));
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw Error(path.string() + ": write failed");
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(path.string() + ": cannot rename temporary file into place");
  }
}

}  // namespace

void write_via_temporary(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write) {
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) throw Error(path.parent_path().string() + ": cannot create folder: " + ec.message());
  const std::filesystem::path tmp = temporary_name(path);
  try {
    write(tmp);
  } catch (...) {
    std::filesystem::remove(tmp, ec);
    throw;
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(path.string() + ": cannot rename temporary file into place");
  }
}

std::filesystem::path staging_folder_name(const std::filesystem::path& dest) {
  return temporary_name(dest);
}

void publish_folder(const std::filesystem::path& staging, const std::filesystem::path& dest) {
  std::error_code ec;
  std::filesystem::path aside;
  if (std::filesystem::exists(dest, ec)) {
    aside = temporary_name(dest);
    std::filesystem::rename(dest, aside, ec);
    if (ec) throw Error(dest.string() + ": cannot move the old folder aside: " + ec.message());
  }
  std::filesystem::rename(staging, dest, ec);
  if (ec) {
    const std::string why = ec.message();
    if (!aside.empty()) std::filesystem::rename(aside, dest, ec);  // keep the old one
    throw Error(dest.string() + ": cannot rename the staged folder into place: " + why);
  }
  if (!aside.empty()) std::filesystem::remove_all(aside, ec);
}

void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  write_bytes_atomically(path, content.data(), content.size());
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::vector<unsigned char>& content) {
  write_bytes_atomically(path, reinterpret_cast<const char*>(content.data()), content.size());
}

}  // namespace hazmap
