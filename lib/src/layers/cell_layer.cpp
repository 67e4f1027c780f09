#include "geovor/layers/cell_layer.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/core/ascii.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/core/copy_short.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/layers/input_columns.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {
namespace {

constexpr std::array<const char*, 8> kOurFields = {"site_index", "site_id", "ids",        "n_rows",
                                                   "area_m2",    "area_sr", "n_vertices", "neighbors"};
constexpr std::array<FieldType, 8> kOurTypes = {FieldType::Integer64, FieldType::String, FieldType::String,
                                                FieldType::Integer64, FieldType::Real,   FieldType::Real,
                                                FieldType::Integer64, FieldType::String};
constexpr std::array<bool, 8> kOurJson = {false, false, true, false, false, false, false, true};
// Weighted sites (table.weighted): their radius follows the fields above.
constexpr const char* kWeightField = "weight_m";

// The number of our fields before the input columns.
std::size_t our_fields(const SiteTable& table) { return kOurFields.size() + (table.weighted); }

// What the cells' properties need besides the geometry, made from the table, the report and the
// triangulation only (so while the diagram and the cells' geometry are built).
struct SiteTexts {
  SiteRows rows;
  // Without an encoder: site s's id (its first row's) as a list element,
  // element_text[element_end[s - 1] .. element_end[s]) (made once: the neighbour lists name
  // every site about six times).
  std::string element_text;
  std::vector<std::size_t> element_end;
  // With an encoder: site s's id as the encoder writes it (site_text, also its element in the
  // lists), so that a cell reaches its neighbours' text in one step.
  CellIdTexts made;  // when the caller gave no id texts
  std::vector<std::string_view> site_text;
  std::vector<SiteId> order;  // the sites with a cell, in id order

  std::string_view element(SiteId s) const {
    const std::size_t from = s == 0 ? 0 : element_end[s - 1];
    return std::string_view(element_text).substr(from, element_end[s] - from);
  }
};

SiteTexts make_site_texts(const SiteTable& table, const BuildReport& report, const SphericalDelaunay& dt,
                          bool encoded, const CellIdTexts* id_texts) {
  const std::size_t num_sites = dt.site_capacity();
  SiteTexts t;
  t.rows = rows_of_sites(report, num_sites);
  if (!encoded) {
    t.element_end.resize(num_sites);
    for (SiteId s = 0; s < num_sites; ++s) {
      if (t.rows.first(s) != kNoIndex) append_id_list_element(t.element_text, table.sites[t.rows.first(s)].id);
      t.element_end[s] = t.element_text.size();
    }
  } else {
    if (id_texts == nullptr || id_texts->text.size() != table.sites.size()) {
      t.made = make_cell_id_texts(table, 1);
      id_texts = &t.made;
    }
    t.site_text.resize(num_sites);
    for (SiteId s = 0; s < num_sites; ++s)
      if (t.rows.first(s) != kNoIndex) t.site_text[s] = id_texts->text[t.rows.first(s)];
  }
  for (SiteId s = 0; s < num_sites; ++s)
    if (dt.is_live(s) || dt.is_hidden(s)) t.order.push_back(s);  // a hidden site: an empty cell
  return t;
}

// Makes the features of the cells (const, so thread-safe: it only reads shared state).
class CellFeatures {
 public:
  CellFeatures(const SiteTable& table, const SiteTexts& texts, const CellGeometry& cells, bool encoded)
      : table_(table), texts_(texts), cells_(cells), diagram_(cells.diagram()), encoded_(encoded) {}

  // The cell's two areas: of the rings written (0 when none), of the exact cell on the sphere.
  struct Areas {
    double m2, sr;
  };

  // The cell of s at the output's precision and its areas; a cell not written valid goes to
  // `unwritten`.
  Areas geometry(SiteId s, MultiPolygon& polygon, std::vector<UnwrittenCell>& unwritten) const {
    if (!diagram_.has_cell(s)) {  // a hidden weighted site (reported by the caller)
      polygon.clear();
      return {0, 0};
    }
    Areas areas{0, diagram_.cell_area_sr(s)};
    const CellStatus status = cells_.polygon(s, polygon, areas.m2);
    if (status != CellStatus::Written)
      unwritten.push_back({s, status});
    else
      GEOVOR_ASSERT(cell_areas_agree(areas.m2, areas.sr, polygon, cells_.options().densify_m, cells_.options().precision));
    return areas;
  }

