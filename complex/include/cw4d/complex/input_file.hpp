#pragma once
// Reading whole input files (models, scenes) defensively: only regular files, of bounded size,
// so that a hostile path (/dev/zero, a FIFO, a directory, a 100 GB file) gives one clear error
// instead of a hang or an exhausted memory.
#include <cstdint>
#include <string>

namespace cw4d {

/// The largest input file read_input_file accepts (1 GiB).
inline constexpr std::uintmax_t max_input_file_bytes = std::uintmax_t{1} << 30;

/// The checks read_input_file makes, for readers that open the file themselves (OpenMesh):
/// \return its size. \throw ParseError(path, 0, reason) as read_input_file.
std::uintmax_t check_input_file(const std::string& path);

/// The whole content of the regular file at `path`.
/// \throw ParseError(path, 0, reason) when it does not exist, is not a regular file (a
///        directory, a device, a FIFO), is larger than `max_bytes` (at most
///        max_input_file_bytes) or cannot be read.
std::string read_input_file(const std::string& path,
                            std::uintmax_t max_bytes = max_input_file_bytes);

}  // namespace cw4d
