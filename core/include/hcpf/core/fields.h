#pragma once
// Options fields declared once. Each field of an Options struct that a
// scenario configures is declared in one table next to the struct: its key,
// the member, unit, range and a one-line doc (the default is the member's
// in-class value). The module's Validate() checks the ranges from the table
// (CheckFields); the scenario reader, the resolved-YAML writer and the tables
// of docs/scenario.md are generated from the same table (scenarios/schema).
// YAML-free: library modules declare tables without seeing YAML.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "hcpf/core/enum_names.h"

namespace hcpf {

// Shortest text that parses back to the same double ("3", "0.05", "1e-09").
std::string FormatNumber(double value);

// The allowed values of a number or integer field: from lo to hi, each end
// closed unless marked open. Integer fields use closed ends.
struct FieldRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  bool Contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  // "[0, 1000]", "(0, 16]", "[0, inf)".
  std::string Text() const;
};

inline FieldRange Closed(double lo, double hi) { return {lo, hi}; }
// (lo, hi]: a value that must be strictly above lo.
inline FieldRange AboveUpTo(double lo, double hi) { return {lo, hi, true, false}; }

// kVector: a fixed number of numbers, each in the range (whole numbers when
// `whole`); kPoints: a list of at least one [x, y]; kText: free text (quoted
// in the resolved YAML); kPath: a file path the reader resolves (it needs the
// scenario's folder: ReadFields takes the resolver); kSeed: a 64-bit seed;
// kWords: a list of distinct names from `choices` (at least `size` of them
// when written; empty = not written); with no `choices` (StringsField), a
// list of any non-empty strings, repeats allowed (a command line).
enum class FieldType {
  kNumber,
  kInteger,
  kFlag,
  kChoice,
  kVector,
  kPoints,
  kText,
  kPath,
  kSeed,
  kWords
};

// "number", "integer", "bool", "enum", "vector", "points", "text", "path",
// "seed", "list".
std::string_view FieldTypeName(FieldType type);

template <class O>
struct Field {
  std::string_view key;
  FieldType type = FieldType::kNumber;
  std::string_view unit;
  FieldRange range;  // kNumber, kInteger
  std::string_view doc;
  double O::*number = nullptr;
  int O::*integer = nullptr;
  bool O::*flag = nullptr;
  // kChoice: the member as its name, a name into the member (false when it is
  // not a name), and every name.
  std::string_view (*get_choice)(const O&) = nullptr;
  bool (*set_choice)(O&, std::string_view) = nullptr;
  std::vector<std::string_view> (*choices)() = nullptr;
  // kInteger through accessors (a member of another integer type, e.g. ObjectId).
  int64_t (*get_integer)(const O&) = nullptr;
  void (*set_integer)(O&, int64_t) = nullptr;
  // kVector: `size` numbers named `elements` ("x, y"); kPoints: [x, y] each.
  int size = 0;
  bool whole = false;
  std::string_view elements;
  std::vector<double> (*get_vector)(const O&) = nullptr;
  void (*set_vector)(O&, const std::vector<double>&) = nullptr;
  std::vector<Eigen::Vector2d> O::*points = nullptr;
  // kText, kPath: the value as written (kPath: as the resolved YAML writes it).
  std::string (*get_text)(const O&) = nullptr;
  void (*set_text)(O&, std::string) = nullptr;
  uint64_t O::*seed = nullptr;                   // kSeed
  std::vector<std::string> O::*words = nullptr;  // kWords
  // No default: the key must be written (`default_doc` says when, if only sometimes).
  bool required = false;
  // kText: left out of the resolved YAML when empty (a value that exists only
  // with another key, e.g. a model's digest).
  bool omitted_when_empty = false;
  // The default column of the docs when the member's in-class value is not
  // the default ("derived from `seed`", "file name without extension").
  std::string_view default_doc;

