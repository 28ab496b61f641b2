#pragma once
// Writing outputs so that a failure leaves nothing half-written.
#include <string>
#include <string_view>
#include <vector>

namespace cw4d {

/// Writes `content` to a temporary file next to `path`, flushes it, and renames it over `path`.
/// On any failure (a full disk: ENOSPC, ...) the temporary file is removed and nothing is left
/// at `path`; on SIGINT, SIGTERM or SIGHUP too (see TemporaryGuard).
///
/// The rule for every output path (this function, write_files_atomically, StagedFiles): only a
/// new name or a regular file is replaced. A symbolic link is followed and kept (the regular file
/// it names is replaced; a device or FIFO it names is written into). An existing device or FIFO
/// (/dev/null, /dev/stdout) is written into, never replaced; a FIFO that no process reads is
/// refused. A directory, a socket and a symbolic link to nothing (or a loop) are refused.
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

/// A group of files too large to hold in memory at once (the layers of a sweep, the frames of a
/// render), written one by one into a hidden staging folder inside `directory` and moved into
/// place together by commit(). Until then nothing at the destinations changes; an exception,
/// SIGINT, SIGTERM or SIGHUP removes the staging folder and what it holds (the folder is guarded
/// by a TemporaryGuard). Only plain files go into the staging folder.
class StagedFiles {
 public:
  /// Creates the staging folder ".STEM.staging.PID.N" in `directory` ("" is "."), which must
  /// exist. \throw IoError
  StagedFiles(const std::string& directory, const std::string& stem);
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();

  /// Where to write the file that becomes directory/name.
  std::string staged(const std::string& name) const;
  /// directory/name
  std::string destination(const std::string& name) const;
  /// Moves each staged file to directory/name, in the order given, by the rule of
  /// write_file_atomically. Every destination is checked first (and every device or FIFO
  /// opened): a directory, a socket, a dangling link or an unread FIFO at any name throws with
  /// nothing moved; only a failing rename, after earlier ones, can leave the group mixed. Then
  /// removes the staging folder. \throw IoError
  void commit(const std::vector<std::string>& names);
  /// Renames the staging folder itself to `folder`, a name that must not exist (a new output
  /// folder, in `directory`). \throw IoError
  void commit_as_folder(const std::string& folder);
  /// Removes the staging folder and its files now (also done by the destructor).
  void discard() noexcept;

 private:
  std::string directory_;
  std::string folder_;
  TemporaryGuard guard_;
};

}  // namespace cw4d
