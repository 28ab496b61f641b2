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
#include "cw4d/complex/text.hpp"

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
      throw IoError("cannot write " + quote_user_text(path) + ": " + reason(errno));
    }
    done += static_cast<std::size_t>(n);
  }
}

// An existing output that is not a regular file (a device such as /dev/null or /dev/stdout, a
// FIFO), opened to be written through, never replaced. A FIFO nobody reads is refused instead of
// waiting. \return a blocking descriptor
int open_through(const std::string& path) {
  int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int err = errno;
    throw IoError("cannot write '" + path +
                  "': " + (err == ENXIO ? std::string("no process is reading it") : reason(err)));
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

// Writes `content` into fd and closes it. \throw IoError naming `path`
void write_and_close(int fd, std::string_view content, const std::string& path) {
  try {
    write_all(fd, content, path);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0 && errno != EINTR)
    throw IoError("cannot write " + quote_user_text(path) + ": " + reason(errno));
}

void write_through(const std::string& path, std::string_view content) {
  write_and_close(open_through(path), content, path);
}

struct Target {
  std::string path;      // where the rename goes (a symbolic link's target)
  bool through = false;  // an existing device or FIFO: write into it
};

// The one rule for every output path (single files, groups, sweep layers, frames): a new name
// or a regular file is replaced by a rename; a symbolic link is followed (the regular file it
// names is replaced and the link kept, a device or FIFO it names is written into); a device or
// FIFO is written into, never replaced; a directory, a socket and a symbolic link to nothing are
// refused. Replacing anything but a regular file would destroy what the user pointed us at.
Target resolve(const std::string& path) {
  const fs::path target(path);
  if (target.filename().empty())
    throw IoError("cannot write " + quote_user_text(path) + ": not a file name");
  struct stat lst {};
  if (::lstat(path.c_str(), &lst) != 0) return {path, false};  // new (or failing later)
  const auto refuse = [&](const std::string& why) -> Target {
    throw IoError("cannot write " + quote_user_text(path) + ": " + why);
  };
  struct stat st = lst;
  if (S_ISLNK(lst.st_mode)) {
    if (::stat(path.c_str(), &st) != 0)
      return refuse(errno == ELOOP ? "it is a loop of symbolic links"
                                   : "it is a symbolic link to a missing file");
  }
  const std::string link = S_ISLNK(lst.st_mode) ? "a symbolic link to " : "";
  if (S_ISDIR(st.st_mode)) return refuse(link.empty() ? "it is a directory" : link + "a directory");
  if (S_ISSOCK(st.st_mode))
    return refuse("it is " + (link.empty() ? "a socket" : link + "a socket"));
  if (!S_ISREG(st.st_mode)) return {path, true};
  if (S_ISLNK(lst.st_mode)) {
    // A symbolic link to a regular file: replace the file it names, keep the link.
    std::error_code ec;
    const fs::path real = fs::canonical(target, ec);
    if (ec) return refuse(ec.message());
    return {real.string(), false};
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
    throw IoError("cannot write " + quote_user_text(shown) + ": directory " +
                  quote_user_text(dir.string()) + " does not exist");
  static std::atomic<unsigned> counter{0};
  fs::path tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 64 && fd < 0; ++attempt) {
    tmp = dir / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                 std::to_string(counter++));
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) throw IoError("cannot write " + quote_user_text(shown) + ": " + reason(errno));
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
    throw IoError("cannot write " + quote_user_text(shown) + ": " + reason(err));
  }
  return tmp;
}

// Renames the temporary file over `path`; on failure removes it. \throw IoError
void rename_into_place(const fs::path& tmp, const std::string& shown, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError("cannot write " + quote_user_text(shown) + ": " + ec.message());
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
  rename_into_place(write_temporary(path, t.path, content, guard), path, t.path);
}

namespace {

// Descriptors of the devices and FIFOs of a group, opened before anything is renamed so that a
// FIFO nobody reads stops the group before it is half replaced.
struct ThroughFds {
  std::vector<int> fds;
  ~ThroughFds() {
    for (int fd : fds)
      if (fd >= 0) ::close(fd);
  }
  void open_all(const std::vector<std::string>& paths, const std::vector<Target>& targets) {
    fds.assign(paths.size(), -1);
    for (std::size_t i = 0; i < paths.size(); ++i)
      if (targets[i].through) fds[i] = open_through(paths[i]);
  }
  void write(std::size_t i, std::string_view content, const std::string& path) {
    const int fd = fds[i];
    fds[i] = -1;
    write_and_close(fd, content, path);
  }
};

std::string read_whole(const fs::path& path, const std::string& shown) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError("cannot write " + quote_user_text(shown) + ": " + reason(errno));
  std::string out;
  char buf[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      throw IoError("cannot write " + quote_user_text(shown) + ": " + reason(err));
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return out;
}

}  // namespace