  // The cell's properties as values, for writers without an encoder.
  void values(SiteId s, Areas areas, std::vector<FieldValue>& values, std::string& buffer) const {
    const std::span<const std::uint32_t> site_rows = texts_.rows.of(s);
    const InputSite& first = table_.sites[site_rows.front()];
    const auto neighbours = diagram_.cell_neighbors(s);
    const std::size_t ours = our_fields(table_);
    values.resize(ours + table_.columns.size());
    values[0] = static_cast<std::int64_t>(s);
    values[1] = first.id;
    buffer.assign(1, '[');
    buffer += texts_.element(s);
    for (std::size_t k = 1; k < site_rows.size(); ++k) {
      buffer += ',';
      append_id_list_element(buffer, table_.sites[site_rows[k]].id);
    }
    buffer += ']';
    values[2] = buffer;
    values[3] = static_cast<std::int64_t>(site_rows.size());
    values[4] = areas.m2;
    values[5] = areas.sr;
    values[6] = static_cast<std::int64_t>(diagram_.cell_vertices(s).size());
    buffer.assign(1, '[');
    for (std::size_t k = 0; k < neighbours.size(); ++k) {
      if (k) buffer += ',';
      buffer += texts_.element(neighbours[k]);
    }
    buffer += ']';
    values[7] = buffer;
    if (ours > kOurFields.size()) values[kOurFields.size()] = first.weight_m;
    for (std::size_t c = 0; c < table_.columns.size(); ++c) values[ours + c] = input_value(table_, first, c);
  }

  // The same properties as the JSON text of each value, in text[0, ends.back()) (value i ends
  // at ends[i]), for the encoder; `ids` is scratch. The fields up to the input columns are
  // written in place, into room made for their longest text (no capacity check per piece).
  void json(SiteId s, Areas areas, std::string& text, std::vector<std::size_t>& ends, std::string& ids) const {
    const std::span<const std::uint32_t> site_rows = texts_.rows.of(s);
    const InputSite& first = table_.sites[site_rows.front()];
    const auto neighbours = diagram_.cell_neighbors(s);
    const std::string_view own = texts_.site_text[s];
    ids.clear();
    if (site_rows.size() > 1) {  // merged rows (rare): their ids escaped as list elements
      ids += '[';
      ids += own;
      for (std::size_t k = 1; k < site_rows.size(); ++k) {
        ids += ',';
        append_id_list_element(ids, table_.sites[site_rows[k]].id);
      }
      ids += ']';
    }
    constexpr std::size_t kIntChars = 24;
    std::size_t bound = 3 * kIntChars + 3 * kMaxRealChars + 2 * own.size() + ids.size() + 4 + neighbours.size();
    for (const SiteId w : neighbours) bound += texts_.site_text[w].size();
    if (text.size() < bound) text.resize(std::max(bound, 2 * text.size()));
    char* const begin = text.data();
    char* p = begin;
    ends.clear();
    auto done = [&] { ends.push_back(static_cast<std::size_t>(p - begin)); };
    auto put_int = [&p](std::size_t x) { p = std::to_chars(p, p + kIntChars, static_cast<std::int64_t>(x)).ptr; };
    auto put_real = [&p](double x) {
      if (std::isfinite(x)) {
        p = format_real(p, x);
      } else {
        std::memcpy(p, "null", 4);  // JSON has no NaN or infinity (as append_json_value)
        p += 4;
      }
    };
    put_int(s);
    done();
    p = copy_short(p, own);
    done();
    if (ids.empty()) {
      *p++ = '[';
      p = copy_short(p, own);
      *p++ = ']';
    } else {
      p = copy_short(p, ids);
    }
    done();
    put_int(site_rows.size());
    done();
    put_real(areas.m2);
    done();
    put_real(areas.sr);
    done();
    put_int(diagram_.cell_vertices(s).size());
    done();
    *p++ = '[';
    for (std::size_t k = 0; k < neighbours.size(); ++k) {
      if (k) *p++ = ',';
      p = copy_short(p, texts_.site_text[neighbours[k]]);
    }
    *p++ = ']';
    done();
    if (table_.weighted) {
      put_real(first.weight_m);
      done();
    }
    text.resize(static_cast<std::size_t>(p - begin));  // shorter: nothing filled
    const std::size_t id_column = table_.id_column >= 0 && table_.column_type(table_.id_column) == FieldType::String
                                      ? static_cast<std::size_t>(table_.id_column)
                                      : table_.columns.size();
    for (std::size_t c = 0; c < table_.columns.size(); ++c) {
      if (c == id_column && c < first.fields.size() && first.fields[c] == first.id)
        text += own;
      else
        append_input_json(text, table_, first, c);
      ends.push_back(text.size());
    }
  }

