#pragma once
// Small helpers shared by the writers of studies/ (reports, JUnit, CSV,
// manifests): text, numbers and the missing value.

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace hcpf::studies {

// Escapes & < > " for HTML and XML text and attribute values.
std::string EscapeMarkup(const std::string& text);

// Standard base64 (RFC 4648, with padding), for data: URIs in reports.
std::string Base64(const std::string& bytes);

// A CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string Csv(const std::string& text);

// A number for tables and CSV: "{:.6g}", "nan" when not finite.
std::string Number(double v);

// A missing value (a metric a run did not report, a cell without runs).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace hcpf::studies
