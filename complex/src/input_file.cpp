#include "cw4d/complex/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "cw4d/complex/error.hpp"

namespace cw4d {

namespace {

std::string too_large(std::uintmax_t size, std::uintmax_t limit) {
  return "file of " + std::to_string(size) + " bytes is larger than the " + std::to_string(limit) +
         " bytes cw4d reads";
}

// The checks on an open file's status. \throw ParseError
std::uintmax_t check_status(const std::string& path, const struct stat& st, std::uintmax_t limit) {
  if (S_ISDIR(st.st_mode)) throw ParseError(path, 0, "cannot read: is a directory");
  if (!S_ISREG(st.st_mode))
    throw ParseError(path, 0, "cannot read: not a regular file (a device, FIFO or socket)");
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > limit) throw ParseError(path, 0, too_large(size, limit));
  return size;
}

[[noreturn]] void cannot_open(const std::string& path, int err) {
  throw ParseError(path, 0,
                   err == ENOENT ? "cannot open: file not found"
                                 : std::string("cannot open: ") + std::strerror(err));
}

}  // namespace

std::uintmax_t check_input_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) cannot_open(path, errno);
  return check_status(path, st, max_input_file_bytes);
}

std::string read_input_file(const std::string& path, std::uintmax_t max_bytes) {
  const std::uintmax_t limit = std::min(max_bytes, max_input_file_bytes);
  // Opened without blocking (a FIFO would otherwise wait for a writer), then checked on the
  // open descriptor, so that the file read is the one checked.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) cannot_open(path, errno);
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw ParseError(path, 0, std::string("cannot read: ") + std::strerror(errno));
  const std::uintmax_t size = check_status(path, st, limit);
  std::string text;
  text.resize(static_cast<std::size_t>(size));
  std::size_t got = 0;
  while (true) {
    if (got == text.size()) {
      // The file may have grown since fstat: read on, up to the limit.
      if (text.size() >= limit) {
        char probe;
        const ssize_t n = ::read(fd, &probe, 1);
        if (n > 0) throw ParseError(path, 0, too_large(text.size() + 1, limit));
        if (n == 0) break;
        if (errno == EINTR) continue;
        throw ParseError(path, 0, std::string("read error: ") + std::strerror(errno));
      }
      text.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(limit, text.size() + 65536)));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw ParseError(path, 0, std::string("read error: ") + std::strerror(errno));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  text.resize(got);
  return text;
}

}  // namespace cw4d