void write_files_atomically(const std::vector<FileContent>& files) {
  // Every file is first written completely to a temporary; a failure there (a full disk, a bad
  // path, a FIFO nobody reads) leaves the previous versions of the whole group untouched.
  std::vector<Target> targets;
  std::vector<std::string> paths;
  for (const auto& f : files) {
    targets.push_back(resolve(f.path));
    paths.push_back(f.path);
  }
  std::vector<fs::path> temps(files.size());
  std::vector<TemporaryGuard> guards(files.size());
  const auto remove_temps = [&](std::size_t from) {
    for (std::size_t i = from; i < temps.size(); ++i) {
      std::error_code ignored;
      if (!temps[i].empty()) fs::remove(temps[i], ignored);
    }
  };
  ThroughFds through;
  try {
    for (std::size_t i = 0; i < files.size(); ++i)
      if (!targets[i].through)
        temps[i] = write_temporary(files[i].path, targets[i].path, files[i].content, guards[i]);
    through.open_all(paths, targets);
  } catch (...) {
    remove_temps(0);
    throw;
  }
  // Then the renames (and writes into devices), in order (companions before the file that
  // refers to them).
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      if (targets[i].through)
        through.write(i, files[i].content, files[i].path);
      else
        rename_into_place(temps[i], files[i].path, targets[i].path);
    } catch (...) {
      remove_temps(i + 1);
      throw;
    }
  }
}

// --- StagedFiles -------------------------------------------------------------------------------

StagedFiles::StagedFiles(const std::string& directory, const std::string& stem)
    : directory_(directory.empty() ? std::string(".") : directory) {
  std::error_code ec;
  if (!fs::is_directory(directory_, ec))
    throw IoError("cannot write into " + quote_user_text(directory_) + ": it is not a directory");
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 64; ++attempt) {
    const fs::path folder =
        fs::path(directory_) /
        ("." + stem + ".staging." + std::to_string(::getpid()) + "." + std::to_string(counter++));
    if (::mkdir(folder.c_str(), 0777) == 0) {
      folder_ = folder.string();
      guard_ = TemporaryGuard(folder_, true);
      return;
    }
    if (errno != EEXIST)
      throw IoError("cannot write into " + quote_user_text(directory_) + ": cannot create '" +
                    folder.string() + "': " + reason(errno));
  }
  throw IoError("cannot write into " + quote_user_text(directory_) +
                ": no free staging folder name");
}

StagedFiles::~StagedFiles() {
  discard();
}

void StagedFiles::discard() noexcept {
  if (folder_.empty()) return;
  std::error_code ignored;
  fs::remove_all(folder_, ignored);
  guard_.release();
  folder_.clear();
}

std::string StagedFiles::staged(const std::string& name) const {
  return (fs::path(folder_) / name).string();
}

std::string StagedFiles::destination(const std::string& name) const {
  return (fs::path(directory_) / name).string();
}

void StagedFiles::commit(const std::vector<std::string>& names) {
  // Every destination is judged (and every device or FIFO opened) before the first file moves:
  // a directory, a socket or an unread FIFO at any name leaves the whole group as it was.
  std::vector<Target> targets;
  std::vector<std::string> paths;
  for (const auto& name : names) {
    paths.push_back(destination(name));
    targets.push_back(resolve(paths.back()));
  }
  ThroughFds through;
  through.open_all(paths, targets);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const fs::path from = staged(names[i]);
    if (targets[i].through) {
      through.write(i, read_whole(from, paths[i]), paths[i]);
      continue;
    }
    std::error_code ec;
    fs::rename(from, targets[i].path, ec);
    if (ec == std::errc::cross_device_link) {
      // A symbolic link to a file on another file system: a temporary beside that file.
      TemporaryGuard guard;
      rename_into_place(
          write_temporary(paths[i], targets[i].path, read_whole(from, paths[i]), guard), paths[i],
          targets[i].path);
    } else if (ec) {
      throw IoError("cannot write " + quote_user_text(paths[i]) + ": " + ec.message());
    }
  }
  discard();
}

void StagedFiles::commit_as_folder(const std::string& folder) {
  // Only a name that does not exist yet becomes the folder (nothing is replaced).
  struct stat st {};
  if (::lstat(folder.c_str(), &st) == 0)
    throw IoError("cannot write " + quote_user_text(folder) +
                  ": it appeared while the files were written");
  std::error_code ec;
  fs::rename(folder_, folder, ec);
  if (ec) throw IoError("cannot write " + quote_user_text(folder) + ": " + ec.message());
  guard_.release();
  folder_.clear();
}

}  // namespace cw4d