  // Input order is not the cells' storage order: their data is scattered, so it is requested in
  // stages some cells ahead (each stage reads what the one before brought in), with the site's
  // row and its fields' text. `i` indexes texts_.order.
  void prefetch_ahead(std::size_t i) const {
    constexpr std::size_t kLists = 12, kVertices = 8, kPoints = 4;
    const std::vector<SiteId>& order = texts_.order;
    if (i + kLists < order.size()) {
      const SiteId s = order[i + kLists];
      cells_.prefetch(s, 0);
      const InputSite* first = &table_.sites[texts_.rows.first(s)];
      __builtin_prefetch(first);
      __builtin_prefetch(reinterpret_cast<const char*>(first + 1) - 1);
    }
    if (i + kVertices < order.size()) {
      const SiteId s = order[i + kVertices];
      cells_.prefetch(s, 1);
      const std::vector<std::string>& fields = table_.sites[texts_.rows.first(s)].fields;
      if (!fields.empty()) {  // the fields' strings (short ones hold their text)
        __builtin_prefetch(fields.data());
        __builtin_prefetch(reinterpret_cast<const char*>(fields.data() + fields.size()) - 1);
      }
      if (encoded_)
        for (const SiteId w : diagram_.cell_neighbors(s)) __builtin_prefetch(&texts_.site_text[w]);
    }
    if (i + kPoints < order.size()) {
      const SiteId s = order[i + kPoints];
      cells_.prefetch(s, 2);
      for (const std::string& f : table_.sites[texts_.rows.first(s)].fields) __builtin_prefetch(f.data());
      if (encoded_)
        for (const SiteId w : diagram_.cell_neighbors(s)) __builtin_prefetch(texts_.site_text[w].data());
    }
  }

 private:
  const SiteTable& table_;
  const SiteTexts& texts_;
  const CellGeometry& cells_;
  const VoronoiDiagram& diagram_;
  bool encoded_;
};

// A block of consecutive cells (of SiteTexts::order), computed by a worker and written in order.
struct CellBlock {
  std::size_t begin = 0, end = 0;
  std::vector<MultiPolygon> polygons;           // without an encoder
  std::vector<std::vector<FieldValue>> values;  // without an encoder
  EncodedFeatures text;                         // with an encoder: the block's features as text
  std::vector<UnwrittenCell> unwritten;
};

// A worker's reused memory.
struct Scratch {
  std::string buffer, ids;
  MultiPolygon polygon;
  std::vector<std::size_t> ends;
  std::vector<std::string_view> json_values;
};

void compute_block(const CellFeatures& features, const std::vector<SiteId>& order, const FeatureEncoder* encoder,
                   CellBlock& block, Scratch& scratch) {
  block.unwritten.clear();
  if (encoder) {
    block.text.clear();
    for (std::size_t i = block.begin; i < block.end; ++i) {
      features.prefetch_ahead(i);
      const CellFeatures::Areas areas = features.geometry(order[i], scratch.polygon, block.unwritten);
      features.json(order[i], areas, scratch.buffer, scratch.ends, scratch.ids);
      scratch.json_values.clear();
      for (std::size_t k = 0, from = 0; k < scratch.ends.size(); from = scratch.ends[k++])
        scratch.json_values.push_back(std::string_view(scratch.buffer).substr(from, scratch.ends[k] - from));
      encoder->encode_json(scratch.polygon, scratch.json_values, i + 1, block.text);
    }
    return;
  }
  block.polygons.resize(block.end - block.begin);
  block.values.resize(block.end - block.begin);
  for (std::size_t i = block.begin; i < block.end; ++i) {
    features.prefetch_ahead(i);
    const CellFeatures::Areas areas = features.geometry(order[i], block.polygons[i - block.begin], block.unwritten);
    features.values(order[i], areas, block.values[i - block.begin], scratch.buffer);
  }
}

}  // namespace

