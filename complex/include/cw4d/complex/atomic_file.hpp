#pragma once
// Writing outputs so that a failure leaves nothing half-written.
#include <string>
#include <string_view>

namespace cw4d {

/// Writes `content` to a temporary file next to `path`, flushes it, and renames it over `path`.
/// On any failure the temporary file is removed and nothing is left at `path`.
/// \throw IoError naming the path and the reason.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace cw4d
