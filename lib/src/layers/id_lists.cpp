#include "geovor/layers/id_lists.hpp"

#include <algorithm>

#include "geovor/core/parallel.hpp"
#include "geovor/io/json_text.hpp"

namespace geovor {

void append_id_list_element(std::string& out, std::string_view id) { append_json_string(out, id); }

CellIdTexts make_cell_id_texts(const SiteTable& table, unsigned threads) {
  const std::size_t n = table.sites.size();
  const unsigned slices = static_cast<unsigned>(std::clamp<std::size_t>(n / 4096, 1, thread_count(threads)));
  CellIdTexts texts;
  texts.storage.resize(slices);
  texts.text.resize(n);
  // Slice i fills storage[i] with rows [n i / slices, n (i + 1) / slices).
  auto make_slice = [&](unsigned slice) {
    const std::size_t begin = n * slice / slices, end = n * (slice + 1) / slices;
    std::string& out = texts.storage[slice];
    out.reserve(64);  // on the heap from the start: moving `texts` keeps the views valid
    std::vector<std::size_t> ends;  // the views come once `out` stops moving
    ends.reserve(end - begin);
    for (std::size_t row = begin; row < end; ++row) {
      append_json_string(out, table.sites[row].id);
      ends.push_back(out.size());
    }
    const std::string_view all(out);
    for (std::size_t row = begin, k = 0, from = 0; row < end; ++row, ++k) {
      texts.text[row] = all.substr(from, ends[k] - from);
      from = ends[k];
    }
  };
  parallel_for(slices, slices, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t slice = begin; slice < end; ++slice) make_slice(static_cast<unsigned>(slice));
  });
  return texts;
}

}  // namespace geovor
