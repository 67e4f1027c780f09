#include "geovor/core/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"

namespace geovor {

OutputFile::OutputFile(const std::string& path, bool overwrite)
    : path_(path), name_(path == "-" ? "<stdout>" : path), overwrite_(overwrite) {
  if (path == "-") {
    file_ = stdout;
    return;
  }
  if (check_output_target(path, overwrite) == OutputTargetState::Special) {  // a device or a FIFO: written in place
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) throw Error(ErrorCode::Io, path + ": cannot open: " + std::strerror(errno));
    return;
  }
  temp_ = TemporaryOutput(path, TemporaryOutput::Kind::File);
  file_ = temp_.take_stdio(path);
}

OutputFile::~OutputFile() {
  if (!committed_) discard();
}

void OutputFile::write(const char* data, std::size_t n) {
  if (file_ == nullptr) throw Error(ErrorCode::Io, name_ + ": the output failed earlier");
  if (n > 0 && std::fwrite(data, 1, n, file_) != n) fail("write error", errno);
  unsynced_ += n;
  if (unsynced_ >= kWriteBackEvery && temp_.active()) {
    unsynced_ = 0;
    flush();
    ::sync_file_range(::fileno(file_), 0, 0, SYNC_FILE_RANGE_WRITE);  // a hint: errors surface in fsync
  }
}

void OutputFile::flush() {
  if (file_ == nullptr) throw Error(ErrorCode::Io, name_ + ": the output failed earlier");
  if (std::fflush(file_) != 0 || std::ferror(file_)) fail("write error", errno);
}

void OutputFile::commit() {
  flush();
  if (!temp_.active()) {  // stdout or a device: nothing to rename
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
  temp_.commit(path_, overwrite_);  // never over a file that appeared meanwhile, unless overwriting
  committed_ = true;
}

void OutputFile::fail(const std::string& what, int err) {
  discard();
  throw Error(ErrorCode::Io, name_ + ": " + what + (err != 0 ? std::string(": ") + std::strerror(err) : ""));
}

void OutputFile::discard() noexcept {
  if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  file_ = nullptr;
  temp_.discard();
}

}  // namespace geovor
