/// \file id_lists.hpp
/// \brief The text of site ids in the cell layer's `ids` and `neighbors` fields: JSON arrays of
/// strings (JSON fields: arrays in GeoJSON, JSON text in a String field of the JSON subtype
/// elsewhere, portable to every format without list field types), and each row's id made once
/// as JSON text for the GeoJSON writer's fast path.
///
/// An element of a list is the id as append_json_string() (io/json_text.hpp) writes it: the one
/// JSON string escaper of geovor, so the lists are valid JSON (UTF-8, bytes that are not replaced
/// by U+FFFD) in every format.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// Appends `id` as an element of an ids/neighbors list, quotes included (the file comment).
void append_id_list_element(std::string& out, std::string_view id);

/// Each input row's id as the cell layer's GeoJSON output writes it: `text[row]`, the id as a
/// JSON string (append_json_string(): site_id, the feature id, and an element of the lists).
/// Views into `storage`, whose strings are on the heap, so moving a CellIdTexts keeps them valid.
struct CellIdTexts {
  std::vector<std::string> storage;
  std::vector<std::string_view> text;
};

/// The CellIdTexts of table's rows, made on `threads` threads (0: one per core; one per 4,096
/// rows at most). write_cell_layer() makes them itself when not given them: this is for making
/// them earlier, e.g. while the triangulation is built.
CellIdTexts make_cell_id_texts(const SiteTable& table, unsigned threads);

}  // namespace geovor
