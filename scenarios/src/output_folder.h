#pragma once
// Output folders that appear complete or not at all: work goes into a sibling
// "<out>.partial-<pid>" folder that is renamed into place at the end. An
// existing folder is replaced only when it is empty or an earlier output of
// ours (it has manifest.json), never a folder of the user's.

#include <filesystem>

namespace hcpf::scenarios {

class StagedFolder {
 public:
  // Checks `out` (InputError naming --out when it is a file or a foreign
  // folder) and creates the partial folder (RunError on failure).
  explicit StagedFolder(const std::filesystem::path& out);
  // Removes the partial folder unless Publish() succeeded.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  const std::filesystem::path& out() const { return out_; }
  const std::filesystem::path& partial() const { return partial_; }
  // Replaces `out` with the partial folder.
  void Publish();

 private:
  std::filesystem::path out_;
  std::filesystem::path partial_;
  bool published_ = false;
};

}  // namespace hcpf::scenarios
