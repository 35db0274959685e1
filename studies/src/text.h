#pragma once
// Small helpers shared by the writers of studies/ (reports, JUnit, CSV,
// manifests): text, numbers, links and the missing value.

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace hcpf::studies {

// Escapes & < > " for HTML and XML text and attribute values.
std::string EscapeMarkup(const std::string& text);

// `text` (Markdown whose only markup is `code` spans) as HTML: escaped, each
// pair of backticks a <code> element (an unpaired one stays a backtick).
std::string CodeSpansToHtml(const std::string& text);

// Standard base64 (RFC 4648, with padding), for data: URIs in reports.
std::string Base64(const std::string& bytes);

// A CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string Csv(const std::string& text);

// `target` as a link from a page in the folder `page_dir`: the relative path
// when there is one, else the absolute path; '/' separators.
std::string LinkFrom(const std::filesystem::path& page_dir, const std::filesystem::path& target);

// `word` as one shell word: unchanged when it holds only characters no
// shell treats specially, else in single quotes; "./" before a leading '-'.
std::string ShellWord(std::string word);

// A number for tables and CSV: "{:.6g}", "nan" when not finite.
std::string Number(double v);

// Below this a distance in px (a camera-motion error) is rounding: a run
// report shows it as 0.
inline constexpr double kRoundingPx = 1e-9;

// A distance in px, 0 when it is rounding.
inline double RoundedPx(double px) { return px < kRoundingPx && px > -kRoundingPx ? 0.0 : px; }

// A missing value (a metric a run did not report, a cell without runs).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace hcpf::studies
