#pragma once
// Whole-file input and output shared by every module that reads a user's file
// (scenarios, sweep files, MOT files, models) or writes a text output.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hcpf {

// The 1-based line and column of byte `offset` of `text` (an offset past the
// end counts as the end), for errors a parser reports by byte, as an editor
// counts them: a UTF-8 byte-order mark at the start is no column of line 1
// (the regress baseline reader and the YAML reader each took it off by hand).
struct TextPosition {
  int line = 1;
  int column = 1;
};
TextPosition PositionOf(std::string_view text, size_t offset);

// The length of a UTF-8 byte-order mark at the start of `text` (3), or 0.
size_t ByteOrderMarkLength(std::string_view text);

// Whether `text` starts with a '+' and a second sign ("+-3", "++3"): no
// number, though std::from_chars after the '+' reads "+-3" as -3 (a
// bad-input audit found it so read in scenarios and MOT files).
bool StartsWithTwoSigns(std::string_view text);

// Writes `text` to `path`, whole or not at all: into a temporary file beside
// it (".<name>.tmp-<pid>-<n>") renamed over `path` at the end, so a failed or
// killed write leaves the earlier file as it was. An existing file keeps its
// permissions; a device, FIFO or symbolic link at `path` is written through
// in place. A path that is this process's standard output (IsStandardOutput:
// `/dev/stdout`, or the file stdout was redirected to) is written through
// standard output itself, after what the process printed there: opened
// again, it would start at offset 0 of a redirected file and the two writes
// would overwrite each other. Throws RunError naming the path and the
// system's reason when it cannot be written.
void WriteTextFile(const std::string& path, const std::string& text);

// Whether `path` names the file, pipe or socket this process's standard
// output writes to (the same device and inode: `/dev/stdout`,
// `/proc/self/fd/1`, or the file the shell redirected stdout to); never a
// device such as a terminal or /dev/null.
bool IsStandardOutput(const std::string& path);

// A new name for the temporary file of `path` in its folder
// (".<name>.tmp-<pid>-<n>", n counting in this process), for writers of other
// files (PNG) that write whole the same way as WriteTextFile.
std::filesystem::path TempFileFor(const std::filesystem::path& path);

// The name of the file whose temporary file WriteTextFile left as `entry`
// (".report.html.tmp-123-0" -> "report.html"), or "" when `entry` is not one:
// how a folder check tells what a killed write left from a user's file.
std::string TempFileTarget(std::string_view entry);

// Removes from `dir` (not below it) the temporary files of WriteTextFile
// whose process no longer runs: what writes killed part-way left. Those of
// live processes, and everything else, stay.
void RemoveStaleTempFiles(const std::filesystem::path& dir);

// Checks that `path` names a regular file that can be opened for reading and
// returns its size in bytes. A directory, a FIFO or a device (/dev/zero,
// /dev/urandom) is an InputError at `path` naming what was found: reading one
// would fail oddly, hang or grow without bound. A file that exists but may
// not be read is a RunError (an I/O problem: exit 1) that says to check its
// permissions. `what` names the expected content ("a YAML file").
uint64_t CheckRegularFile(const std::string& path, const std::string& what);

// Reads the whole of a regular file (CheckRegularFile) of at most `max_bytes`
// bytes; a larger one is an InputError naming both sizes, raised before
// anything is read.
std::string ReadInputFile(const std::string& path, const std::string& what, uint64_t max_bytes);

// Reads the first `count` bytes of a regular file (fewer when it is shorter),
// for format checks made before a whole file is handed to a library.
std::string ReadFilePrefix(const std::string& path, size_t count);

// A file a command will write, named by the option that gave it ("--json").
struct FileToWrite {
  std::string path;
  std::string option;
};

// A file a command reads, with what it is to the command ("the suite").
// An empty path is skipped.
struct FileRead {
  std::string path;
  std::string what;
};

// Checks a command's output files before it reads or runs anything, so a
// bad name costs nothing and destroys nothing. Each of `writes`, in order,
// must be: not a folder; in an existing folder; not one of `reads` (the same
// file by fs::equivalent, so a symbolic or hard link to an input is caught);
// not an earlier entry of `writes`; and not inside any of `reads_under`
// (folders the command reads whole). Throws InputError at the path, keyed by
// its option; `command` names the command in the messages ("a file score
// does not read"), and `consequence` is the hint ("nothing was written").
void CheckFilesToWrite(const std::vector<FileToWrite>& writes, const std::vector<FileRead>& reads,
                       const std::vector<std::filesystem::path>& reads_under,
                       const std::string& command, const std::string& consequence);

}  // namespace hcpf
