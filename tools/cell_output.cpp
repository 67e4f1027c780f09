#include "cell_output.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <condition_variable>
#include <exception>
#include <future>
#include <mutex>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "geovor/core/ascii.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "commands.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

// A block of consecutive cells, computed in parallel and then written in order.
struct CellBlock {
  std::vector<SiteId> sites;
  std::vector<MultiPolygon> polygons;
  std::vector<std::vector<FieldValue>> values;
};

// Appends s as a JSON string (ids and neighbours are JSON arrays in a string field: portable in
// every format, no list field types needed).
void append_json(std::string& out, const std::string& s) {
  out += '"';
  std::size_t plain = 0;  // copy runs of ordinary characters at once
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c != '"' && c != '\\' && c >= 0x20) continue;
    out.append(s, plain, i - plain);
    if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += '\\';
      out += static_cast<char>(c);
    }
    plain = i + 1;
  }
  out.append(s, plain, std::string::npos);
  out += '"';
}

// Whether append_json() only adds quotes around `id`.
bool plain_json(const std::string& id) {
  return std::none_of(id.begin(), id.end(), [](char c) { return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20; });
}

// Appends the text append_json() makes of `id` as it stands inside a JSON string (escaped once
// more, without the quotes): an element of the ids/neighbors lists in GeoJSON. Escaping a list
// piece by piece gives the same bytes as escaping it whole, since every piece ("[", ",", "]",
// elements) starts and ends with an ASCII character.
void append_escaped_element(std::string& out, const std::string& id) {
  std::string element, escaped;
  append_json(element, id);
  append_json_string(escaped, element);
  out.append(escaped, 1, escaped.size() - 2);
}

