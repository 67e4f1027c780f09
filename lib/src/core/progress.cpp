#include "geovor/core/progress.hpp"

#include <unistd.h>

namespace geovor {

Progress::Progress(std::size_t total, std::FILE* out) : total_(total), out_(out) {}

std::FILE* Progress::on_terminal(std::FILE* out, bool quiet) {
  return !quiet && out != nullptr && isatty(fileno(out)) ? out : nullptr;
}

void Progress::advance(std::size_t done) {
  if (out_ == nullptr || total_ == 0) return;
  const int step = static_cast<int>(done * 40 / total_);  // 40 ticks of 2.5 %, as GDAL prints
  while (printed_ < step) {
    ++printed_;
    if (printed_ % 4 == 0)
      std::fprintf(out_, "%d", printed_ / 4 * 10);
    else
      std::fputc('.', out_);
  }
}

void Progress::finish() {
  if (out_ == nullptr) return;
  advance(total_);
  std::fprintf(out_, " - done.\n");
}

}  // namespace geovor
