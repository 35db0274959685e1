#pragma once
// Scenario YAML from the declared Options fields of core/fields.h: the reader
// and the resolved-YAML writer of every declared key, so neither spells a key,
// a default or a range of its own.

#include <yaml-cpp/yaml.h>

#include <span>
#include <string>
#include <vector>

#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/fields.h"

namespace hcpf::config {

// Reads each field present in `r` into `o`, checking its type and range;
// absent keys keep `o`'s value (the in-class default). Marks every field as
// asked for, so r.Finish() rejects only keys outside the table.
template <class O>
void ReadFields(YamlReader& r, O& o, std::span<const Field<O>> fields) {
  for (const Field<O>& f : fields) {
    const std::string key(f.key);
    switch (f.type) {
      case FieldType::kNumber:
        o.*f.number = r.Number(key, o.*f.number, f.range);
        break;
      case FieldType::kInteger:
        o.*f.integer = static_cast<int>(r.Integer(
            key, o.*f.integer, static_cast<int64_t>(f.range.lo), static_cast<int64_t>(f.range.hi)));
        break;
      case FieldType::kFlag:
        o.*f.flag = r.Bool(key, o.*f.flag);
        break;
      case FieldType::kChoice: {
        const std::vector<std::string_view> names = f.choices();
        const std::string value = r.Enum(key, std::string(f.get_choice(o)),
                                         std::vector<std::string>(names.begin(), names.end()));
        f.set_choice(o, value);
        break;
      }
    }
  }
}

// Writes every field as `key: value` pairs into the open mapping of `out`,
// in table order.
template <class O>
void WriteFields(YAML::Emitter& out, const O& o, std::span<const Field<O>> fields) {
  for (const Field<O>& f : fields) {
    out << YAML::Key << std::string(f.key) << YAML::Value << f.ValueText(o);
  }
}

}  // namespace hcpf::config
