#pragma once
// Errors the library reports to its caller. The library never exits; `main` turns
// an Error into one line on stderr and a non-zero exit code.

#include <stdexcept>
#include <string>

namespace hazmap {

/// An expected failure (bad input file, bad configuration, I/O problem). The message
/// is one line and names the file, line or key at fault.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Throws Error(message) when `condition` is false. Active in every build type,
/// unlike assert. The const char* form builds no string unless it throws, so it is free
/// on the per-frame path.
inline void check(bool condition, const char* message) {
  if (!condition) throw Error(message);
}
void check(bool condition, const std::string& message);

}  // namespace hazmap
