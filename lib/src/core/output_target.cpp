#include "geovor/core/output_target.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int err) { return std::strerror(err); }

// ---------------------------------------------------------------------------------------------
// The registry of live temporaries, read by the signal handler: fixed storage, no allocation.
// An entry's state: 0 free, 1 being filled, 2 live, 3 being removed by the handler.

constexpr int kEntries = 64;
constexpr std::size_t kPathBytes = 4096;

struct Entry {
  std::atomic<int> state{0};
  bool directory = false;
  char path[kPathBytes];
};
Entry g_entries[kEntries];

std::atomic<unsigned> g_counter{0};

// getdents64's record (not declared by glibc).
struct LinuxDirent64 {
  unsigned long long d_ino;
  long long d_off;
  unsigned short d_reclen;
  unsigned char d_type;
  char d_name[1];
};

// Empties a directory (its files and empty subdirectories: what a GDAL driver leaves in its
// temporary directory) and removes it, with async-signal-safe calls only.
void remove_directory(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    // Removing entries while reading may skip some: passes until one removes nothing.
    for (int pass = 0; pass < 8; ++pass) {
      bool removed = false;
      ::lseek(fd, 0, SEEK_SET);
      for (;;) {
        const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
        if (n <= 0) break;
        for (long off = 0; off < n;) {
          const auto* d = reinterpret_cast<const LinuxDirent64*>(buf + off);
          off += d->d_reclen;
          const char* name = d->d_name;
          if (name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))) continue;
          if (::unlinkat(fd, name, 0) == 0 || ::unlinkat(fd, name, AT_REMOVEDIR) == 0) removed = true;
        }
      }
      if (!removed) break;
    }
    ::close(fd);
  }
  ::rmdir(path);
}

void on_signal(int sig) {
  remove_registered_temporaries();
  // End as the signal would have: its default action, delivered once the handler returns (the
  // signal is blocked while it runs) or at once where unblocked here.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  ::sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  sigset_t set;
  ::sigemptyset(&set);
  ::sigaddset(&set, sig);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  ::raise(sig);
  ::_exit(128 + sig);
}

std::atomic<bool> g_installed{false};

// A temporary name in `dir`: ".gv-PID-N.tmp".
fs::path temporary_name(const fs::path& dir) {
  return dir / (".gv-" + std::to_string(::getpid()) + "-" + std::to_string(g_counter.fetch_add(1)) + ".tmp");
}

// The identity of an output path, for same_output_file.
struct Identity {
  bool dash = false;
  bool exists = false;
  bool char_device = false;
  dev_t dev = 0;
  ino_t ino = 0;
  std::string canonical;  // when it does not exist
};

Identity identity_of(const std::string& path) {
  Identity id;
  struct stat st;
  if (path == "-") {
    id.dash = true;
    if (::fstat(STDOUT_FILENO, &st) == 0) id.exists = true;
  } else if (::stat(path.c_str(), &st) == 0) {
    id.exists = true;
  } else {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    id.canonical = ec ? fs::absolute(path, ec).lexically_normal().string() : p.string();
    return id;
  }
  if (id.exists) {
    id.dev = st.st_dev;
    id.ino = st.st_ino;
    id.char_device = S_ISCHR(st.st_mode);
  }
  return id;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::string output_exists(const std::string& path, const std::string& more) {
  return path + ": exists; use --overwrite to replace it" + more;
}

void refuse_existing_output(const std::string& path, bool overwrite) {
  if (path.empty() || path == "-" || overwrite) return;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) throw Error(ErrorCode::Io, output_exists(path));
}

OutputTargetState check_output_target(const std::string& path, bool overwrite) {
  if (path == "-") return OutputTargetState::Special;
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) return OutputTargetState::Absent;
  if (::stat(path.c_str(), &st) != 0) {  // a dangling symbolic link: an existing name
    if (!overwrite) throw Error(ErrorCode::Io, output_exists(path));
    return OutputTargetState::Absent;
  }
  if (S_ISDIR(st.st_mode)) throw Error(ErrorCode::Io, path + ": is a directory");
  // Renaming over a device or a FIFO would replace it (/dev/null, as root).
  if (!S_ISREG(st.st_mode)) return OutputTargetState::Special;
  if (!overwrite) throw Error(ErrorCode::Io, output_exists(path));
  return OutputTargetState::Regular;
}

// ---------------------------------------------------------------------------------------------

TemporaryOutput::TemporaryOutput(const std::string& target, Kind kind) : kind_(kind) {
  const fs::path t(target);
  const fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
  const char* what = kind == Kind::File ? "file" : "directory";
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path temp = temporary_name(dir);
    const int ok = kind == Kind::File
                       ? (fd_ = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_TRUNC | O_CLOEXEC, 0666))
                       : ::mkdir(temp.c_str(), 0700);
    if (ok >= 0) {
      path_ = temp.string();
      slot_ = register_temporary(path_.c_str(), kind == Kind::Directory);
      return;
    }
    const int err = errno;
    if (err != EEXIST) {
      throw Error(ErrorCode::Io, target + ": cannot create the temporary " + what + " " + temp.string() + ": " +
                                     errno_text(err));
    }
  }
  throw Error(ErrorCode::Io, target + ": cannot find a free temporary " + what + " name");
}

TemporaryOutput::~TemporaryOutput() { discard(); }

