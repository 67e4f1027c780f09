#include "io/direct_output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace geovor {

void DirectOutput::enable_direct() {
  const int fd = ::fileno(file_);
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags == -1 || ::fcntl(fd, F_SETFL, flags | O_DIRECT) != 0) return;
  stage_.reset(static_cast<char*>(std::aligned_alloc(kDirectBlock, kStageSize)));
  if (stage_ == nullptr) {
    disable_direct();
    return;
  }
  direct_ = true;
}

void DirectOutput::disable_direct() {
  const int fd = ::fileno(file_);
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags != -1) ::fcntl(fd, F_SETFL, flags & ~O_DIRECT);
  direct_ = false;
}

// Writes n bytes to the file's descriptor (whole blocks while direct_).
void DirectOutput::write_fd(const char* data, std::size_t n) {
  const int fd = ::fileno(file_);
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      if (errno == EINVAL && direct_) {
        disable_direct();
        continue;
      }
      throw Failure{errno};
    }
    data += w, n -= static_cast<std::size_t>(w);
    if (n % kDirectBlock != 0 && direct_) disable_direct();  // a short write broke the alignment
  }
}

// Writes the staged bytes: the whole blocks, and the rest too if `all` (then direct I/O ends).
void DirectOutput::write_stage(bool all) {
  const std::size_t blocks = staged_ / kDirectBlock * kDirectBlock;
  write_fd(stage_.get(), blocks);
  std::memmove(stage_.get(), stage_.get() + blocks, staged_ - blocks);
  staged_ -= blocks;
  if (all && staged_ > 0) {
    if (direct_) disable_direct();
    write_fd(stage_.get(), staged_);
    staged_ = 0;
  }
}

void DirectOutput::write(const char* data, std::size_t n) {
  if (stage_ != nullptr) {
    while (n > 0) {
      const std::size_t k = std::min(n, kStageSize - staged_);
      std::memcpy(stage_.get() + staged_, data, k);
      staged_ += k, data += k, n -= k;
      if (staged_ == kStageSize) write_stage(false);
    }
    return;
  }
  errno = 0;
  if (std::fwrite(data, 1, n, file_) != n) throw Failure{errno};
  unsynced_ += n;
  if (unsynced_ >= kWriteBackEvery && write_back_) {
    unsynced_ = 0;
    if (std::fflush(file_) != 0) throw Failure{errno};
    ::sync_file_range(::fileno(file_), 0, 0, SYNC_FILE_RANGE_WRITE);  // a hint: errors surface in fsync
  }
}

}  // namespace geovor
