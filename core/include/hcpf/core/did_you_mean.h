#pragma once
// "Did you mean" for names a user typed: keys, enum values, commands.

#include <string>
#include <vector>

namespace hcpf {

// Edit distance: insertions, deletions, substitutions and swaps of two
// adjacent characters (optimal string alignment).
int EditDistance(const std::string& a, const std::string& b);

// The closest candidate within a small distance, else the shortest one that
// extends the word at an underscore (a dropped unit suffix), else "".
std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace hcpf