TemporaryOutput::TemporaryOutput(TemporaryOutput&& other) noexcept
    : path_(std::move(other.path_)), kind_(other.kind_), fd_(std::exchange(other.fd_, -1)),
      slot_(std::exchange(other.slot_, -1)) {
  other.path_.clear();
}

TemporaryOutput& TemporaryOutput::operator=(TemporaryOutput&& other) noexcept {
  if (this != &other) {
    discard();
    path_ = std::move(other.path_);
    other.path_.clear();
    kind_ = other.kind_;
    fd_ = std::exchange(other.fd_, -1);
    slot_ = std::exchange(other.slot_, -1);
  }
  return *this;
}

int TemporaryOutput::take_fd() { return std::exchange(fd_, -1); }

std::FILE* TemporaryOutput::take_stdio(const std::string& target) {
  const int fd = take_fd();
  std::FILE* file = ::fdopen(fd, "wb");
  if (file == nullptr) {
    const int err = errno;
    ::close(fd);
    discard();
    throw Error(ErrorCode::Io, target + ": cannot open the temporary file: " + errno_text(err));
  }
  return file;
}

void TemporaryOutput::commit(const std::string& target, bool overwrite) {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  const int err = rename_into_place(path_, target, overwrite);
  if (err != 0) {
    const std::string temp = path_;
    discard();
    if (err == EEXIST) throw Error(ErrorCode::Io, output_exists(target));
    throw Error(ErrorCode::Io, target + ": cannot rename " + temp + " to it: " + errno_text(err));
  }
  release();
}

void TemporaryOutput::release() noexcept {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  unregister_temporary(std::exchange(slot_, -1));
  path_.clear();
}

void TemporaryOutput::discard() noexcept {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  if (!path_.empty()) {
    if (kind_ == Kind::File) {
      ::unlink(path_.c_str());
    } else {
      std::error_code ec;
      fs::remove_all(path_, ec);
    }
  }
  unregister_temporary(std::exchange(slot_, -1));
  path_.clear();
}

// ---------------------------------------------------------------------------------------------

int rename_into_place(const std::string& from, const std::string& to, bool overwrite) noexcept {
  if (overwrite) return std::rename(from.c_str(), to.c_str()) == 0 ? 0 : errno;
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return 0;
  int err = errno;
  if (err != EINVAL && err != ENOSYS && err != ENOTSUP && err != EOPNOTSUPP) return err;
  // The file system refuses the flag: link() refuses an existing name just as atomically.
  if (::link(from.c_str(), to.c_str()) == 0) {
    ::unlink(from.c_str());
    return 0;
  }
  err = errno;
  if (err != EPERM && err != ENOTSUP && err != EOPNOTSUPP && err != EMLINK) return err;
  // No hard links either (FAT, some FUSE file systems): a check, then rename (not atomic).
  struct stat st;
  if (::lstat(to.c_str(), &st) == 0) return EEXIST;
  return std::rename(from.c_str(), to.c_str()) == 0 ? 0 : errno;
}

// ---------------------------------------------------------------------------------------------

bool same_output_file(const std::string& a, const std::string& b) {
  if (a == "-" && b == "-") return true;
  const Identity x = identity_of(a), y = identity_of(b);
  if (x.exists != y.exists) return false;
  if (x.exists) return x.dev == y.dev && x.ino == y.ino && !x.char_device;
  return !x.dash && !y.dash && x.canonical == y.canonical;
}

void check_distinct_outputs(const std::vector<NamedOutput>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].path.empty()) continue;
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      if (outputs[j].path.empty() || !same_output_file(outputs[i].path, outputs[j].path)) continue;
      throw Error(ErrorCode::InvalidArgument, outputs[i].option + " " + outputs[i].path + " and " + outputs[j].option +
                                                  " " + outputs[j].path +
                                                  " are the same file; give each output its own file");
    }
  }
}

// ---------------------------------------------------------------------------------------------

void install_output_cleanup() {
  if (g_installed.exchange(true)) return;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup: stays ignored
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    ::sigemptyset(&sa.sa_mask);
    ::sigaddset(&sa.sa_mask, SIGINT);  // one handler at a time in a thread
    ::sigaddset(&sa.sa_mask, SIGTERM);
    ::sigaddset(&sa.sa_mask, SIGHUP);
    sa.sa_flags = SA_RESTART;
    ::sigaction(sig, &sa, nullptr);
  }
}

int register_temporary(const char* path, bool directory) noexcept {
  const std::size_t n = std::strlen(path);
  if (n >= kPathBytes) return -1;
  for (int i = 0; i < kEntries; ++i) {
    int expected = 0;
    if (!g_entries[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_entries[i].path, path, n + 1);
    g_entries[i].directory = directory;
    g_entries[i].state.store(2, std::memory_order_release);
    return i;
  }
  return -1;
}

void unregister_temporary(int entry) noexcept {
  if (entry < 0 || entry >= kEntries) return;
  // State 3: the handler (on another thread) is removing it, and the process ends after that.
  for (int expected = 2; !g_entries[entry].state.compare_exchange_weak(expected, 0); expected = 2) {
    if (expected != 2 && expected != 3) return;
  }
}

void remove_registered_temporaries() noexcept {
  const int saved = errno;
  for (Entry& e : g_entries) {
    int expected = 2;
    if (!e.state.compare_exchange_strong(expected, 3, std::memory_order_acquire)) continue;
    if (e.directory)
      remove_directory(e.path);
    else
      ::unlink(e.path);
    e.state.store(2, std::memory_order_release);
  }
  errno = saved;
}

}  // namespace geovor
