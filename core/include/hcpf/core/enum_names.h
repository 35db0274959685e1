#pragma once
// One enum <-> name mechanism for every enum a scenario or a command line
// names. An enum opts in by specialising EnumNames<E> with a constexpr array
// `kNames` of {value, name} pairs in declaration order; NameOf, ParseName and
// NamesOf then work for it, and ToString(e) is found by ordinary lookup from
// every hcpf namespace.

#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace hcpf {

template <class E>
struct EnumNames;  // specialise: static constexpr std::array<std::pair<E, std::string_view>, N>
                   // kNames

template <class E>
concept NamedEnum = std::is_enum_v<E> && requires {
  EnumNames<E>::kNames;
};

// The name of `value`; "?" for a value outside the table (a bug).
template <NamedEnum E>
constexpr std::string_view NameOf(E value) {
  for (const auto& [v, name] : EnumNames<E>::kNames) {
    if (v == value) return name;
  }
  return "?";
}

// The value named `name` exactly (case-sensitive), or nothing.
template <NamedEnum E>
constexpr std::optional<E> ParseName(std::string_view name) {
  for (const auto& [v, n] : EnumNames<E>::kNames) {
    if (n == name) return v;
  }
  return std::nullopt;
}

// Every name, in declaration order.
template <NamedEnum E>
std::vector<std::string_view> NamesOf() {
  std::vector<std::string_view> names;
  for (const auto& entry : EnumNames<E>::kNames) names.push_back(entry.second);
  return names;
}

// Every value, in declaration order (contract test suites iterate these).
template <NamedEnum E>
std::vector<E> EnumValues() {
  std::vector<E> values;
  for (const auto& entry : EnumNames<E>::kNames) values.push_back(entry.first);
  return values;
}

template <NamedEnum E>
constexpr std::string_view ToString(E value) {
  return NameOf(value);
}

}  // namespace hcpf
