// Private to the io module: the bytes of an output file written in large blocks, with direct I/O
// (O_DIRECT) where its file system allows it, which spares the kernel's copy into the page cache
// (a fifth of the CPU time of a large cells file).
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace geovor {

/// Writes to a FILE it does not own. Failures throw DirectOutput::Failure (the caller's message
/// names the file); after one, the object must not be used again.
class DirectOutput {
 public:
  struct Failure {
    int err;  ///< errno, or 0 when the system said nothing
  };

  /// `file` is written with fwrite(), or (after enable_direct()) through its descriptor.
  /// write_back: start the write-back every 8 MB written (without waiting for it), so that a
  /// final fsync has little left to wait for.
  void attach(std::FILE* file, bool write_back) {
    file_ = file;
    write_back_ = write_back;
  }

  /// Direct I/O from now on, where the file system allows it: the bytes are staged in an aligned
  /// buffer and written in whole 4 KiB blocks with O_DIRECT; the last partial block is written
  /// normally by finish(). Any refusal (EINVAL) falls back to normal writes.
  void enable_direct();

  /// Writes n bytes (staged while direct I/O is on).
  void write(const char* data, std::size_t n);

  /// Writes what is staged, the last partial block too (direct I/O then ends). The FILE itself
  /// is neither flushed nor closed.
  void finish() {
    if (stage_ != nullptr) write_stage(true);
  }

 private:
  static constexpr std::size_t kWriteBackEvery = std::size_t{8} << 20;
  static constexpr std::size_t kDirectBlock = 4096, kStageSize = std::size_t{4} << 20;

  void disable_direct();
  void write_fd(const char* data, std::size_t n);
  void write_stage(bool all);

  std::FILE* file_ = nullptr;
  bool write_back_ = false;
  std::size_t unsynced_ = 0;  // bytes written since the last write-back request
  struct FreeAligned {
    void operator()(char* p) const { std::free(p); }
  };
  std::unique_ptr<char, FreeAligned> stage_;  // the bytes not yet written (fd I/O)
  std::size_t staged_ = 0;
  bool direct_ = false;  // O_DIRECT is on
};

}  // namespace geovor
