/// \file progress.hpp
/// \brief Progress: GDAL's terminal progress ("0...10...20...30...40...50...60...70...80...90...100 -
/// done.") for a job of known size, printed as it advances.
#pragma once

#include <cstddef>
#include <cstdio>

namespace geovor {

class Progress {
 public:
  /// A job of `total` steps, printed on `out` (null: nothing is printed).
  Progress(std::size_t total, std::FILE* out);
  /// `out` when it is a terminal and not `quiet`, else null: the progress of a job for a person who
  /// watches it, not for a log.
  static std::FILE* on_terminal(std::FILE* out, bool quiet);
  /// `done` of the total steps are done: prints the ticks (40 of 2.5 % each: a number every 10 %,
  /// dots between) reached since the last call.
  void advance(std::size_t done);
  /// Prints the ticks left and " - done." with a line end.
  void finish();

 private:
  std::size_t total_;
  std::FILE* out_;
  int printed_ = -1;
};

}  // namespace geovor
