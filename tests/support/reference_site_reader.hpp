/// \file reference_site_reader.hpp
/// \brief The CSV site reader before the two-stage CsvSiteScan (read_csv_table over the streaming
/// CsvReader), kept as the oracle of tests/geo/csv_site_scan_test.cpp, the fuzz target and the
/// read bench. Same contract as read_sites_csv / read_sites_csv_file.
#pragma once

#include <istream>
#include <string>

#include "geovor/geo/site_reader.hpp"

namespace geovor::testing {

/// read_sites_csv as it was: CsvReader record by record, coordinates converted afterwards.
SiteTable reference_read_sites_csv(std::istream& in, const std::string& source,
                                   const SiteReaderOptions& options = {});

/// read_sites_csv_file as it was ("-": standard input).
SiteTable reference_read_sites_csv_file(const std::string& path,
                                        const SiteReaderOptions& options = {});

}  // namespace geovor::testing