// make(out, i) appends item i's first text then its second, and returns where the second
// starts; for items 0 .. n - 1, on `threads` threads.
template <typename Make>
IdTexts make_texts(std::size_t n, unsigned threads, const Make& make) {
  threads = static_cast<unsigned>(std::clamp<std::size_t>(n / 4096, 1, std::max(1u, threads)));
  IdTexts texts;
  texts.storage.resize(threads);
  texts.text.resize(n);
  texts.element.resize(n);
  auto run = [&](unsigned t) {
    const std::size_t begin = n * t / threads, end = n * (t + 1) / threads;
    std::string& out = texts.storage[t];
    out.reserve(64);  // on the heap from the start: moving `texts` keeps the views valid
    std::vector<std::size_t> ends;  // the views come once `out` stops moving
    ends.reserve(2 * (end - begin));
    for (std::size_t i = begin; i < end; ++i) {
      ends.push_back(make(out, i));
      ends.push_back(out.size());
    }
    const std::string_view all(out);
    for (std::size_t i = begin, k = 0, from = 0; i < end; ++i, k += 2) {
      texts.text[i] = all.substr(from, ends[k] - from);
      texts.element[i] = all.substr(ends[k], ends[k + 1] - ends[k]);
      from = ends[k + 1];
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(run, t);
  run(0);
  for (std::thread& th : pool) th.join();
  return texts;
}

}  // namespace

bool writes_geojson(const CellOutputArgs& args) { return !output_needs_gdal(args.output, args.format); }

IdTexts make_id_texts(const SiteTable& table, unsigned threads) {
  return make_texts(table.sites.size(), threads, [&](std::string& out, std::size_t row) {
    const std::string& id = table.sites[row].id;
    const std::size_t at = out.size();
    append_json_string(out, id);
    const std::size_t split = out.size();
    if (plain_json(id)) {
      // The quotes become \": \" + the id as just written without its closing quote + \".
      out += '\\';
      out.append(out, at, split - 1 - at);  // (appending part of itself is well-defined)
      out += "\\\"";
    } else {
      append_escaped_element(out, id);
    }
    return split;
  });
}

std::size_t write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                        const SphericalDelaunay& dt, const std::function<void()>& before_finish,
                        const IdTexts* id_texts, std::vector<UnwrittenCell>* unwritten) {
  const unsigned threads = args.threads > 0 ? static_cast<unsigned>(args.threads)
                                            : std::max(1u, std::thread::hardware_concurrency());
  // Schema: our fields, then every input column (renamed src_<name> if it clashes with ours).
  const std::vector<std::string> ours = {"site_index", "site_id", "ids",        "n_rows",
                                         "area_m2",    "area_sr", "n_vertices", "neighbors"};
  std::vector<Field> schema = {{"site_index", FieldType::Integer}, {"site_id", FieldType::String},
                               {"ids", FieldType::String},         {"n_rows", FieldType::Integer},
                               {"area_m2", FieldType::Real},       {"area_sr", FieldType::Real},
                               {"n_vertices", FieldType::Integer}, {"neighbors", FieldType::String}};
  for (const std::string& column : table.columns) {
    const bool clash = std::any_of(ours.begin(), ours.end(), [&](const std::string& o) { return ascii_iequals(o, column); });
    schema.push_back({clash ? "src_" + column : column, FieldType::String});
  }
  WriterOptions writer_options;
  writer_options.format = args.format;
  writer_options.layer = "cells";
  writer_options.precision = args.precision;
  writer_options.overwrite = args.overwrite;
  writer_options.id_field = "site_id";
  const auto writer = open_feature_writer(args.output, GeometryType::MultiPolygon, schema, writer_options);
  const FeatureEncoder* encoder = writer->encoder();

  // What needs only the table and the triangulation is made on another thread while the
  // diagram and the cells' geometry are built (it fills their sequential stretches):
  // - the rows of each site (as rows_of_sites() orders them: the row it was built from, then
  //   the merged ones), flat: site s has row_list[row_begin[s] .. row_begin[s + 1]);
  // - each site's id (its first row's) as text, made once: the neighbour lists name every site
  //   about six times. Without an encoder: as a JSON string, an element of the lists (site s:
  //   id_json.text[s]). With one (GeoJSON): as the encoder writes the id (site_id, the feature
  //   id), and as a list element escaped inside the list's JSON string (id_texts, by row; then
  //   site_text and site_element, by site, so that a cell reaches its neighbours' text in one
  //   step);
  // - the sites with a cell, in id order.
  const std::size_t num_sites = dt.site_capacity();
  std::vector<std::uint32_t> row_begin(num_sites + 1, 0), row_list;
  IdTexts id_json, made;
  std::vector<std::string_view> site_text, site_element;
  std::vector<SiteId> order;
  auto prepare = [&] {
    std::vector<char> merged(report.site_of_input.size(), 0);
    for (const Merge& m : report.merges) merged[m.input] = 1;
    for (const std::uint32_t site : report.site_of_input)
      if (site < num_sites) ++row_begin[site + 1];
    for (std::size_t s = 0; s < num_sites; ++s) row_begin[s + 1] += row_begin[s];
    row_list.resize(row_begin[num_sites]);
    std::vector<std::uint32_t> fill(row_begin.begin(), row_begin.end() - 1);
    for (const bool merged_pass : {false, true})
      for (std::uint32_t i = 0; i < report.site_of_input.size(); ++i)
        if (report.site_of_input[i] < num_sites && (merged[i] != 0) == merged_pass)
          row_list[fill[report.site_of_input[i]]++] = i;
    if (!encoder) {
      id_json = make_texts(num_sites, 1, [&](std::string& out, std::size_t s) {
        if (row_begin[s] < row_begin[s + 1]) append_json(out, table.sites[row_list[row_begin[s]]].id);
        return out.size();
      });
    } else {
      if (id_texts == nullptr || id_texts->text.size() != table.sites.size()) {
        made = make_id_texts(table, 1);
        id_texts = &made;
      }
      site_text.resize(num_sites);
      site_element.resize(num_sites);
      for (std::size_t s = 0; s < num_sites; ++s)
        if (row_begin[s] < row_begin[s + 1]) {
          site_text[s] = id_texts->text[row_list[row_begin[s]]];
          site_element[s] = id_texts->element[row_list[row_begin[s]]];
        }
    }
    for (SiteId s = 0; s < num_sites; ++s)
      if (dt.is_live(s)) order.push_back(s);  // VoronoiDiagram::has_cell
  };
  std::future<void> prepared = std::async(threads > 1 ? std::launch::async : std::launch::deferred, prepare);
  const VoronoiDiagram diagram(dt, threads);
  CellGeometryOptions geometry_options;
  geometry_options.densify_m = args.densify_m;
  geometry_options.threads = threads;
  geometry_options.precision = encoder ? args.precision : kFullPrecision;
  const CellGeometry cells(diagram, geometry_options);
  prepared.get();
  auto rows_of = [&](SiteId s) {
    return std::span<const std::uint32_t>(row_list.data() + row_begin[s], row_list.data() + row_begin[s + 1]);
  };
  auto id_text = [&](SiteId s) { return site_text[s]; };
  auto id_element = [&](SiteId s) { return site_element[s]; };
  auto append_id = [&](std::string& out, SiteId s) { out += id_json.text[s]; };

  // Cells that could not be written valid, found by the workers.
  std::mutex unwritten_mutex;
  std::vector<UnwrittenCell> unwritten_cells;
  // The cell of s at the output's precision, its area, and the checks of what is written.
  auto cell_geometry = [&](SiteId s, MultiPolygon& polygon) {
    double area_m2 = 0;
    const CellStatus status = cells.polygon(s, polygon, area_m2);
    if (status != CellStatus::Written) {
      std::lock_guard lock(unwritten_mutex);
      unwritten_cells.push_back({s, status});
    } else {
      GEOVOR_ASSERT(cell_areas_agree(area_m2, diagram.cell_area_sr(s), polygon, geometry_options.densify_m,
                                     geometry_options.precision));
    }
    return area_m2;
  };
  // One cell's geometry and properties (thread-safe: only reads shared state).
  auto make_cell = [&](SiteId s, MultiPolygon& polygon, std::vector<FieldValue>& values, std::string& buffer) {
    const double area_m2 = cell_geometry(s, polygon);
    const std::span<const std::uint32_t> site_rows = rows_of(s);
    const InputSite& first = table.sites[site_rows.front()];
    const auto neighbours = diagram.cell_neighbors(s);
    values.resize(schema.size());
    values[0] = static_cast<std::int64_t>(s);
    values[1] = first.id;
    buffer.assign(1, '[');
    append_id(buffer, s);
    for (std::size_t k = 1; k < site_rows.size(); ++k) {
      buffer += ',';
      append_json(buffer, table.sites[site_rows[k]].id);
    }
    buffer += ']';
    values[2] = buffer;
    values[3] = static_cast<std::int64_t>(site_rows.size());
    values[4] = area_m2;
    values[5] = diagram.cell_area_sr(s);
    values[6] = static_cast<std::int64_t>(diagram.cell_vertices(s).size());
    buffer.assign(1, '[');
    for (std::size_t k = 0; k < neighbours.size(); ++k) {
      if (k) buffer += ',';
      append_id(buffer, neighbours[k]);
    }
    buffer += ']';
    values[7] = buffer;
    for (std::size_t c = 0; c < table.columns.size(); ++c)
      values[8 + c] = c < first.fields.size() ? FieldValue(first.fields[c]) : FieldValue();
  };
  // The same properties as the JSON text of each value, in one string (`text`, value i ends at
  // ends[i]), for the encoder.
  const std::size_t id_column = table.id_column >= 0 ? static_cast<std::size_t>(table.id_column) : schema.size();
  auto make_cell_json = [&](SiteId s, MultiPolygon& polygon, std::string& text, std::vector<std::size_t>& ends) {
    const double area_m2 = cell_geometry(s, polygon);
    const std::span<const std::uint32_t> site_rows = rows_of(s);
    const InputSite& first = table.sites[site_rows.front()];
    const auto neighbours = diagram.cell_neighbors(s);
    text.clear();
    ends.clear();
    auto done = [&] { ends.push_back(text.size()); };
    append_json_value(text, static_cast<std::int64_t>(s));
    done();
    text += id_text(s);
    done();
    text += "\"[";
    text += id_element(s);
    for (std::size_t k = 1; k < site_rows.size(); ++k) {
      text += ',';
      append_escaped_element(text, table.sites[site_rows[k]].id);
    }
    text += "]\"";
    done();
    append_json_value(text, static_cast<std::int64_t>(site_rows.size()));
    done();
    append_json_value(text, area_m2);
    done();
    append_json_value(text, diagram.cell_area_sr(s));
    done();
    append_json_value(text, static_cast<std::int64_t>(diagram.cell_vertices(s).size()));
    done();
    text += "\"[";
    for (std::size_t k = 0; k < neighbours.size(); ++k) {
      if (k) text += ',';
      text += id_element(neighbours[k]);
    }
    text += "]\"";
    done();
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
      if (c >= first.fields.size())
        text += "null";
      else if (c == id_column && first.fields[c] == first.id)
        text += id_text(s);
      else
        append_json_string(text, first.fields[c]);
      done();
    }
  };

  // A pipeline: worker threads take blocks of consecutive cells (in site order) and compute
  // them, and encode them too when the format has an encoder (GeoJSON), while this thread
  // writes the finished blocks in order. At most `window` blocks are in flight, in reused
  // slots: enough that the workers go on while a direct write blocks the writer (2-5 ms per
  // 4 MiB); with 2 threads, 6 slots left the workers waiting 30-70 ms on the cities, 12 slots
  // 4-10 ms. Past 32 slots, 2 per thread as before (memory: a slot holds a block's cells).
  constexpr std::size_t kBlock = 1024;
  const std::size_t num_blocks = (order.size() + kBlock - 1) / kBlock;
  const std::size_t window = std::max<std::size_t>(2 * std::size_t{threads} + 2, std::min<std::size_t>(4 * std::size_t{threads} + 4, 32));
  struct Slot {
    CellBlock cells;        // without an encoder: the block's polygons and values
    EncodedFeatures text;   // with an encoder: the block's features as text
    std::exception_ptr error;
    bool ready = false;
  };
  std::vector<Slot> slots(window);
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t next_block = 0, blocks_written = 0;
  bool stop = false;

  // A worker's reused memory.
  struct Scratch {
    std::string buffer;
    MultiPolygon polygon;
    std::vector<FieldValue> values;
    std::vector<std::size_t> ends;
    std::vector<std::string_view> json_values;
  };
  // Input order is not the cells' storage order: their data is scattered, so it is requested in
  // stages some cells ahead (each stage reads what the one before brought in), with the site's
  // row and its fields' text.
  auto prefetch_ahead = [&](std::size_t i) {
    constexpr std::size_t kLists = 12, kVertices = 8, kPoints = 4;
    if (i + kLists < order.size()) cells.prefetch(order[i + kLists], 0);
    if (i + kVertices < order.size()) {
      const SiteId s = order[i + kVertices];
      cells.prefetch(s, 1);
      const InputSite* first = &table.sites[row_list[row_begin[s]]];
      __builtin_prefetch(first);
      __builtin_prefetch(reinterpret_cast<const char*>(first + 1) - 1);
      if (encoder)
        for (const SiteId w : diagram.cell_neighbors(s)) __builtin_prefetch(&site_element[w]);
    }
    if (i + kPoints < order.size()) {
      const SiteId s = order[i + kPoints];
      cells.prefetch(s, 2);
      const std::vector<std::string>& fields = table.sites[row_list[row_begin[s]]].fields;
      for (const std::string& f : fields) __builtin_prefetch(f.data());
      if (encoder)
        for (const SiteId w : diagram.cell_neighbors(s)) __builtin_prefetch(site_element[w].data());
    }
  };
  auto compute = [&](std::size_t b, Slot& slot, Scratch& scratch) {
    const std::size_t begin = b * kBlock, end = std::min(order.size(), begin + kBlock);
    std::string& buffer = scratch.buffer;
    if (encoder) {
      slot.text.clear();
      for (std::size_t i = begin; i < end; ++i) {
        prefetch_ahead(i);
        make_cell_json(order[i], scratch.polygon, buffer, scratch.ends);
        scratch.json_values.clear();
        for (std::size_t k = 0, from = 0; k < scratch.ends.size(); from = scratch.ends[k++])
          scratch.json_values.push_back(std::string_view(buffer).substr(from, scratch.ends[k] - from));
        encoder->encode_json(scratch.polygon, scratch.json_values, i + 1, slot.text);
      }
      return;
    }
    CellBlock& block = slot.cells;
    block.sites.assign(order.begin() + static_cast<std::ptrdiff_t>(begin),
                       order.begin() + static_cast<std::ptrdiff_t>(end));
    block.polygons.resize(block.sites.size());
    block.values.resize(block.sites.size());
    for (std::size_t i = 0; i < block.sites.size(); ++i) {
      prefetch_ahead(begin + i);
      make_cell(block.sites[i], block.polygons[i], block.values[i], buffer);
    }
  };
  auto work = [&] {
    Scratch scratch;
    for (;;) {
      std::size_t b;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || next_block >= num_blocks || next_block < blocks_written + window; });
        if (stop || next_block >= num_blocks) return;
        b = next_block++;
      }
      Slot& slot = slots[b % window];
      std::exception_ptr error;
      try {
        compute(b, slot, scratch);
      } catch (...) {
        error = std::current_exception();
      }
      {
        std::lock_guard lock(mutex);
        slot.error = error;
        slot.ready = true;
      }
      changed.notify_all();
    }
  };
  std::vector<std::thread> pool;
  // Stops and joins the workers however this function ends.
  struct Joiner {
    std::vector<std::thread>& pool;
    std::mutex& mutex;
    std::condition_variable& changed;
    bool& stop;
    ~Joiner() {
      {
        std::lock_guard lock(mutex);
        stop = true;
      }
      changed.notify_all();
      for (std::thread& t : pool) t.join();
    }
  } joiner{pool, mutex, changed, stop};
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);

  Progress progress(order.size(), args.quiet);
  std::size_t written = 0;
  for (std::size_t b = 0; b < num_blocks; ++b) {
    Slot& slot = slots[b % window];
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return slot.ready; });
      slot.ready = false;
    }
    if (slot.error) std::rethrow_exception(slot.error);
    if (encoder) {
      writer->write_encoded(slot.text);
      written += slot.text.boxes.size();
    } else {
      const CellBlock& block = slot.cells;
      for (std::size_t i = 0; i < block.sites.size(); ++i) writer->write(block.polygons[i], block.values[i]);
      written += block.sites.size();
    }
    progress.advance(written);
    {
      std::lock_guard lock(mutex);
      blocks_written = b + 1;
    }
    changed.notify_all();
  }
  std::sort(unwritten_cells.begin(), unwritten_cells.end(),
            [](const UnwrittenCell& a, const UnwrittenCell& b) { return a.site < b.site; });
  // Listed even with --quiet, as rejected rows are: a cell without geometry must not pass unseen.
  if (!unwritten_cells.empty()) {
    std::fprintf(stderr, "%zu cell(s) written with an empty geometry: at %s they %s:\n", unwritten_cells.size(),
                 geometry_options.precision >= 0 ? ("--precision " + std::to_string(geometry_options.precision)).c_str()
                                                 : "full precision",
                 "collapse or would not be valid polygons (raise --precision)");
    std::size_t shown = 0;
    for (const UnwrittenCell& c : unwritten_cells) {
      if (++shown > 20) {
        std::fprintf(stderr, "  ... (%zu more; --report lists them all)\n", unwritten_cells.size() - 20);
        break;
      }
      std::fprintf(stderr, "  site %u (id %s): %s\n", c.site, table.sites[row_list[row_begin[c.site]]].id.c_str(),
                   to_string(c.status));
    }
  }
  if (unwritten) *unwritten = unwritten_cells;
  if (before_finish) before_finish();
  writer->finish();
  progress.finish();
  return written;
}

}  // namespace geovor::tools
