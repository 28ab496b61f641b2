#include "cw4d/complex/input_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cw4d/complex/error.hpp"

namespace cw4d {

std::string read_input_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status))
    throw ParseError(path, 0, "cannot open: " + (ec ? ec.message() : std::strerror(ENOENT)));
  if (fs::is_directory(status)) throw ParseError(path, 0, "cannot read: is a directory");
  if (!fs::is_regular_file(status))
    throw ParseError(path, 0, "cannot read: not a regular file (a device, FIFO or socket)");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw ParseError(path, 0, "cannot read: " + ec.message());
  if (size > max_input_file_bytes)
    throw ParseError(path, 0, "file of " + std::to_string(size) + " bytes is larger than the " +
                                  std::to_string(max_input_file_bytes) + " bytes cw4d reads");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string text;
  text.reserve(static_cast<std::size_t>(size));
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) throw ParseError(path, 0, "read error");
  if (text.size() > max_input_file_bytes)  // grew while being read
    throw ParseError(path, 0, "file is larger than the " + std::to_string(max_input_file_bytes) +
                                  " bytes cw4d reads");
  return text;
}

}  // namespace cw4d
