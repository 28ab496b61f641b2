#include "cw4d/complex/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sys/syscall.h>
#endif
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>

#include "cw4d/complex/error.hpp"

namespace cw4d {

namespace {

namespace fs = std::filesystem;

// --- temporaries removed on SIGINT / SIGTERM ---------------------------------------------------
//
// Every temporary file or folder is entered in a fixed table while it exists; the signal handler
// (which may only make async-signal-safe calls) unlinks what the table holds, then lets the
// signal end the process as it would have.

constexpr std::size_t kSlots = 64;
constexpr std::size_t kPathMax = 4096;

struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 a file, 3 a folder (files inside)
  char path[kPathMax];
};
std::array<Slot, kSlots> g_slots;

void remove_folder_in_handler(const char* path) {
#if defined(__linux__) && !defined(__EMSCRIPTEN__)
  // getdents64 is the async-signal-safe way to list a folder (opendir/readdir allocate).
  const int dir = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    alignas(8) char buf[4096];
    while (true) {
      const long n = ::syscall(SYS_getdents64, dir, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        // struct linux_dirent64: ino (8), off (8), reclen (2), type (1), name.
        unsigned short reclen;
        std::memcpy(&reclen, buf + off + 16, sizeof reclen);
        const char* name = buf + off + 19;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(dir, name, 0);
        off += reclen;
      }
    }
    ::close(dir);
  }
#endif
  ::rmdir(path);  // elsewhere only an empty folder goes
}

extern "C" void remove_temporaries_and_die(int sig) {
  for (Slot& s : g_slots) {
    const int state = s.state.load();
    if (state == 2) ::unlink(s.path);
    if (state == 3) remove_folder_in_handler(s.path);
  }
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_handlers_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      ::sigaction(sig, nullptr, &old);
      if (old.sa_handler != SIG_DFL) continue;  // ignored, or handled by the program
      struct sigaction sa {};
      sa.sa_handler = remove_temporaries_and_die;
      sigemptyset(&sa.sa_mask);
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

}  // namespace

TemporaryGuard::TemporaryGuard(const std::string& path, bool folder) {
  install_handlers_once();
  // A path that does not fit stays unguarded (it is removed normally, just not on a signal).
  if (path.size() >= kPathMax) return;
  for (std::size_t i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(folder ? 3 : 2);
      slot_ = static_cast<int>(i);
      return;
    }
  }
}

TemporaryGuard::~TemporaryGuard() {
  release();
}

void TemporaryGuard::release() {
  if (slot_ >= 0) g_slots[static_cast<std::size_t>(slot_)].state.store(0);
  slot_ = -1;
}

namespace {

std::string reason(int err) {
  return err == ENOSPC ? "no space left on the device" : std::strerror(err);
}

// Writes all of `content` to fd. \throw IoError naming `path`
void write_all(int fd, std::string_view content, const std::string& path) {
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError("cannot write '" + path + "': " + reason(errno));
    }
    done += static_cast<std::size_t>(n);
  }
}

// An existing output that is not a regular file (a device such as /dev/null or /dev/stdout, a
// FIFO): written through, never replaced. A FIFO nobody reads is refused instead of waiting.
void write_through(const std::string& path, std::string_view content) {
  int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int err = errno;
    throw IoError("cannot write '" + path +
                  "': " + (err == ENXIO ? std::string("no process is reading it") : reason(err)));
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  try {
    write_all(fd, content, path);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0 && errno != EINTR)
    throw IoError("cannot write '" + path + "': " + reason(errno));
}

struct Target {
  std::string path;      // where the rename goes (a symbolic link's target)
  bool through = false;  // an existing device or FIFO: write into it
};

Target resolve(const std::string& path) {
  const fs::path target(path);
  if (target.filename().empty()) throw IoError("cannot write '" + path + "': not a file name");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw IoError("cannot write '" + path + "': it is a directory");
    if (!S_ISREG(st.st_mode)) return {path, true};
    // A symbolic link to a regular file: replace the file it names, keep the link.
    std::error_code ec;
    const fs::path real = fs::canonical(target, ec);
    if (!ec && real != fs::absolute(target)) return {real.string(), false};
  }
  return {path, false};
}

// Writes `content` to a new temporary file in the directory of `path` (so that renaming it over
// `path` is atomic) and returns its name. \throw IoError, with nothing left behind.
fs::path write_temporary(const std::string& shown, const std::string& path,
                         std::string_view content, TemporaryGuard& guard) {
  const fs::path target(path);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError("cannot write '" + shown + "': directory '" + dir.string() + "' does not exist");
  static std::atomic<unsigned> counter{0};
  fs::path tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 64 && fd < 0; ++attempt) {
    tmp = dir / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                 std::to_string(counter++));
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) throw IoError("cannot write '" + shown + "': " + reason(errno));
  guard = TemporaryGuard(tmp.string(), false);
  try {
    write_all(fd, content, shown);
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0 && errno != EINTR) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw IoError("cannot write '" + shown + "': " + reason(err));
  }
  return tmp;
}

// Renames the temporary file over `path`; on failure removes it. \throw IoError
void commit(const fs::path& tmp, const std::string& shown, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError("cannot write '" + shown + "': " + ec.message());
  }
}

}  // namespace

TemporaryGuard& TemporaryGuard::operator=(TemporaryGuard&& other) noexcept {
  if (this != &other) {
    release();
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

void write_file_atomically(const std::string& path, std::string_view content) {
  const Target t = resolve(path);
  if (t.through) return write_through(path, content);
  TemporaryGuard guard;
  commit(write_temporary(path, t.path, content, guard), path, t.path);
}

void write_files_atomically(const std::vector<FileContent>& files) {
  // Every file is first written completely to a temporary; a failure there (a full disk, a bad
  // path) leaves the previous versions of the whole group untouched.
  std::vector<Target> targets;
  for (const auto& f : files) targets.push_back(resolve(f.path));
  std::vector<fs::path> temps(files.size());
  std::vector<TemporaryGuard> guards(files.size());
  const auto remove_temps = [&](std::size_t from) {
    for (std::size_t i = from; i < temps.size(); ++i) {
      std::error_code ignored;
      if (!temps[i].empty()) fs::remove(temps[i], ignored);
    }
  };
  try {
    for (std::size_t i = 0; i < files.size(); ++i)
      if (!targets[i].through)
        temps[i] = write_temporary(files[i].path, targets[i].path, files[i].content, guards[i]);
  } catch (...) {
    remove_temps(0);
    throw;
  }
  // Then the renames (and writes into devices), in order (companions before the file that
  // refers to them).
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      if (targets[i].through)
        write_through(files[i].path, files[i].content);
      else
        commit(temps[i], files[i].path, targets[i].path);
    } catch (...) {
      remove_temps(i + 1);
      throw;
    }
  }
}

}  // namespace cw4d
