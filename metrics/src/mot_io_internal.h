#pragma once
// Private to metrics/ and its tests.

#include <optional>
#include <string>

#include "hcpf/metrics/mot_io.h"

namespace hcpf::metrics::internal {

// The straightforward reader ParseMotText is checked against: every line split
// into fields and parsed on the general path, duplicate ids found by sorting all
// rows by (frame, id, line). Same results and same InputError messages as
// ParseMotText, only slower.
MotFile ParseMotTextReference(const std::string& text, const std::string& path, MotFileKind kind,
                              std::optional<int> seq_length = std::nullopt);

}  // namespace hcpf::metrics::internal
