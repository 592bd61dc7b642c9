#include "hazmap/core/core_config.hpp"

namespace hazmap {

const char* rule_name(RuleKind kind) {
  switch (kind) {
    case RuleKind::bananas: return "bananas";
    case RuleKind::kalman: return "kalman";
    case RuleKind::omg: return "omg";
    case RuleKind::ccm: return "ccm";
  }
  return "?";
}

}  // namespace hazmap
