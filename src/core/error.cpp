#include "hazmap/core/error.hpp"

namespace hazmap {

void check(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace hazmap