  int64_t IntegerOf(const O& o) const { return get_integer ? get_integer(o) : o.*integer; }
  void SetInteger(O& o, int64_t v) const {
    if (set_integer) {
      set_integer(o, v);
    } else {
      o.*integer = static_cast<int>(v);
    }
  }
  // kVector / kPoints as flat numbers (points: x0, y0, x1, y1, ...).
  std::vector<double> NumbersOf(const O& o) const {
    if (type == FieldType::kVector) return get_vector(o);
    std::vector<double> out;
    for (const Eigen::Vector2d& p : o.*points) out.insert(out.end(), {p.x(), p.y()});
    return out;
  }

  // The member's value as the resolved YAML writes it.
  std::string ValueText(const O& o) const {
    switch (type) {
      case FieldType::kNumber:
        return FormatNumber(o.*number);
      case FieldType::kInteger:
        return std::to_string(IntegerOf(o));
      case FieldType::kFlag:
        return o.*flag ? "true" : "false";
      case FieldType::kChoice:
        return std::string(get_choice(o));
      case FieldType::kVector:
      case FieldType::kPoints: {
        const std::vector<double> v = NumbersOf(o);
        std::string out = "[";
        const bool pairs = type == FieldType::kPoints;
        for (size_t i = 0; i < v.size(); ++i) {
          if (i > 0) out += ", ";
          if (pairs && i % 2 == 0) out += "[";
          out += FormatNumber(v[i]);
          if (pairs && i % 2 == 1) out += "]";
        }
        return out + "]";
      }
      case FieldType::kText:
      case FieldType::kPath:
        return get_text(o);
      case FieldType::kSeed:
        return std::to_string(o.*seed);
      case FieldType::kWords: {
        std::string out = "[";
        for (const std::string& w : o.*words) out += (out.size() > 1 ? ", " : "") + w;
        return out + "]";
      }
    }
    return {};
  }
};

template <class O>
Field<O> NumberField(std::string_view key, double O::*member, FieldRange range,
                     std::string_view unit, std::string_view doc) {
  Field<O> f;
  f.key = key;
  f.type = FieldType::kNumber;
  f.unit = unit;
  f.range = range;
  f.doc = doc;
  f.number = member;
  return f;
}

template <class O>
Field<O> IntegerField(std::string_view key, int O::*member, int lo, int hi, std::string_view unit,
                      std::string_view doc) {
  Field<O> f;
  f.key = key;
  f.type = FieldType::kInteger;
  f.unit = unit;
  f.range = Closed(lo, hi);
  f.doc = doc;
  f.integer = member;
  return f;
}

template <class O>
Field<O> FlagField(std::string_view key, bool O::*member, std::string_view doc) {
  Field<O> f;
  f.key = key;
  f.type = FieldType::kFlag;
  f.doc = doc;
  f.flag = member;
  return f;
}

// The same field with no default: the key must be written.
template <class O>
Field<O> Required(Field<O> f) {
  f.required = true;
  return f;
}
// The same field with a default the docs describe in words.
template <class O>
Field<O> DefaultDoc(Field<O> f, std::string_view default_doc) {
  f.default_doc = default_doc;
  return f;
}

template <class O>
Field<O> SeedField(std::string_view key, uint64_t O::*member, std::string_view doc) {
  Field<O> f;
  f.key = key;
  f.type = FieldType::kSeed;
  f.doc = doc;
  f.seed = member;
  return f;
}

template <class O>
Field<O> PointsField(std::string_view key, std::vector<Eigen::Vector2d> O::*member,
                     FieldRange range, std::string_view unit, std::string_view doc) {
  Field<O> f;
  f.key = key;
  f.type = FieldType::kPoints;
  f.unit = unit;
  f.range = range;
  f.doc = doc;
  f.size = 2;
  f.elements = "x, y";
  f.points = member;
  return f;
}

namespace internal {
template <class T>
struct MemberOf;
template <class O, class T>
struct MemberOf<T O::*> {
  using Object = O;
  using Type = T;
};
}  // namespace internal

