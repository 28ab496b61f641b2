#include "cw4d/complex/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <atomic>
#include <unistd.h>
#include <string>

#include "cw4d/complex/error.hpp"

namespace cw4d {

void write_file_atomically(const std::string& path, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.filename().empty()) throw IoError("cannot write '" + path + "': not a file name");
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
  // A unique temporary name in the same directory, so the rename is atomic.
  static std::atomic<unsigned> counter{0};
  fs::path tmp;
  for (int attempt = 0; attempt < 64; ++attempt) {
    tmp = dir / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                 std::to_string(counter++));
    if (!fs::exists(tmp, ec)) break;
  }
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("cannot write '" + path + "': " + std::strerror(errno));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw IoError("cannot write '" + path + "': write failed");
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError("cannot write '" + path + "': " + ec.message());
  }
}

void write_files_atomically(const std::vector<FileContent>& files) {
  std::size_t written = 0;
  try {
    for (; written < files.size(); ++written)
      write_file_atomically(files[written].path, files[written].content);
  } catch (...) {
    for (std::size_t i = 0; i < written; ++i) {
      std::error_code ignored;
      std::filesystem::remove(files[i].path, ignored);
    }
    throw;
  }
}

}  // namespace cw4d
