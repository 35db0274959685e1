#pragma once
// The keys of sweep files and regression suites, declared once: the readers
// (sweep.cc, regress.cc) take their ranges and defaults from here, a test
// checks that the keys they accept are exactly these, and the tables of
// docs/sweeps.md are generated from them (`hcpf schema --update docs/sweeps.md`).

#include <span>
#include <string>
#include <string_view>

namespace hcpf::studies {

struct FileKey {
  std::string_view key;           // dotted; `[i]` for list items, `<m>` for a metric name
  std::string_view type;          // as a user reads it
  std::string_view default_text;  // "**required**", "none" or the value
  std::string_view meaning;
};

// `seeds`: runs per cell.
inline constexpr int kMinSweepSeeds = 1;
inline constexpr int kMaxSweepSeeds = 100'000;
// `scenes[i].seeds` of a suite: a paired interval needs two seeds (one seed is
// the exact mode, `seeds` left out); every seed is a full run of the scene.
inline constexpr int kMinSuiteSeeds = 2;
inline constexpr int kMaxSuiteSeeds = 1000;
// `metrics.<m>.tolerance` of a suite.
inline constexpr double kMaxTolerance = 1e12;

std::span<const FileKey> SweepFileKeys();
std::span<const FileKey> SuiteFileKeys();

// The sections `hcpf schema` adds for these files: "sweep", "suite".
std::span<const std::string_view> FileKeySections();
// The markdown table of a section (| key | type | default | meaning |);
// "" when `section` is not one of FileKeySections().
std::string FileKeysMarkdown(std::string_view section);

}  // namespace hcpf::studies
