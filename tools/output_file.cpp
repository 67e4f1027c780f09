#include "output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "geovor/core/error.hpp"

namespace geovor::tools {
namespace {

std::atomic<unsigned> g_temp_counter{0};

}  // namespace

OutputFile::OutputFile(const std::string& path, bool overwrite)
    : path_(path), name_(path == "-" ? "<stdout>" : path) {
  if (path == "-") {
    file_ = stdout;
    return;
  }
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw Error(ErrorCode::Io, path + ": is a directory");
    if (!S_ISREG(st.st_mode)) {  // a device or a FIFO: written in place
      file_ = std::fopen(path.c_str(), "wb");
      if (file_ == nullptr) throw Error(ErrorCode::Io, path + ": cannot open: " + std::strerror(errno));
      return;
    }
    if (!overwrite) throw Error(ErrorCode::Io, path + ": exists; use --overwrite to replace it");
  }
  const std::filesystem::path target(path);
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name(".");
    name += target.filename().string();
    name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_temp_counter.fetch_add(1));
    const std::string temp = (dir / name).string();
    file_ = std::fopen(temp.c_str(), "wbx");  // "x": O_EXCL, never an existing file
    if (file_ != nullptr) {
      temp_ = temp;
      return;
    }
    if (errno != EEXIST)
      throw Error(ErrorCode::Io, path + ": cannot create the temporary file " + temp + ": " + std::strerror(errno));
  }
  throw Error(ErrorCode::Io, path + ": cannot find a free temporary file name");
}

OutputFile::~OutputFile() {
  if (!committed_) discard();
}

void OutputFile::write(const char* data, std::size_t n) {
  if (file_ == nullptr) throw Error(ErrorCode::Io, name_ + ": the output failed earlier");
  if (n > 0 && std::fwrite(data, 1, n, file_) != n) fail("write error", errno);
}

void OutputFile::flush() {
  if (file_ == nullptr) throw Error(ErrorCode::Io, name_ + ": the output failed earlier");
  if (std::fflush(file_) != 0 || std::ferror(file_)) fail("write error", errno);
}

void OutputFile::commit() {
  flush();
  if (temp_.empty()) {  // stdout or a device: nothing to rename
    if (file_ != stdout) {
      std::FILE* f = file_;
      file_ = nullptr;
      if (std::fclose(f) != 0) fail("write error", errno);
    }
    committed_ = true;
    return;
  }
  // Durable before it appears under its name; a full disk may only show here.
  if (::fsync(::fileno(file_)) != 0 && errno != EINVAL && errno != EROFS) fail("write error", errno);
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) fail("write error", errno);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail("cannot rename " + temp_ + " to it", errno);
  temp_.clear();
  committed_ = true;
}

void OutputFile::fail(const std::string& what, int err) {
  discard();
  throw Error(ErrorCode::Io, name_ + ": " + what + (err != 0 ? std::string(": ") + std::strerror(err) : ""));
}

void OutputFile::discard() noexcept {
  if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  file_ = nullptr;
  if (!temp_.empty()) std::remove(temp_.c_str());
  temp_.clear();
}

}  // namespace geovor::tools
