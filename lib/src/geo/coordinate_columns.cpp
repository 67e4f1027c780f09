#include "geovor/geo/coordinate_columns.hpp"

#include <algorithm>
#include <array>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geo/trim.hpp"

namespace geovor {
namespace {

constexpr std::array<std::string_view, 19> kUnitWords = {
    "deg", "degs", "degree", "degrees", "dd", "decimal", "dec", "wgs", "wgs84", "84",
    "1984", "wgs1984", "epsg", "4326", "m", "metres", "meters", "ft", "feet"};

bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool is_upper(char c) { return c >= 'A' && c <= 'Z'; }
bool is_alnum(char c) { return is_letter(c) || (c >= '0' && c <= '9'); }

// The name's words, lower case, without what is bracketed and without unit words.
std::vector<std::string> words_of(std::string_view name) {
  std::vector<std::string> words;
  std::string word;
  int depth = 0;
  auto end_word = [&] {
    if (!word.empty() && std::find(kUnitWords.begin(), kUnitWords.end(), word) == kUnitWords.end())
      words.push_back(word);
    word.clear();
  };
  char prev = 0;
  for (const char c : name) {
    if (c == '(' || c == '[' || c == '{') {
      end_word();
      ++depth;
    } else if (c == ')' || c == ']' || c == '}') {
      end_word();
      depth = std::max(0, depth - 1);
    } else if (depth > 0) {
      // bracketed: a unit or a note
    } else if (!is_alnum(c)) {
      end_word();
    } else {
      // camelCase: a capital after a small letter starts a word (decimalLatitude, LatDD).
      if (is_upper(c) && prev >= 'a' && prev <= 'z') end_word();
      word += ascii_lower(std::string_view(&c, 1))[0];
    }
    prev = depth > 0 ? 0 : c;
  }
  end_word();
  return words;
}

bool one_of(const std::string& w, std::initializer_list<std::string_view> names) {
  return std::find(names.begin(), names.end(), w) != names.end();
}

std::string axis_name(Axis axis) { return axis == Axis::Latitude ? "latitude" : "longitude"; }

}  // namespace

int coordinate_name_rank(std::string_view name, Axis axis, bool projected) {
  const std::vector<std::string> w = words_of(name);
  if (w.empty()) return 0;
  const bool lat = axis == Axis::Latitude;
  // Rank 1: the coordinate alone.
  if (w.size() == 1 && (lat ? one_of(w[0], {"lat", "latitude"}) : one_of(w[0], {"lon", "lng", "long", "longitude"})))
    return 1;
  // The planar axis: y/x alone or with point/coord (POINT_Y, ycoord, y_coord, coord_y).
  const std::string_view planar = lat ? "y" : "x";
  const std::string_view planar_word = lat ? "ycoord" : "xcoord";
  const bool is_planar = (w.size() == 1 && (w[0] == planar || w[0] == planar_word)) ||
                         (w.size() == 2 && ((w[0] == planar && one_of(w[1], {"coord", "coordinate"})) ||
                                            (w[1] == planar && one_of(w[0], {"point", "coord", "coordinate"}))));
  if (projected) {
    if (is_planar) return 1;
    if (w.size() == 1 && (lat ? one_of(w[0], {"northing", "north"}) : one_of(w[0], {"easting", "east"}))) return 1;
  }
  // Rank 2: the coordinate after other words (stop_lat, pickup_latitude); not "long" (NAME_LONG).
  if (w.size() > 1 && (lat ? one_of(w.back(), {"lat", "latitude"}) : one_of(w.back(), {"lon", "lng", "longitude"})))
    return 2;
  if (is_planar) return 3;
  return 0;
}

int detect_coordinate_column(const std::vector<std::string>& columns, Axis axis, bool projected,
                             const std::string& source, std::string_view option_prefix) {
  int best_rank = 0;
  std::vector<int> best;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const int rank = coordinate_name_rank(columns[i], axis, projected);
    if (rank == 0 || (best_rank != 0 && rank > best_rank)) continue;
    if (rank < best_rank || best_rank == 0) best.clear();
    best_rank = rank;
    best.push_back(static_cast<int>(i));
  }
  if (best.empty()) return -1;
  if (best.size() > 1) {
    std::string names;
    for (const int c : best) names += (names.empty() ? "'" : ", '") + columns[static_cast<std::size_t>(c)] + "'";
    const std::string option = "--" + std::string(option_prefix) + (axis == Axis::Latitude ? "lat-field" : "lon-field");
    throw Error(ErrorCode::BadData, source + ": ambiguous " + axis_name(axis) + " column: " + names +
                                        " are equally likely; choose one with " + option);
  }
  return best[0];
}

std::size_t check_header_names(const std::vector<std::string>& columns, const std::string& source) {
  std::size_t trailing_empty = 0;
  while (trailing_empty < columns.size() && trim(columns[columns.size() - 1 - trailing_empty]).empty())
    ++trailing_empty;
  const std::size_t named = columns.size() - trailing_empty;
  for (std::size_t i = 0; i < named; ++i)
    if (trim(columns[i]).empty())
      throw Error(ErrorCode::BadData, source + ": header: column " + std::to_string(i + 1) +
                                          " has no name; every column but empty trailing ones needs one");
  // Sorted by folded name, then position: a repeat follows its first use (n log n for wide headers).
  std::vector<std::pair<std::string, std::size_t>> names;
  names.reserve(named);
  for (std::size_t i = 0; i < named; ++i) names.emplace_back(ascii_lower(trim(columns[i])), i);
  std::sort(names.begin(), names.end());
  std::size_t first = 0, repeat = 0;  // the repeat found earliest in the header, and what it repeats
  for (std::size_t k = 1; k < names.size(); ++k)
    if (names[k].first == names[k - 1].first && (repeat == 0 || names[k].second < repeat) &&
        (k < 2 || names[k - 2].first != names[k].first)) {  // the name's first repeat
      repeat = names[k].second;
      first = names[k - 1].second;
    }
  if (repeat != 0)
    throw Error(ErrorCode::BadData, source + ": header: column " + std::to_string(repeat + 1) + " '" + columns[repeat] +
                                        "' has the same name as column " + std::to_string(first + 1) + " '" +
                                        columns[first] + "'; rename one of them");
  return trailing_empty;
}

}  // namespace geovor
