#pragma once
// The names a configuration enum's values have in the YAML, the dump and the outputs: one
// table per enum (EnumNames<E>::names, in enumerator order), read by the parser once at
// load and by whatever prints a value. No parsing library here: the map core uses it.

#include <cstddef>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hazmap {

/// Specialise with `static constexpr const char* names[]`, one per enumerator in order.
template <class E>
struct EnumNames;

/// The name of `value`.
template <class E>
const char* enum_name(E value) {
  return EnumNames<E>::names[static_cast<std::size_t>(value)];
}

/// The value named `name`, nothing for any other name.
template <class E>
std::optional<E> enum_value(std::string_view name) {
  for (std::size_t i = 0; i < std::size(EnumNames<E>::names); ++i)
    if (name == EnumNames<E>::names[i]) return static_cast<E>(i);
  return std::nullopt;
}

/// Every name, in enumerator order.
template <class E>
std::vector<std::string> enum_names() {
  return {std::begin(EnumNames<E>::names), std::end(EnumNames<E>::names)};
}

}  // namespace hazmap
