#include "hcpf/config/file_lookup.h"

#include <algorithm>
#include <filesystem>

namespace hcpf::config {

namespace fs = std::filesystem;

std::optional<std::string> FindFile(const std::string& written, const std::string& beside_dir,
                                    std::vector<std::string>* looked_at) {
  std::vector<fs::path> candidates;
  const fs::path p(written);
  if (p.is_absolute()) {
    candidates.push_back(p);
  } else {
    if (!beside_dir.empty()) candidates.push_back(fs::path(beside_dir) / p);
    candidates.push_back(fs::current_path() / p);
    candidates.push_back(fs::path(HCPF_PROJECT_SOURCE_DIR) / p);
  }
  std::error_code ec;
  for (const fs::path& c : candidates) {
    if (fs::is_regular_file(c, ec)) return c.lexically_normal().string();
    if (looked_at == nullptr) continue;
    // A folder looked in twice (the scenario's folder is the current one)
    // is listed once (a bad-input audit: "looked at /a/x.glb, /a/x.glb, ...").
    const std::string normal = fs::absolute(c, ec).lexically_normal().string();
    if (std::find(looked_at->begin(), looked_at->end(), normal) == looked_at->end()) {
      looked_at->push_back(normal);
    }
  }
  return std::nullopt;
}

std::string NotFoundText(const std::string& written, const std::vector<std::string>& looked_at) {
  std::error_code ec;
  std::string list;
  for (const std::string& l : looked_at) {
    const fs::file_status st = fs::status(l, ec);
    if (fs::is_directory(st))
      return "\"" + written + "\", which is a folder, not a file (" + l + ")";
    // /dev/null, a FIFO or a socket: there, but not a file to read (a second
    // bad-input audit found /dev/null reported as not existing).
    if (fs::exists(st)) {
      return "\"" + written + "\", which is " +
             (fs::is_character_file(st) || fs::is_block_file(st) ? "a device"
              : fs::is_fifo(st)                                  ? "a named pipe"
                                                                 : "not a regular file") +
             ", not a file (" + l + ")";
    }
    list += (list.empty() ? "" : ", ") + l;
  }
  return "\"" + written + "\", which does not exist (looked at " + list + ")";
}

std::string FindFileOrFail(const SourceLocation& where, const std::string& written,
                           const std::string& beside_dir, const std::string& expected) {
  std::vector<std::string> looked;
  if (auto found = FindFile(written, beside_dir, &looked)) return *found;
  throw InputError(where, expected, NotFoundText(written, looked));
}

}  // namespace hcpf::config
