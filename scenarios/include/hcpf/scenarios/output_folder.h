#pragma once
// Output folders that appear complete or not at all: work goes into a sibling
// "<out>.partial-<pid>" folder that is renamed into place at the end. An
// existing folder is replaced only when it is empty or an earlier output of
// ours: its manifest.json is a run or render manifest of this tool, and it
// holds nothing a run or render does not write. A folder of the user's is
// never touched.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

namespace hcpf::scenarios {

// Checks a folder given on the command line as `option` (e.g. "--out"): not
// empty, not an existing file (or a link to one), not a link to nothing, and
// not below a file or a link to nothing. InputError naming the option
// otherwise; a missing folder is fine (it is created).
void CheckFolderArgument(const std::string& path, const std::string& option);

// The staging folder StagedFolder makes for `out` in this process:
// "<absolute out>.partial-<pid>" (a trailing '/' of `out` dropped). The
// interrupt message of run and render names it.
std::filesystem::path StagingFolderFor(const std::filesystem::path& out);

class StagedFolder {
 public:
  // Checks `out` (InputError naming --out when it is a file or a foreign
  // folder), removes siblings "<out>.partial-<pid>" / "<out>.old-<pid>" left
  // by processes that no longer run (unless `remove_stale_siblings` is false:
  // that lists the parent folder, and a sweep, which cleans its runs/ once
  // under its folder lock, would list it once per run: a scale audit found
  // a 20,000-run sweep quadratic), and creates the partial folder (RunError
  // on failure).
  explicit StagedFolder(const std::filesystem::path& out, bool remove_stale_siblings = true);
  // Removes the partial folder unless Publish() succeeded.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  const std::filesystem::path& out() const { return out_; }
  const std::filesystem::path& partial() const { return partial_; }
  // Replaces `out` with the partial folder without a moment where `out` is
  // half deleted: an earlier folder is renamed aside to "<out>.old-<pid>",
  // the partial folder renamed into place, then the old one deleted.
  void Publish();

 private:
  std::filesystem::path out_;
  std::filesystem::path partial_;
  bool published_ = false;
};

// Why `dir` is not an earlier output folder of this tool that may be
// replaced, or "" when it is one (manifest format hcpf-run/1 or
// hcpf-render/1, and only the files those write).
std::string WhyNotOurOutput(const std::filesystem::path& dir);

// Why a run may not write its folder at `out`, or "" when it may: `out` is
// absent, an empty folder, or an earlier output folder (WhyNotOurOutput). A
// symbolic link (even to a folder) or a file is never replaced. StagedFolder
// and regress's check of its --work folders ask this.
std::string WhyNotReplaceable(const std::filesystem::path& out);

// The name of the first entry of `dir` (in directory order) that `allowed`
// refuses, or "" when it accepts every one or `dir` is not a folder: how the
// sweep's --out and the report's --out tell a folder of theirs from one of
// the user's.
std::string FirstForeignEntry(
    const std::filesystem::path& dir,
    const std::function<bool(const std::filesystem::directory_entry&)>& allowed);

// Removes "<prefix>.partial-<pid>" and "<prefix>.old-<pid>" entries of
// `parent` whose process no longer runs; with an empty prefix, every such
// entry. Folders of live processes stay.
void RemoveStaleStagingFolders(const std::filesystem::path& parent, const std::string& prefix);

// The size in bytes of every regular file below `dir`, by its path relative
// to `dir` with '/' separators ("gt/gt.txt"): the "files" of a run's
// manifest.json, by which a resumed sweep or a merge tells a stored run
// folder that is whole from one with a file deleted, cut short or emptied.
// A folder that cannot be listed is a RunError.
std::map<std::string, uint64_t> FileSizesOf(const std::filesystem::path& dir);

}  // namespace hcpf::scenarios
