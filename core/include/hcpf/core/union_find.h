#pragma once
// The root of an element in a union-find forest stored as parent indices
// (a root is its own parent), halving the path on the way. The callers keep
// their own union rule: PRCA's clustering and the tracker's gated blocks both
// hang the later root under the earlier one, so a root is its set's first
// element.

#include <cstddef>
#include <vector>

namespace hcpf {

template <class Index>
Index FindRoot(std::vector<Index>& parent, Index x) {
  while (parent[static_cast<size_t>(x)] != x) {
    parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
    x = parent[static_cast<size_t>(x)];
  }
  return x;
}

}  // namespace hcpf
