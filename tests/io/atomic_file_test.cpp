#include "hazmap/io/atomic_file.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

TEST(AtomicFile, WritesCreatesFoldersAndLeavesNoTemporaries) {
  testing::TempDir dir;
  const auto path = dir / "a/b/out.txt";
  write_file_atomically(path, std::string("first"));
  write_file_atomically(path, std::string("second"));
  EXPECT_EQ(testing::read_text(path), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path.parent_path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(AtomicFile, FailedWriteKeepsTheOldFile) {
  testing::TempDir dir;
  const auto path = dir / "keep.txt";
  write_file_atomically(path, std::string("precious"));
  // A folder where the temporary file would go cannot be written into: make the
  // destination a path whose parent is a regular file.
  EXPECT_THROW(write_file_atomically(path / "child.txt", std::string("x")), Error);
  EXPECT_EQ(testing::read_text(path), "precious");
}

}  // namespace
}  // namespace hazmap
