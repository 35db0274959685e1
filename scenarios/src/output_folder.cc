#include "hcpf/scenarios/output_folder.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string_view>

#include "hcpf/core/error.h"
#include "hcpf/core/subprocess.h"
#include "hcpf/core/text_file.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

namespace {

// What RunScenario (run.cc) and RenderToFolder (render_folder.cc) write at
// the top of their folder, and report.html that `hcpf report RUN_DIR` adds
// (studies/src/run_report.cc); gt/, det/ (rendered runs) and frames/ are
// checked file by file below.
constexpr std::array<std::string_view, 12> kOutputFiles = {
    "manifest.json",     "scenario.resolved.yaml", "seqinfo.ini",
    "gt.json",           "detections.txt",         "tracks.txt",
    "filters.csv",       "metrics.json",           "overlay.mp4",
    "contact_sheet.png", "camera_motion.csv",      "report.html"};

bool IsFrameFile(std::string_view name) {
  // 000001.png, 000001_depth.png, 000001_ids.png (render_folder.cc).
  if (name.size() < 10) return false;
  for (size_t i = 0; i < 6; ++i) {
    if (name[i] < '0' || name[i] > '9') return false;
  }
  const std::string_view rest = name.substr(6);
  return rest == ".png" || rest == "_depth.png" || rest == "_ids.png";
}

}  // namespace

std::string WhyNotOurOutput(const fs::path& dir) {
  std::error_code ec;
  const fs::path manifest_path = dir / "manifest.json";
  if (!fs::is_regular_file(manifest_path, ec)) return "a folder with other files in it";
  nlohmann::json manifest;
  try {
    std::ifstream in(manifest_path);
    manifest = nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return "a folder whose manifest.json is not one of this tool's";
  }
  const std::string format =
      manifest.is_object() && manifest.contains("format") && manifest["format"].is_string()
          ? manifest["format"].get<std::string>()
          : std::string();
  if (format != "hcpf-run/1" && format != "hcpf-render/1") {
    return "a folder whose manifest.json is not one of this tool's (no \"format\": "
           "\"hcpf-run/1\" or \"hcpf-render/1\")";
  }
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const bool known_file =
        std::find(kOutputFiles.begin(), kOutputFiles.end(), name) != kOutputFiles.end() &&
        entry.is_regular_file(ec) && !entry.is_symlink(ec);
    // What a write killed part-way left (WriteTextFile's temporary file of
    // one of these files, from `hcpf report DIR`) is ours too.
    const std::string target = TempFileTarget(name);
    const bool our_temp = !target.empty() && std::find(kOutputFiles.begin(), kOutputFiles.end(),
                                                       target) != kOutputFiles.end();
    if (known_file || our_temp) continue;
    const bool known_dir = (name == "gt" || name == "det" || name == "frames") &&
                           entry.is_directory(ec) && !entry.is_symlink(ec);
    if (!known_dir) {
      return fmt::format(
          "an output folder of this tool that also holds \"{}\", which no run "
          "writes",
          name);
    }
    // The entry inside a run's folder that no run writes is named, not the
    // folder (a docs audit: "gt/extra.txt" was refused as "gt", which every
    // run writes).
    for (const auto& inner : fs::directory_iterator(entry.path(), ec)) {
      const std::string inner_name = inner.path().filename().string();
      const bool ok = inner.is_regular_file(ec) && !inner.is_symlink(ec) &&
                      (name == "frames" ? IsFrameFile(inner_name) : inner_name == name + ".txt");
      if (!ok) {
        return fmt::format(
            "an output folder of this tool that also holds \"{}/{}\", which no run "
            "writes",
            name, inner_name);
      }
    }
  }
  if (ec) return fmt::format("a folder that cannot be listed ({})", ec.message());
  return "";
}

std::string WhyNotReplaceable(const fs::path& out) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(out, ec);
  if (!fs::exists(st)) return "";
  if (!fs::is_directory(st)) return fs::is_symlink(st) ? "a symbolic link" : "an existing file";
  return fs::is_empty(out, ec) ? "" : WhyNotOurOutput(out);
}

std::string FirstForeignEntry(const fs::path& dir,
                              const std::function<bool(const fs::directory_entry&)>& allowed) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return "";
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!allowed(entry)) return entry.path().filename().string();
  }
  return "";
}

