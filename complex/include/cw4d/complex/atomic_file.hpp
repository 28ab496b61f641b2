#pragma once
// Writing outputs so that a failure leaves nothing half-written.
#include <string>
#include <string_view>
#include <vector>

namespace cw4d {

/// Writes `content` to a temporary file next to `path`, flushes it, and renames it over `path`.
/// On any failure (a full disk: ENOSPC, ...) the temporary file is removed and nothing is left
/// at `path`; on SIGINT, SIGTERM or SIGHUP too (see TemporaryGuard). An existing `path` that is
/// not a regular file (/dev/null, /dev/stdout, a FIFO) is written into, never replaced; a FIFO
/// that no process reads is refused. A symbolic link keeps pointing at the file it names.
/// \throw IoError naming the path and the reason.
void write_file_atomically(const std::string& path, std::string_view content);

/// Registers a temporary file (or a folder of plain files) to be removed when SIGINT, SIGTERM
/// or SIGHUP ends the process while the guard lives; release() or destruction unregisters it
/// (removing it is then the owner's job). The handlers are installed on first use, and only
/// for signals the program leaves at their default. At most 64 are guarded at once.
class TemporaryGuard {
 public:
  TemporaryGuard() = default;
  TemporaryGuard(const std::string& path, bool folder);
  TemporaryGuard(TemporaryGuard&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  TemporaryGuard& operator=(TemporaryGuard&& other) noexcept;
  TemporaryGuard(const TemporaryGuard&) = delete;
  TemporaryGuard& operator=(const TemporaryGuard&) = delete;
  ~TemporaryGuard();
  void release();

 private:
  int slot_ = -1;
};

/// A file of a group that belongs together (an OBJ and its .mtl, a .gltf and its .bin).
struct FileContent {
  std::string path;
  std::string_view content;
};

/// Writes every file to a temporary first, then renames them over their paths in the order given
/// (put companions first and the file that refers to them last). A failure while writing (a full
/// disk, a missing directory, a path that is a directory) leaves every previous file untouched
/// and no temporary behind; only a failing rename, after the earlier ones, can leave the group
/// mixed.
/// \throw IoError from the first failure.
void write_files_atomically(const std::vector<FileContent>& files);

}  // namespace cw4d
