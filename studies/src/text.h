#pragma once
// Small text helpers shared by the writers of scenarios/ (reports, JUnit,
// manifests).

#include <optional>
#include <string>
#include <vector>

namespace hcpf::studies {

// Escapes & < > " for HTML and XML text and attribute values.
std::string EscapeMarkup(const std::string& text);

// Standard base64 (RFC 4648, with padding), for data: URIs in reports.
std::string Base64(const std::string& bytes);

}  // namespace hcpf::studies
