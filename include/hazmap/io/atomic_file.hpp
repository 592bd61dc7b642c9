#pragma once
// Atomic output: content goes to a temporary file in the destination folder, which is
// then renamed over the destination. A reader (or an interrupted run) sees either the
// old file or the complete new one, never a truncated one.

#include <filesystem>
#include <string>
#include <vector>

namespace hazmap {

/// Writes `content` to `path` atomically; creates parent folders. Throws Error naming
/// the path on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Same for binary content (encoded PNG bytes, PLY).
void write_file_atomically(const std::filesystem::path& path,
                           const std::vector<unsigned char>& content);

}  // namespace hazmap
