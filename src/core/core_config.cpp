#include "hazmap/core/core_config.hpp"

#include "hazmap/rules/rule_registry.hpp"

namespace hazmap {

const char* rule_name(RuleKind kind) { return rule_info(kind).name; }

}  // namespace hazmap