void RemoveStaleStagingFolders(const fs::path& parent, const std::string& prefix) {
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) return;
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    for (const std::string_view marker : {".partial-", ".old-"}) {
      const size_t at = name.rfind(marker);
      if (at == std::string::npos) continue;
      // With a prefix, the name must be exactly "<prefix><marker><pid>".
      if (!prefix.empty() && name.compare(0, at, prefix) != 0) continue;
      if (ProcessIsGone(std::string_view(name).substr(at + marker.size()))) {
        fs::remove_all(entry.path(), ec);
      }
      break;
    }
  }
}

void CheckFolderArgument(const std::string& path, const std::string& option) {
  if (path.empty()) {
    throw InputError(SourceLocation{"command line", 0, 0, option}, "a folder", "an empty path");
  }
  const SourceLocation where{path, 0, 0, option};
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) {
      throw InputError(where, "a folder (new or existing)", "an existing file", "name a folder");
    }
    return;
  }
  // A second bad-input audit: a link to nothing, or a path below a file,
  // failed later with exit 1 ("cannot create ...: File exists"). The
  // nearest part of the path that exists must be a folder.
  const fs::path whole = fs::path(path).lexically_normal();
  for (fs::path at = whole; !at.empty(); at = at.parent_path()) {
    if (fs::exists(fs::status(at, ec))) {
      if (!fs::is_directory(fs::status(at, ec))) {
        throw InputError(where, "a folder (new or existing)",
                         fmt::format("a path below the file {}", at.string()),
                         "nothing was changed; name a folder");
      }
      break;
    }
    if (fs::is_symlink(fs::symlink_status(at, ec))) {
      throw InputError(
          where, "a folder (new or existing)",
          fmt::format("{}a symbolic link to nothing ({} -> {})", at == whole ? "" : "a path below ",
                      at.string(), fs::read_symlink(at, ec).string()),
          "nothing was changed; name a folder, or create the one the link names");
    }
    if (at == at.parent_path()) break;
  }
}

namespace {
// `out` absolute, without a trailing '/': "DIR/" put the staging folder
// inside DIR and failed to move it aside ("Invalid argument", leaving an
// empty DIR; a review).
fs::path Absolute(const fs::path& out) {
  fs::path p = fs::absolute(out).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

fs::path AbsoluteFolder(const fs::path& out) {
  CheckFolderArgument(out.string(), "--out");
  return Absolute(out);
}
}  // namespace

fs::path StagingFolderFor(const fs::path& out) {
  return Absolute(out).string() + fmt::format(".partial-{}", ::getpid());
}

StagedFolder::StagedFolder(const fs::path& out, bool remove_stale_siblings)
    : out_(AbsoluteFolder(out)) {
  std::error_code ec;
  const SourceLocation where{out_.string(), 0, 0, "--out"};
  const std::string why = WhyNotReplaceable(out_);
  if (!why.empty()) {
    throw InputError(
        where, "a new or empty folder, or an earlier output folder of hcpf run or hcpf render", why,
        "nothing was changed; name another folder");
  }
  if (remove_stale_siblings)
    RemoveStaleStagingFolders(out_.parent_path(), out_.filename().string());
  partial_ = StagingFolderFor(out_);
  fs::remove_all(partial_, ec);
  fs::create_directories(partial_, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", partial_.string(), ec.message()));
}

StagedFolder::~StagedFolder() {
  if (published_) return;
  std::error_code ec;
  fs::remove_all(partial_, ec);
}

void StagedFolder::Publish() {
  std::error_code ec;
  const fs::path old = out_.string() + fmt::format(".old-{}", ::getpid());
  const bool had_old = fs::exists(fs::symlink_status(out_, ec));
  if (had_old) {
    fs::remove_all(old, ec);
    fs::rename(out_, old, ec);
    if (ec) {
      throw RunError(
          fmt::format("cannot move the earlier {} aside: {}", out_.string(), ec.message()));
    }
  }
  fs::rename(partial_, out_, ec);
  if (ec) {
    const std::string message = ec.message();
    if (had_old) fs::rename(old, out_, ec);  // put the earlier output back
    throw RunError(fmt::format("cannot move the output to {}: {}", out_.string(), message));
  }
  published_ = true;
  if (had_old) fs::remove_all(old, ec);
}

std::map<std::string, uint64_t> FileSizesOf(const fs::path& dir) {
  std::map<std::string, uint64_t> sizes;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec) || it->is_symlink(ec)) continue;
    const uint64_t size = it->file_size(ec);
    if (ec) break;
    sizes[it->path().lexically_relative(dir).generic_string()] = size;
  }
  if (ec) throw RunError(fmt::format("cannot list {}: {}", dir.string(), ec.message()));
  return sizes;
}

}  // namespace hcpf::scenarios
