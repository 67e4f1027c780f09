/// @file
/// OutputFile: a text output (the nearest join's CSV, the cells' row report, the balanced sites)
/// that never leaves a half-written file: written under a temporary name next to the target and
/// renamed into place by commit() (the rules of output_target.hpp).
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

#include "geovor/core/output_target.hpp"

namespace geovor {

class OutputFile {
 public:
  /// Opens `path` for writing: "-" is stdout; an existing regular file is refused (Error(Io))
  /// unless `overwrite`; an existing device or FIFO (/dev/null, /dev/stdout) is written in place,
  /// since renaming over it would replace it; anything else gets a temporary file in the target's
  /// directory (geovor/core/output_target.hpp: a short name, removed on errors and on SIGINT,
  /// SIGTERM and SIGHUP).
  OutputFile(const std::string& path, bool overwrite);
  /// Removes the temporary file unless commit() succeeded.
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* get() const { return file_; }
  /// "<stdout>" or the path, for messages.
  const std::string& name() const { return name_; }
  /// Writes `n` bytes; Error(Io) naming the file and the reason if they cannot be written. Every
  /// kWriteBackEvery bytes to a temporary file, starts their write-back to the disk without
  /// waiting for it, so that commit()'s fsync has little left to wait for.
  void write(const char* data, std::size_t n);
  /// Flushes the buffer; Error(Io) on failure (a full disk), with the temporary file removed.
  void flush();
  /// Flushes, syncs, closes and renames the file into place, never over a file that appeared
  /// meanwhile unless `overwrite`; Error(Io) on failure (a full disk, "PATH: exists; use
  /// --overwrite to replace it"), with the temporary file removed.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& what, int err);
  void discard() noexcept;

  std::string path_, name_;
  bool overwrite_ = false;
  TemporaryOutput temp_;  // unless stdout or a device
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  static constexpr std::size_t kWriteBackEvery = std::size_t{8} << 20;
  std::size_t unsynced_ = 0;  // bytes written since the last write-back started
};

}  // namespace geovor
