#pragma once
// Whole-file text output shared by the run pipeline and the studies.

#include <string>

namespace hcpf {

// Writes `text` to `path` (truncating); throws RunError naming the path and
// the system's reason when it cannot be opened or written.
void WriteTextFile(const std::string& path, const std::string& text);

}  // namespace hcpf
