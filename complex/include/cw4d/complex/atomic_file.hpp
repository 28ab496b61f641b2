#pragma once
// Writing outputs so that a failure leaves nothing half-written.
#include <string>
#include <string_view>
#include <vector>

namespace cw4d {

/// Writes `content` to a temporary file next to `path`, flushes it, and renames it over `path`.
/// On any failure the temporary file is removed and nothing is left at `path`.
/// \throw IoError naming the path and the reason.
void write_file_atomically(const std::string& path, std::string_view content);

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
