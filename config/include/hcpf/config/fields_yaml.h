#pragma once
// Scenario YAML from the declared Options fields of core/fields.h: the reader
// and the resolved-YAML writer of every declared key, so neither spells a key,
// a default or a range of its own.

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/check.h"
#include "hcpf/core/fields.h"

namespace hcpf::config {

// Resolves a kPath field's text (a model file named relative to the
// scenario) at the location of its value; throws InputError.
using PathResolver = std::function<std::string(const std::string& text, const SourceLocation&)>;

// Reads each field present in `r` into `o`, checking its type and range;
// absent keys keep `o`'s value (the default), required ones are an error.
// Marks every field as asked for, so r.Finish() rejects only keys outside
// the table. `resolve` is needed only by tables with a kPath field.
template <class O>
void ReadFields(YamlReader& r, O& o, std::span<const Field<O>> fields,
                const PathResolver& resolve = {}) {
  for (const Field<O>& f : fields) {
    const std::string key(f.key);
    const bool req = f.required;
    switch (f.type) {
      case FieldType::kNumber:
        o.*f.number = r.Number(key, req ? std::nullopt : std::optional(o.*f.number), f.range);
        break;
      case FieldType::kInteger:
        f.SetInteger(o,
                     r.Integer(key, req ? std::nullopt : std::optional(f.IntegerOf(o)),
                               static_cast<int64_t>(f.range.lo), static_cast<int64_t>(f.range.hi)));
        break;
      case FieldType::kFlag:
        o.*f.flag = r.Bool(key, req ? std::nullopt : std::optional(o.*f.flag));
        break;
      case FieldType::kChoice: {
        const std::vector<std::string_view> names = f.choices();
        const std::string value =
            r.Enum(key, req ? std::nullopt : std::optional(std::string(f.get_choice(o))),
                   std::vector<std::string>(names.begin(), names.end()));
        f.set_choice(o, value);
        break;
      }
      case FieldType::kVector: {
        if (!req && !r.Has(key)) break;
        const Eigen::VectorXd v = r.Vector(key, f.size, std::nullopt, f.range.lo, f.range.hi);
        if (f.whole) {
          // At the item that is not whole: its own line, or the --set that
          // wrote it (a second bad-input audit: --set camera.resolution.0=320.5
          // was blamed on the file's line, "found a list of 2 item(s)").
          const std::vector<YamlReader> items = r.Child(key).Items();
          for (int i = 0; i < v.size(); ++i) {
            if (v[i] != std::floor(v[i])) {
              items[static_cast<size_t>(i)].Fail(fmt::format(
                  "a whole number in {} (item {} of [{}])", f.range.Text(), i, f.elements));
            }
          }
        }
        f.set_vector(o, std::vector<double>(v.data(), v.data() + v.size()));
        break;
      }
      case FieldType::kPoints: {
        if (!req && !r.Has(key)) break;
        YamlReader list = r.Child(key);
        std::vector<Eigen::Vector2d> points;
        for (const YamlReader& item : list.Items()) {
          const Eigen::VectorXd p = item.AsVector(2, f.range.lo, f.range.hi);
          points.emplace_back(p[0], p[1]);
        }
        if (points.empty()) list.Fail("a list of at least one [x, y] point");
        o.*f.points = std::move(points);
        break;
      }
      case FieldType::kText:
        f.set_text(o, r.String(key, req ? std::nullopt : std::optional(f.get_text(o))));
        break;
      case FieldType::kPath: {
        if (!req && !r.Has(key)) break;
        const SourceLocation where = r.Child(key).Where();
        HCPF_CHECK(resolve) << "a path field needs a resolver: " << key;
        f.set_text(o, resolve(r.String(key, std::nullopt), where));
        break;
      }
      case FieldType::kSeed:
        o.*f.seed = r.Seed(key, req ? std::nullopt : std::optional(o.*f.seed));
        break;
      case FieldType::kWords: {
        if (!req && !r.Has(key)) break;
        YamlReader list = r.Child(key);
        if (!f.choices) {  // free strings (StringsField)
          const std::string expected =
              fmt::format("a list of at least {} non-empty strings", f.size);
          std::vector<std::string> strings;
          for (const YamlReader& item : list.Items()) {
            if (!item.node().IsScalar() || item.node().Scalar().empty()) item.Fail(expected);
            strings.push_back(item.node().Scalar());
          }
          // An empty list is the key not written.
          if (!strings.empty() && static_cast<int>(strings.size()) < f.size) list.Fail(expected);
          o.*f.words = std::move(strings);
          break;
        }
        const std::vector<std::string_view> names = f.choices();
        const std::vector<std::string> choices(names.begin(), names.end());
        std::vector<std::string> words;
        for (const YamlReader& item : list.Items()) {
          std::string word = item.AsEnum(choices);
          if (std::find(words.begin(), words.end(), word) != words.end()) {
            item.Fail(WordsExpectation(f.size, names), "\"" + word + "\" is listed twice");
          }
          words.push_back(std::move(word));
        }
        if (static_cast<int>(words.size()) < f.size) list.Fail(WordsExpectation(f.size, names));
        o.*f.words = std::move(words);
        break;
      }
    }
  }
}

// Writes every field as `key: value` pairs into the open mapping of `out`,
// in table order; an optional path that is not set is left out, as is an
// empty text marked omitted_when_empty.
template <class O>
void WriteFields(YAML::Emitter& out, const O& o, std::span<const Field<O>> fields) {
  for (const Field<O>& f : fields) {
    if (f.type == FieldType::kPath && !f.required && f.get_text(o).empty()) continue;
    if (f.type == FieldType::kWords && !f.required && (o.*f.words).empty()) continue;
    if (f.type == FieldType::kText && f.omitted_when_empty && f.get_text(o).empty()) continue;
    out << YAML::Key << std::string(f.key) << YAML::Value;
    if (f.type == FieldType::kVector || f.type == FieldType::kPoints) {
      const std::vector<double> v = f.NumbersOf(o);
      out << YAML::Flow << YAML::BeginSeq;
      for (size_t i = 0; i < v.size(); ++i) {
        if (f.type == FieldType::kPoints && i % 2 == 0) out << YAML::Flow << YAML::BeginSeq;
        out << FormatNumber(v[i]);
        if (f.type == FieldType::kPoints && i % 2 == 1) out << YAML::EndSeq;
      }
      out << YAML::EndSeq;
    } else if (f.type == FieldType::kWords) {
      out << YAML::Flow << YAML::BeginSeq;
      for (const std::string& w : o.*f.words) {
        if (f.choices) {
          out << w;
        } else {
          out << YAML::DoubleQuoted << w;
        }
      }
      out << YAML::EndSeq;
    } else if (f.type == FieldType::kText || f.type == FieldType::kPath) {
      out << YAML::DoubleQuoted << f.get_text(o);
    } else {
      out << f.ValueText(o);
    }
  }
}

}  // namespace hcpf::config
