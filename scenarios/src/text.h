#pragma once
// Small text helpers shared by the writers of scenarios/ (reports, JUnit,
// manifests) and the lookup of files named in YAML files.

#include <optional>
#include <string>
#include <vector>

namespace hcpf::scenarios {

// Escapes & < > " for HTML and XML text and attribute values.
std::string EscapeMarkup(const std::string& text);

// Standard base64 (RFC 4648, with padding), for data: URIs in reports.
std::string Base64(const std::string& bytes);

// A file named in a YAML file: an absolute path as is; a relative one is
// looked for next to that file (`beside_dir`), then relative to the current
// folder, then to the project's source folder. Returns the first that exists
// (lexically normalised), or nullopt; `looked_at` lists every candidate.
std::optional<std::string> FindFile(const std::string& written, const std::string& beside_dir,
                                    std::vector<std::string>* looked_at = nullptr);

}  // namespace hcpf::scenarios
