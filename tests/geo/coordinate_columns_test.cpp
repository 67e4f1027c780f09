/// \file coordinate_columns_test.cpp
/// \brief Tests of the coordinate column names (the headers of real public data sets and GIS
/// exports), ambiguity, and the header's names.
#include "geovor/geo/coordinate_columns.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

// The message of the Error thrown by f, or "" if none.
template <typename F>
std::string error_of(F f, ErrorCode* code = nullptr) {
  try {
    f();
  } catch (const Error& e) {
    if (code) *code = e.code();
    return e.what();
  }
  return "";
}

struct Header {
  const char* what;
  std::vector<std::string> columns;
  int lat, lon;
};

TEST(CoordinateColumns, HeadersOfPublicDataSets) {
  const std::vector<Header> headers = {
      {"GTFS stops.txt", {"stop_id", "stop_code", "stop_name", "stop_lat", "stop_lon", "zone_id", "parent_station"}, 3, 4},
      {"GBIF occurrence", {"gbifID", "species", "decimalLatitude", "decimalLongitude", "coordinateUncertaintyInMeters"}, 2, 3},
      {"OurAirports", {"id", "ident", "type", "name", "latitude_deg", "longitude_deg", "elevation_ft"}, 4, 5},
      {"NOAA ISD history", {"USAF", "WBAN", "STATION NAME", "CTRY", "ICAO", "LAT", "LON", "ELEV(M)"}, 5, 6},
      {"GeoNames", {"geonameid", "name", "asciiname", "latitude", "longitude", "feature class"}, 3, 4},
      {"ArcGIS table", {"OBJECTID", "Name", "POINT_X", "POINT_Y"}, 3, 2},
      {"QGIS AS_XY", {"X", "Y", "name"}, 1, 0},
      {"QGIS geometry attributes", {"name", "xcoord", "ycoord"}, 2, 1},
      {"units and spaces", {"Name", "Latitude (deg)", "Longitude [°]"}, 1, 2},
      {"WGS84 suffix", {"LAT_WGS84", "LON_WGS84"}, 0, 1},
      {"decimal degrees", {"Lat_DD", "Long_DD"}, 0, 1},
      {"spreadsheet", {" Latitude ", " Longitude "}, 0, 1},
      {"lng", {"lng", "lat"}, 1, 0},
      {"Natural Earth", {"NAME", "NAME_LONG", "LATITUDE", "LONGITUDE"}, 2, 3},
      {"rank 1 beats y/x", {"y", "x", "lat_deg", "lon_deg"}, 2, 3},
      {"rank 2 beats y/x", {"x", "y", "site_latitude", "site_longitude"}, 2, 3},
  };
  for (const Header& h : headers) {
    EXPECT_EQ(detect_coordinate_column(h.columns, Axis::Latitude, false, "f.csv"), h.lat) << h.what;
    EXPECT_EQ(detect_coordinate_column(h.columns, Axis::Longitude, false, "f.csv"), h.lon) << h.what;
  }
}

TEST(CoordinateColumns, Ranks) {
  EXPECT_EQ(coordinate_name_rank("lat", Axis::Latitude), 1);
  EXPECT_EQ(coordinate_name_rank("Latitude (WGS84)", Axis::Latitude), 1);
  EXPECT_EQ(coordinate_name_rank("decimalLatitude", Axis::Latitude), 1);
  EXPECT_EQ(coordinate_name_rank("stop_lat", Axis::Latitude), 2);
  EXPECT_EQ(coordinate_name_rank("verbatimLatitude", Axis::Latitude), 2);
  EXPECT_EQ(coordinate_name_rank("POINT_Y", Axis::Latitude), 3);
  EXPECT_EQ(coordinate_name_rank("y", Axis::Latitude), 3);
  EXPECT_EQ(coordinate_name_rank("y", Axis::Latitude, true), 1);
  EXPECT_EQ(coordinate_name_rank("northing_m", Axis::Latitude, true), 1);
  EXPECT_EQ(coordinate_name_rank("easting", Axis::Longitude, true), 1);
  // Not coordinates: NAME_LONG is a name, lat_dms is text, easting is metres without --s-srs.
  EXPECT_EQ(coordinate_name_rank("NAME_LONG", Axis::Longitude), 0);
  EXPECT_EQ(coordinate_name_rank("lat_dms", Axis::Latitude), 0);
  EXPECT_EQ(coordinate_name_rank("easting_m", Axis::Longitude), 0);
  EXPECT_EQ(coordinate_name_rank("latency", Axis::Latitude), 0);
  EXPECT_EQ(coordinate_name_rank("lat", Axis::Longitude), 0);
}

TEST(CoordinateColumns, AmbiguousHeadersAreRefusedWithTheCandidates) {
  ErrorCode code = ErrorCode::Internal;
  // NYC taxi trips: two latitudes, equally good.
  const std::vector<std::string> taxi = {"pickup_longitude", "pickup_latitude", "dropoff_longitude", "dropoff_latitude"};
  std::string what = error_of([&] { detect_coordinate_column(taxi, Axis::Latitude, false, "trips.csv"); }, &code);
  EXPECT_EQ(code, ErrorCode::BadData);
  EXPECT_EQ(what, "trips.csv: ambiguous latitude column: 'pickup_latitude', 'dropoff_latitude' are equally likely; "
                  "choose one with --lat-field");
  // lat and Latitude; lon and lng.
  what = error_of([] { detect_coordinate_column({"lat", "Latitude", "lon"}, Axis::Latitude, false, "f.csv"); });
  EXPECT_NE(what.find("'lat', 'Latitude'"), std::string::npos) << what;
  what = error_of([] { detect_coordinate_column({"lat", "lon", "lng"}, Axis::Longitude, false, "f.csv"); });
  EXPECT_NE(what.find("'lon', 'lng' are equally likely; choose one with --lon-field"), std::string::npos) << what;
  // With a projected source, x and lon are both rank 1.
  what = error_of([] { detect_coordinate_column({"x", "lon"}, Axis::Longitude, true, "f.csv"); });
  EXPECT_NE(what.find("ambiguous longitude column"), std::string::npos) << what;
  EXPECT_EQ(detect_coordinate_column({"x", "lon"}, Axis::Longitude, false, "f.csv"), 1);
  EXPECT_EQ(detect_coordinate_column({"a", "b"}, Axis::Longitude, false, "f.csv"), -1);
}

TEST(CoordinateColumns, HeaderNames) {
  EXPECT_EQ(check_header_names({"id", "lat", "lon"}, "f.csv"), 0u);
  EXPECT_EQ(check_header_names({"id", "lat", "lon", ""}, "f.csv"), 1u);
  EXPECT_EQ(check_header_names({"id", "lat", "lon", " ", ""}, "f.csv"), 2u);
  ErrorCode code = ErrorCode::Internal;
  EXPECT_EQ(error_of([] { check_header_names({"id", "lat", "lon", "lat"}, "f.csv"); }, &code),
            "f.csv: header: column 4 'lat' has the same name as column 2 'lat'; rename one of them");
  EXPECT_EQ(code, ErrorCode::BadData);
  // Compared as columns are looked up: trimmed, case-insensitive; the first repeat is named.
  EXPECT_EQ(error_of([] { check_header_names({"a", "b", "B ", "A", "a"}, "f.csv"); }),
            "f.csv: header: column 3 'B ' has the same name as column 2 'b'; rename one of them");
  EXPECT_EQ(error_of([] { check_header_names({"id", "", "lat", "lon"}, "f.csv"); }),
            "f.csv: header: column 2 has no name; every column but empty trailing ones needs one");
}

}  // namespace
}  // namespace geovor
