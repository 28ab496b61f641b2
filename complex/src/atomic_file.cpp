#include "cw4d/complex/atomic_file.hpp"

#include <unistd.h>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cw4d/complex/error.hpp"

namespace cw4d {

namespace {

namespace fs = std::filesystem;

// Writes `content` to a new temporary file in the directory of `path` (so that renaming it over
// `path` is atomic) and returns its name. \throw IoError, with nothing left behind.
fs::path write_temporary(const std::string& path, std::string_view content) {
  const fs::path target(path);
  if (target.filename().empty()) throw IoError("cannot write '" + path + "': not a file name");
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(target, ec)) throw IoError("cannot write '" + path + "': it is a directory");
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
  return tmp;
}

// Renames the temporary file over `path`; on failure removes it. \throw IoError
void commit(const fs::path& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError("cannot write '" + path + "': " + ec.message());
  }
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view content) {
  commit(write_temporary(path, content), path);
}

void write_files_atomically(const std::vector<FileContent>& files) {
  // Every file is first written completely to a temporary; a failure there (a full disk, a bad
  // path) leaves the previous versions of the whole group untouched.
  std::vector<fs::path> temps;
  const auto remove_temps = [&](std::size_t from) {
    for (std::size_t i = from; i < temps.size(); ++i) {
      std::error_code ignored;
      fs::remove(temps[i], ignored);
    }
  };
  try {
    for (const auto& f : files) temps.push_back(write_temporary(f.path, f.content));
  } catch (...) {
    remove_temps(0);
    throw;
  }
  // Then the renames, in order (companions before the file that refers to them).
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      commit(temps[i], files[i].path);
    } catch (...) {
      remove_temps(i + 1);
      throw;
    }
  }
}

}  // namespace cw4d