// An enum member whose names come from EnumNames<E> (core/enum_names.h).
template <auto Member>
Field<typename internal::MemberOf<decltype(Member)>::Object> ChoiceField(std::string_view key,
                                                                         std::string_view doc) {
  using O = typename internal::MemberOf<decltype(Member)>::Object;
  using E = typename internal::MemberOf<decltype(Member)>::Type;
  static_assert(NamedEnum<E>, "specialise EnumNames<E> for the member's enum");
  Field<O> f;
  f.key = key;
  f.type = FieldType::kChoice;
  f.doc = doc;
  f.get_choice = [](const O& o) { return NameOf(o.*Member); };
  f.set_choice = [](O& o, std::string_view name) {
    const std::optional<E> value = ParseName<E>(name);
    if (value) o.*Member = *value;
    return value.has_value();
  };
  f.choices = [] { return NamesOf<E>(); };
  return f;
}

// A text member that holds one of a fixed list of words, `Names()`.
template <auto Member, std::vector<std::string_view> (*Names)()>
Field<typename internal::MemberOf<decltype(Member)>::Object> WordField(std::string_view key,
                                                                       std::string_view doc) {
  using O = typename internal::MemberOf<decltype(Member)>::Object;
  static_assert(std::is_same_v<typename internal::MemberOf<decltype(Member)>::Type, std::string>);
  Field<O> f;
  f.key = key;
  f.type = FieldType::kChoice;
  f.doc = doc;
  f.get_choice = [](const O& o) { return std::string_view(o.*Member); };
  f.set_choice = [](O& o, std::string_view name) {
    for (std::string_view n : Names()) {
      if (n == name) {
        o.*Member = std::string(name);
        return true;
      }
    }
    return false;
  };
  f.choices = Names;
  return f;
}

