#include "geovor/layers/id_lists.hpp"

#include <algorithm>

#include "geovor/core/parallel.hpp"
#include "geovor/io/json_text.hpp"

namespace geovor {
namespace {

// Whether append_json_string() escapes nothing in `id` (it may replace bytes that are not UTF-8,
// which need no second escaping either).
bool plain_element(std::string_view id) {
  return std::none_of(id.begin(), id.end(),
                      [](char c) { return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20; });
}

}  // namespace

void append_id_list_element(std::string& out, std::string_view id) { append_json_string(out, id); }

void append_escaped_id_list_element(std::string& out, std::string_view id) {
  std::string element, escaped;
  append_id_list_element(element, id);
  append_json_string(escaped, element);
  out.append(escaped, 1, escaped.size() - 2);
}

CellIdTexts make_cell_id_texts(const SiteTable& table, unsigned threads) {
  const std::size_t n = table.sites.size();
  const unsigned slices = static_cast<unsigned>(std::clamp<std::size_t>(n / 4096, 1, thread_count(threads)));
  CellIdTexts texts;
  texts.storage.resize(slices);
  texts.text.resize(n);
  texts.element.resize(n);
  // Slice i fills storage[i] with rows [n i / slices, n (i + 1) / slices).
  auto make_slice = [&](unsigned slice) {
    const std::size_t begin = n * slice / slices, end = n * (slice + 1) / slices;
    std::string& out = texts.storage[slice];
    out.reserve(64);  // on the heap from the start: moving `texts` keeps the views valid
    std::vector<std::size_t> ends;  // the views come once `out` stops moving
    ends.reserve(2 * (end - begin));
    for (std::size_t row = begin; row < end; ++row) {
      const std::string& id = table.sites[row].id;
      const std::size_t at = out.size();
      append_json_string(out, id);
      const std::size_t split = out.size();
      if (plain_element(id)) {
        // The quotes become \": \" + the id as just written without its closing quote + \".
        out += '\\';
        out.append(out, at, split - 1 - at);  // (appending part of itself is well-defined)
        out += "\\\"";
      } else {
        append_escaped_id_list_element(out, id);
      }
      ends.push_back(split);
      ends.push_back(out.size());
    }
    const std::string_view all(out);
    for (std::size_t row = begin, k = 0, from = 0; row < end; ++row, k += 2) {
      texts.text[row] = all.substr(from, ends[k] - from);
      texts.element[row] = all.substr(ends[k], ends[k + 1] - ends[k]);
      from = ends[k + 1];
    }
  };
  parallel_for(slices, slices, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t slice = begin; slice < end; ++slice) make_slice(static_cast<unsigned>(slice));
  });
  return texts;
}

}  // namespace geovor
