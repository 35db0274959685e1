#pragma once
// Files named inside YAML files (models, a sweep's base scenario, a suite's
// scenes).

#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/error.h"

namespace hcpf::config {

// A file named in a YAML file: an absolute path as is; a relative one is
// looked for next to that file (`beside_dir`), then relative to the current
// folder, then to the project's source folder. Returns the first that exists
// (lexically normalised), or nullopt; `looked_at` lists every candidate.
std::optional<std::string> FindFile(const std::string& written, const std::string& beside_dir,
                                    std::vector<std::string>* looked_at = nullptr);

// What was found when FindFile found nothing, for an error message:
// "\"x\", which does not exist (looked at a, b)", or, when a candidate is a
// folder, "\"x\", which is a folder, not a file (a)": "does not exist" sent
// users looking for a file that was there.
std::string NotFoundText(const std::string& written, const std::vector<std::string>& looked_at);

// FindFile, or an InputError at `where` (the YAML value that names the file)
// saying `expected` and NotFoundText.
std::string FindFileOrFail(const SourceLocation& where, const std::string& written,
                           const std::string& beside_dir, const std::string& expected);

}  // namespace hcpf::config