// An Eigen fixed-size vector member (Vector2d, Vector3d), each element in `range`.
template <auto Member>
Field<typename internal::MemberOf<decltype(Member)>::Object> VectorField(std::string_view key,
                                                                         std::string_view elements,
                                                                         FieldRange range,
                                                                         std::string_view unit,
                                                                         std::string_view doc) {
  using O = typename internal::MemberOf<decltype(Member)>::Object;
  using V = typename internal::MemberOf<decltype(Member)>::Type;
  Field<O> f;
  f.key = key;
  f.type = FieldType::kVector;
  f.unit = unit;
  f.range = range;
  f.doc = doc;
  f.size = static_cast<int>(V::SizeAtCompileTime);
  f.elements = elements;
  f.get_vector = [](const O& o) {
    const V& v = o.*Member;
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  f.set_vector = [](O& o, const std::vector<double>& v) {
    for (int i = 0; i < static_cast<int>(V::SizeAtCompileTime); ++i) (o.*Member)[i] = v[i];
  };
  return f;
}

// A free-text member, written quoted.
template <auto Member>
Field<typename internal::MemberOf<decltype(Member)>::Object> TextField(std::string_view key,
                                                                       std::string_view doc) {
  using O = typename internal::MemberOf<decltype(Member)>::Object;
  Field<O> f;
  f.key = key;
  f.type = FieldType::kText;
  f.doc = doc;
  f.get_text = [](const O& o) { return std::string(o.*Member); };
  f.set_text = [](O& o, std::string v) { o.*Member = std::move(v); };
  return f;
}

// A list of free strings (kWords without `choices`): empty when not written,
// else at least `min_items` non-empty strings, written double-quoted.
template <auto Member>
Field<typename internal::MemberOf<decltype(Member)>::Object> StringsField(std::string_view key,
                                                                          int min_items,
                                                                          std::string_view doc) {
  using O = typename internal::MemberOf<decltype(Member)>::Object;
  static_assert(std::is_same_v<typename internal::MemberOf<decltype(Member)>::Type,
                               std::vector<std::string>>);
  Field<O> f;
  f.key = key;
  f.type = FieldType::kWords;
  f.doc = doc;
  f.size = min_items;
  f.words = Member;
  return f;
}

// A list of distinct words from `Names()`: empty when not written, else at
// least `min_items` of them (a StringsField whose items are `choices`).
template <auto Member, std::vector<std::string_view> (*Names)()>
Field<typename internal::MemberOf<decltype(Member)>::Object> WordsField(std::string_view key,
                                                                        int min_items,
                                                                        std::string_view doc) {
  auto f = StringsField<Member>(key, min_items, doc);
  f.choices = Names;
  return f;
}

namespace internal {
// Throws InputError {key: "<prefix>.<key>", expected: the range, found: value}.
[[noreturn]] void FailFieldRange(std::string_view prefix, std::string_view key, FieldType type,
                                 const FieldRange& range, double value);
[[noreturn]] void FailFieldChoice(std::string_view prefix, std::string_view key,
                                  const std::vector<std::string_view>& choices,
                                  std::string_view value);
// Throws InputError for a kWords list that repeats a word or is too short.
[[noreturn]] void FailFieldWords(std::string_view prefix, std::string_view key, int min_items,
                                 const std::vector<std::string_view>& choices,
                                 const std::vector<std::string>& found);
// HCPF_CHECK-style abort: RangeOf asked for a key no field declares.
[[noreturn]] void FailUndeclaredField(std::string_view key);
}  // namespace internal

// The one way an Options::Validate() reports a broken rule: throws
// InputError {key: "<prefix>.<field>", expected, found}. The scenario reader
// relocates it to the key's file line. A number is written as FormatNumber
// writes it.
[[noreturn]] void FailOption(std::string_view prefix, std::string_view field,
                             std::string_view expected, std::string_view found);
[[noreturn]] void FailOption(std::string_view prefix, std::string_view field,
                             std::string_view expected, double found);

// "a number in [0, 1000]" / "an integer in [1, 10000000]".
std::string FieldExpectation(FieldType type, const FieldRange& range);
// "a list of at least 2 distinct names, each one of a | b | c".
std::string WordsExpectation(int min_items, const std::vector<std::string_view>& choices);

// Checks every number and integer field of `o` against its range (numbers
// must also be finite) and every choice against its names; throws InputError
// naming "<prefix>.<key>" for the first that is not.
template <class O>
void CheckFields(const O& o, std::span<const Field<O>> fields, std::string_view prefix) {
  for (const Field<O>& f : fields) {
    if (f.type == FieldType::kNumber) {
      const double v = o.*f.number;
      if (!std::isfinite(v) || !f.range.Contains(v)) {
        internal::FailFieldRange(prefix, f.key, f.type, f.range, v);
      }
    } else if (f.type == FieldType::kInteger) {
      const double v = static_cast<double>(f.IntegerOf(o));
      if (!f.range.Contains(v)) internal::FailFieldRange(prefix, f.key, f.type, f.range, v);
    } else if (f.type == FieldType::kVector || f.type == FieldType::kPoints) {
      for (double v : f.NumbersOf(o)) {
        if (!std::isfinite(v) || !f.range.Contains(v) || (f.whole && v != std::floor(v))) {
          internal::FailFieldRange(prefix, f.key, f.type, f.range, v);
        }
      }
    } else if (f.type == FieldType::kChoice) {
      const std::string_view name = f.get_choice(o);
      bool known = false;
      const std::vector<std::string_view> names = f.choices();
      for (std::string_view n : names) known = known || n == name;
      if (!known) internal::FailFieldChoice(prefix, f.key, names, name);
    } else if (f.type == FieldType::kWords && f.choices) {
      const std::vector<std::string>& words = o.*f.words;
      const std::vector<std::string_view> names = f.choices();
      bool ok = words.empty() || static_cast<int>(words.size()) >= f.size;
      for (size_t i = 0; i < words.size(); ++i) {
        bool known = false;
        for (std::string_view n : names) known = known || n == words[i];
        for (size_t j = 0; j < i; ++j) ok = ok && words[j] != words[i];
        ok = ok && known;
      }
      if (!ok) internal::FailFieldWords(prefix, f.key, f.size, names, words);
    }
  }
}

}  // namespace hcpf

namespace hcpf {

// The range declared for `key` in `fields` (a bug when there is none): lets a
// second Options struct over the same quantity reuse one declaration.
template <class O>
const FieldRange& RangeOf(std::span<const Field<O>> fields, std::string_view key) {
  for (const Field<O>& f : fields) {
    if (f.key == key) return f.range;
  }
  internal::FailUndeclaredField(key);
}

}  // namespace hcpf
