#pragma once
// Atomic output: content goes to a temporary file in the destination folder, which is
// then renamed over the destination. A reader (or an interrupted run) sees either the
// old file or the complete new one, never a truncated one.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hazmap {

/// Writes `content` to `path` atomically; creates parent folders. Throws Error naming
/// the path on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Same for binary content (encoded PNG bytes, PLY).
void write_file_atomically(const std::filesystem::path& path,
                           const std::vector<unsigned char>& content);

/// For writers that need a file name (GDAL): `write` fills the hidden temporary path it
/// is given, which is then renamed onto `path`. The temporary file is removed when
/// `write` throws; Error names `path`.
void write_via_temporary(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write);

/// A folder filled under a hidden staging name (`staging_folder_name`) and then renamed
/// onto `dest`, so that `dest` is either absent, the old folder or the complete new one.
/// An existing `dest` is moved aside first and removed after the rename (rename(2) does
/// not replace a non-empty folder).
std::filesystem::path staging_folder_name(const std::filesystem::path& dest);
void publish_folder(const std::filesystem::path& staging, const std::filesystem::path& dest);

}  // namespace hazmap
