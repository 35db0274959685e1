#include "output_folder.h"

#include <fmt/format.h>
#include <unistd.h>

#include "hcpf/core/error.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

StagedFolder::StagedFolder(const fs::path& out) : out_(fs::absolute(out).lexically_normal()) {
  std::error_code ec;
  if (fs::exists(out_, ec)) {
    if (!fs::is_directory(out_, ec)) {
      throw InputError(SourceLocation{out_.string(), 0, 0, "--out"}, "a folder for the outputs",
                       "an existing file");
    }
    if (!fs::is_empty(out_, ec) && !fs::exists(out_ / "manifest.json", ec)) {
      throw InputError(SourceLocation{out_.string(), 0, 0, "--out"},
                       "a new or empty folder, or an earlier output folder (with manifest.json)",
                       "a folder with other files in it");
    }
  }
  partial_ = out_.string() + fmt::format(".partial-{}", ::getpid());
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
  if (fs::exists(out_, ec)) fs::remove_all(out_, ec);
  if (ec) throw RunError(fmt::format("cannot replace {}: {}", out_.string(), ec.message()));
  fs::rename(partial_, out_, ec);
  if (ec) throw RunError(fmt::format("cannot move the output to {}: {}", out_.string(), ec.message()));
  published_ = true;
}

}  // namespace hcpf::scenarios