std::vector<Field> cell_layer_schema(const SiteTable& table) {
  std::vector<Field> schema;
  for (std::size_t i = 0; i < kOurFields.size(); ++i) schema.push_back({kOurFields[i], kOurTypes[i], kOurJson[i]});
  if (table.weighted) schema.push_back({kWeightField, FieldType::Real, false});
  std::vector<std::size_t> columns(table.columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c) columns[c] = c;
  const std::vector<Field> inputs = input_column_fields(table, columns, schema);
  schema.insert(schema.end(), inputs.begin(), inputs.end());
  return schema;
}

std::unique_ptr<FeatureWriter> open_cell_layer_writer(const std::string& path, const SiteTable& table,
                                                      WriterOptions options) {
  if (options.id_field.empty()) options.id_field = "site_id";
  return open_feature_writer(path, GeometryType::MultiPolygon, cell_layer_schema(table), options);
}

CellLayerReport write_cell_layer(FeatureWriter& writer, const SiteTable& table, const BuildReport& report,
                                 const SphericalDelaunay& dt, const CellLayerOptions& options) {
  const unsigned threads = thread_count(options.threads);
  const FeatureEncoder* encoder = writer.encoder();
  // The sites' texts on another thread while the diagram and the cells' geometry are built (it
  // fills their sequential stretches).
  SiteTexts texts;
  TaskGroup background;
  auto prepare = [&] { texts = make_site_texts(table, report, dt, encoder != nullptr, options.id_texts); };
  if (threads > 1)
    background.run(prepare);
  else
    prepare();
  if (options.diagram != nullptr &&
      (options.diagram->site_capacity() != dt.site_capacity() || options.diagram->num_cells() != dt.num_sites()))
    throw Error(ErrorCode::InvalidArgument, "write_cell_layer: the diagram given is not of the triangulation's sites");
  VoronoiDiagram built;
  if (options.diagram == nullptr) built.assign(dt, threads);
  const VoronoiDiagram& diagram = options.diagram != nullptr ? *options.diagram : built;
  CellGeometryOptions geometry_options;
  geometry_options.densify_m = options.densify_m;
  geometry_options.threads = threads;
  geometry_options.precision = encoder ? options.precision : kFullPrecision;
  const CellGeometry cells(diagram, geometry_options);
  background.wait();
  const CellFeatures features(table, texts, cells, encoder != nullptr);

  // Workers compute blocks of consecutive cells (and encode them when the format has an
  // encoder) while this thread writes the finished blocks in order. The window is enough that
  // the workers go on while a direct write blocks the writer (2-5 ms per 4 MiB); with 2 threads,
  // 6 slots left the workers waiting 30-70 ms on the cities, 12 slots 4-10 ms. Past 32 slots, 2
  // per thread (memory: a slot holds a block's cells).
  constexpr std::size_t kBlock = 1024;
  const std::size_t window =
      std::max<std::size_t>(2 * std::size_t{threads} + 2, std::min<std::size_t>(4 * std::size_t{threads} + 4, 32));
  const std::vector<SiteId>& order = texts.order;
  std::vector<Scratch> scratch(threads);
  std::size_t next = 0;
  CellLayerReport result;
  ordered_pipeline<CellBlock>(
      threads, window,
      [&](CellBlock& block) {
        if (next >= order.size()) return false;
        block.begin = next;
        block.end = next = std::min(order.size(), next + kBlock);
        return true;
      },
      [&](CellBlock& block, unsigned worker) { compute_block(features, order, encoder, block, scratch[worker]); },
      [&](CellBlock& block) {
        if (encoder) {
          writer.write_encoded(block.text);
        } else {
          for (std::size_t i = 0; i < block.polygons.size(); ++i) writer.write(block.polygons[i], block.values[i]);
        }
        result.cells_written += block.end - block.begin;
        result.unwritten.insert(result.unwritten.end(), block.unwritten.begin(), block.unwritten.end());
        if (options.progress) options.progress(result.cells_written);
      });
  return result;
}

}  // namespace geovor
