#include "hcpf/core/fields.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"

namespace hcpf {

std::string FormatNumber(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15) {
    return fmt::format("{}", static_cast<int64_t>(value));
  }
  return fmt::format("{}", value);
}

std::string FieldRange::Text() const {
  const std::string low = std::isinf(lo) ? "-inf" : FormatNumber(lo);
  const std::string high = std::isinf(hi) ? "inf" : FormatNumber(hi);
  return fmt::format("{}{}, {}{}", lo_open || std::isinf(lo) ? "(" : "[", low, high,
                     hi_open || std::isinf(hi) ? ")" : "]");
}

std::string_view FieldTypeName(FieldType type) {
  switch (type) {
    case FieldType::kNumber:
      return "number";
    case FieldType::kInteger:
      return "integer";
    case FieldType::kFlag:
      return "bool";
    case FieldType::kChoice:
      return "enum";
    case FieldType::kVector:
      return "vector";
    case FieldType::kPoints:
      return "points";
    case FieldType::kText:
      return "text";
    case FieldType::kPath:
      return "path";
    case FieldType::kSeed:
      return "seed";
    case FieldType::kWords:
      return "list";
  }
  return "?";
}

std::string FieldExpectation(FieldType type, const FieldRange& range) {
  switch (type) {
    case FieldType::kInteger:
      return fmt::format("an integer in {}", range.Text());
    case FieldType::kVector:
    case FieldType::kPoints:
      return fmt::format("numbers in {}", range.Text());
    default:
      return fmt::format("a number in {}", range.Text());
  }
}

namespace {
std::string DottedKey(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : fmt::format("{}.{}", prefix, key);
}
}  // namespace

void FailOption(std::string_view prefix, std::string_view field, std::string_view expected,
                std::string_view found) {
  throw InputError(SourceLocation{{}, 0, 0, DottedKey(prefix, field)}, std::string(expected),
                   std::string(found));
}

void FailOption(std::string_view prefix, std::string_view field, std::string_view expected,
                double found) {
  FailOption(prefix, field, expected, FormatNumber(found));
}

std::string WordsExpectation(int min_items, const std::vector<std::string_view>& choices) {
  std::string joined;
  for (std::string_view c : choices) joined += fmt::format("{}{}", joined.empty() ? "" : " | ", c);
  return fmt::format("a list of at least {} distinct names, each one of {}", min_items, joined);
}

namespace internal {

void FailFieldRange(std::string_view prefix, std::string_view key, FieldType type,
                    const FieldRange& range, double value) {
  throw InputError(SourceLocation{{}, 0, 0, DottedKey(prefix, key)}, FieldExpectation(type, range),
                   FormatNumber(value));
}

void FailFieldChoice(std::string_view prefix, std::string_view key,
                     const std::vector<std::string_view>& choices, std::string_view value) {
  std::string joined;
  for (std::string_view c : choices) joined += fmt::format("{}{}", joined.empty() ? "" : " | ", c);
  FailOption(prefix, key, "one of " + joined, fmt::format("\"{}\"", value));
}

void FailFieldWords(std::string_view prefix, std::string_view key, int min_items,
                    const std::vector<std::string_view>& choices,
                    const std::vector<std::string>& found) {
  std::string text = "[";
  for (const std::string& w : found) text += (text.size() > 1 ? ", " : "") + w;
  FailOption(prefix, key, WordsExpectation(min_items, choices), text + "]");
}

void FailUndeclaredField(std::string_view key) {
  HCPF_CHECK(false) << "no declared field \"" << std::string(key) << "\"";
  std::abort();
}

}  // namespace internal
}  // namespace hcpf
