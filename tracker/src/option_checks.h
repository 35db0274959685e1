#pragma once
// Helpers for Options::Validate(): throw hcpf::InputError naming the dotted key
// (e.g. "tracker.resampling.beta"), what was expected and what was found. The
// scenarios layer adds the file/line when it maps YAML onto the Options.

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <string_view>

#include "hcpf/core/error.h"

namespace hcpf::tracker::internal {

inline std::string Key(std::string_view prefix, std::string_view field) {
  return fmt::format("{}.{}", prefix, field);
}

template <typename T>
[[noreturn]] void FailOption(std::string_view prefix, std::string_view field,
                             std::string_view expected, const T& found) {
  SourceLocation where;
  where.key = Key(prefix, field);
  throw InputError(where, std::string(expected), fmt::format("{}", found));
}

inline void RequireFinite(std::string_view prefix, std::string_view field, double v) {
  if (!std::isfinite(v)) FailOption(prefix, field, "a finite number", v);
}
inline void RequirePositive(std::string_view prefix, std::string_view field, double v) {
  if (!(std::isfinite(v) && v > 0.0)) FailOption(prefix, field, "a finite number > 0", v);
}
inline void RequireNonNegative(std::string_view prefix, std::string_view field, double v) {
  if (!(std::isfinite(v) && v >= 0.0)) FailOption(prefix, field, "a finite number >= 0", v);
}
inline void RequireInRange(std::string_view prefix, std::string_view field, double v, double lo,
                           double hi) {
  if (!(v >= lo && v <= hi)) {
    FailOption(prefix, field, fmt::format("a number in [{}, {}]", lo, hi), v);
  }
}

}  // namespace hcpf::tracker::internal
